#include "remesh/bound.h"

#include "analysis/curvature.h"
#include "sizing/gradation.h"
#include "sizing/metric.h"
#include "sizing/size_field.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <queue>

namespace vesselmesh::remesh {
namespace {

// Per input point, the largest distance the output may keep from the input there (inf: none).
// Without radii, the radius is 1 / max(|k1|, |k2|), but never below a quarter of its median
// over the surface: a segmentation's bumps and a closed model's rounded ends curve far more
// than the vessel, and bounding by them would refine every bump. `radius`: the local radius it
// took (empty without a relative bound).
std::vector<double> distance_bounds(const TriMesh& input, const RemeshOptions& o, const analysis::CurvatureField* c,
                                    std::vector<double>& radius) {
  const double absolute = o.hausdorff > 0.0 ? o.hausdorff : std::numeric_limits<double>::infinity();
  std::vector<double> bound(input.points.size(), absolute);
  radius.clear();
  if (!(o.hausdorff_relative > 0.0)) return bound;
  radius.assign(input.points.size(), 0.0);
  if (o.input_radius) {
    radius = *o.input_radius;
  } else {
    for (int v = 0; v < input.num_points(); ++v) {
      const double k = std::max(std::abs(c->k1[v]), std::abs(c->k2[v]));
      radius[v] = k > 0.0 ? 1.0 / k : std::numeric_limits<double>::infinity();
    }
    std::vector<double> sorted = radius;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double floor = 0.25 * sorted[sorted.size() / 2];
    for (double& r : radius) r = std::max(r, floor);
  }
  for (int v = 0; v < input.num_points(); ++v)
    if (radius[v] > 0.0 && std::isfinite(radius[v])) bound[v] = std::min(bound[v], o.hausdorff_relative * radius[v]);
  return bound;
}

// How much longer than round it the isotropic kinds' chord bound lets an edge be along a tube
// (the chord error lies round it: an edge along the axis strays by nothing): kMaxStretch where
// the smaller principal curvature is under a tenth of the larger, none from half of it on, and
// only where the larger is the tube's, within 1.5 times 1 / the local radius (not at a bump or
// a crease). A polygon round the tube within the bound then needs no more points than the bound
// asks: isotropic edges as short round it as the bound wants were as short along it, 1.8 to 1.9
// times the triangles a 16-gon round it needs (issue 51's thin daughter; 1.21 with this, 1.32
// with 1.45). Stretched by 1.55, an equilateral triangle of the metric keeps angles of 40
// degrees or more; 1.6 left 19 degrees on the SimVascular aorta's curvature kind at 8000.
constexpr double kMaxStretch = 1.55;
double tube_stretch(const analysis::CurvatureField& c, int v, double radius) {
  const double k_large = std::max(std::abs(c.k1[v]), std::abs(c.k2[v]));
  const double k_small = std::min(std::abs(c.k1[v]), std::abs(c.k2[v]));
  if (!(k_large > 0.0) || !(radius > 0.0) || !std::isfinite(radius)) return 1.0;
  if (k_large * radius > 1.5 || k_large * radius < 1.0 / 1.5) return 1.0;
  const double ratio = k_small / k_large;
  return 1.0 + (kMaxStretch - 1.0) * std::clamp((0.5 - ratio) / 0.4, 0.0, 1.0);
}

// Per input point, the distance to the nearest feature-curve point along the input's edges
// (Dijkstra; infinite without curves).
std::vector<double> distance_to_curves(const TriMesh& input, const analysis::Features& features) {
  std::vector<double> d(input.points.size(), std::numeric_limits<double>::infinity());
  std::vector<std::vector<std::pair<int, double>>> next(input.points.size());
  for (const auto& [a, b] : features.edges.edges) {
    const double l = (input.points[a] - input.points[b]).norm();
    next[a].push_back({b, l});
    next[b].push_back({a, l});
  }
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  for (size_t v = 0; v < d.size(); ++v)
    if (features.kind[v] != analysis::PointKind::free) {
      d[v] = 0.0;
      queue.push({0.0, static_cast<int>(v)});
    }
  while (!queue.empty()) {
    const auto [dv, v] = queue.top();
    queue.pop();
    if (dv > d[v]) continue;
    for (const auto& [u, l] : next[v])
      if (dv + l < d[u]) {
        d[u] = dv + l;
        queue.push({d[u], u});
      }
  }
  return d;
}

// p.metric: M intersected with the chord bound for half the distance bound p.bound (edges up to
// sqrt 2 long then stray at most the bound), refining tenfold at most; p.geometric_points counts
// the points where that made M finer, p.peak where it did most. An isotropic kind's (M isotropic
// everywhere) is longer along tubes (tube_stretch; p.stretched says whether it was) and then graded
// as the size fields are (sizing::grade_metrics, 1.3): where the bound takes over from the field
// (a thin branch off a wide vessel), its sizes meet the field's over a few edges rather than
// across one (without it the crotch of issue 51's bifurcation fell to 17 degrees). An anisotropic
// kind's is left as it was.
constexpr double kBoundGradation = 1.3;
void bounded_metrics(const TriMesh& input, const std::vector<Sym3>& metrics, const std::vector<double>& radius,
                     const analysis::CurvatureField& c, BoundedField& p) {
  const std::vector<double>& bound = p.bound;
  std::vector<Vec3> sizes(metrics.size());
  bool isotropic_field = true;  // an isotropic kind's (an anisotropic field is isotropic where it is clamped)
  for (size_t v = 0; v < metrics.size(); ++v) {
    Eigen::Matrix3d directions;
    sizing::metric_sizes(metrics[v], sizes[v], directions);
    isotropic_field = isotropic_field && !(sizes[v].maxCoeff() > 1.05 * sizes[v].minCoeff());
  }
  const bool stretch_tubes = isotropic_field && !radius.empty();
  // Near a feature curve (an open end's rim keeps its polygon) the stretch fades in: none within
  // one round size of it, all from three (stretched triangles against a rim fell to 23 degrees).
  const std::vector<double> to_curve = stretch_tubes ? distance_to_curves(input, p.features) : std::vector<double>();
  std::vector<Sym3> out = metrics;
  for (size_t v = 0; v < metrics.size(); ++v) {
    if (!std::isfinite(bound[v])) continue;
    const int i = static_cast<int>(v);
    const bool anisotropic = sizes[v].maxCoeff() > 1.05 * sizes[v].minCoeff();
    double stretch = stretch_tubes ? tube_stretch(c, i, radius[v]) : 1.0;
    if (stretch > 1.0) {
      const double round = std::sqrt(8.0 * 0.5 * bound[v] / std::max(std::abs(c.k1[v]), std::abs(c.k2[v])));
      stretch = 1.0 + (stretch - 1.0) * std::clamp((to_curve[v] / round - 1.0) / 2.0, 0.0, 1.0);
      p.stretched = p.stretched || stretch > 1.0;
    }
    const Sym3 chord = stretch > 1.0 ? sizing::stretched_chord_metric(c, i, 0.5 * bound[v], stretch)
                                     : sizing::chord_metric(c, i, 0.5 * bound[v], anisotropic);
    const Sym3 g = sizing::clamp_sizes(chord, 0.1 * sizes[v].minCoeff(), std::numeric_limits<double>::infinity());
    out[v] = sizing::intersect(metrics[v], g);
  }
  if (stretch_tubes) sizing::grade_metrics(input, out, kBoundGradation);
  p.geometric_points = 0;
  for (size_t v = 0; v < metrics.size(); ++v) {
    const double factor = out[v].matrix().trace() / metrics[v].matrix().trace();
    p.geometric_points += factor > 1.01;
    p.peak.raise(static_cast<int>(v), factor);
  }
  p.metric = std::move(out);
}

}  // namespace

BoundedField bounded_field(const TriMesh& input, const std::vector<Sym3>& metrics, const RemeshOptions& options) {
  BoundedField p;
  p.features = analysis::detect_features(input, options.features);
  const bool bounded = options.hausdorff > 0.0 || options.hausdorff_relative > 0.0;
  std::optional<analysis::CurvatureField> own;
  const analysis::CurvatureField* curvature = options.curvature;
  if (!curvature && bounded && (options.geometric_metric || !options.input_radius)) {
    own = analysis::patch_curvature(input, p.features);
    curvature = &*own;
  }
  std::vector<double> radius;
  p.bound = distance_bounds(input, options, curvature, radius);
  if (options.geometric_metric && bounded)
    bounded_metrics(input, metrics, radius, *curvature, p);
  else
    p.metric = metrics;
  return p;
}

std::vector<Sym3> effective_metric(const TriMesh& input, const std::vector<Sym3>& metrics, const RemeshOptions& options,
                                   int* changed) {
  BoundedField p = bounded_field(input, metrics, options);
  if (changed) *changed = p.geometric_points;
  return std::move(p.metric);
}

}  // namespace vesselmesh::remesh
