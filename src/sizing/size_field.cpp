#include "sizing/size_field.h"

#include "analysis/mixed_areas.h"
#include "analysis/normals.h"
#include "mesh/error.h"
#include "sizing/gradation.h"
#include "sizing/metric.h"

#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace vesselmesh::sizing {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const auto i = static_cast<std::ptrdiff_t>(q * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + i, v.end());
  return v[static_cast<size_t>(i)];
}

void validate(const SizingOptions& o, const SizeInputs& in, int points) {
  auto positive = [](double x) { return x > 0.0 && std::isfinite(x); };
  if (o.kind == SizeKind::uniform && !positive(o.h) && !positive(o.target_triangles))
    throw OptionError("a uniform size needs --h (the size in mm) or --target-triangles");
  if (o.kind != SizeKind::uniform && !positive(o.points_per_circle))
    throw OptionError(fmt::format("--points-per-circle must be positive, got {}", o.points_per_circle));
  if ((o.hmin > 0.0) && (o.hmax > 0.0) && o.hmin > o.hmax)
    throw OptionError(fmt::format("--hmin ({}) is larger than --hmax ({})", o.hmin, o.hmax));
  if (o.hmin < 0.0 || o.hmax < 0.0 || o.max_chord_error < 0.0 || o.target_triangles < 0.0 || o.h < 0.0)
    throw OptionError("sizes, chord error and target count must not be negative");
  if (o.kind == SizeKind::flow && (!in.flow || static_cast<int>(in.flow->size()) != points))
    throw InputError("the flow size field needs the flow's error metric on the surface's points");
  if (o.kind == SizeKind::flow && !positive(o.target_triangles))
    throw OptionError("the flow size field needs --target-triangles: the flow's error says where to refine, the count "
                      "how much");
  const bool needs_curvature = o.kind == SizeKind::curvature || o.kind == SizeKind::anisotropic ||
                               o.kind == SizeKind::flow || o.max_chord_error > 0.0;
  if (needs_curvature && (!in.curvature || in.curvature->size() != points))
    throw InternalError("the curvature field is missing for this size field");
  if (o.kind == SizeKind::distance && (!in.distance || in.distance->distance.size() != static_cast<size_t>(points)))
    throw InputError("the distance size field needs centerlines: the surface needs an inlet and an outlet");
}

// The field before clamping, scaling and gradation (sizes in `raw_size`; the anisotropic
// kind keeps its principal sizes in `raw_aniso`, one per direction).
struct RawField {
  std::vector<double> size;
  std::vector<std::array<double, 3>> aniso;  // h1, h2, hn along dir1, dir2, normal
  std::vector<std::array<Vec3, 3>> frame;    // dir1, dir2, normal
};

// The flow's error metric in each point's tangent plane (the curvature's normal): its two
// principal sizes and directions, the normal as the finer, all scaled so that the field meets
// `target` triangles unclamped (its own scale is arbitrary; the clamps, in mm, then mean what
// they say).
void flow_field(const TriMesh& mesh, const SizeInputs& in, double target, RawField& raw) {
  const analysis::CurvatureField& c = *in.curvature;
  std::vector<Sym3> tangent(mesh.points.size());
  for (int v = 0; v < mesh.num_points(); ++v) {
    const Vec3 n = c.normal[v].squaredNorm() > 0.0 ? c.normal[v] : Vec3(c.dir1[v].cross(c.dir2[v]));
    const Vec3 u = n.unitOrthogonal(), w = n.cross(u);
    const Sym3& m = (*in.flow)[v];
    Eigen::Matrix2d m2;
    m2 << m.form(u, u), m.form(u, w), m.form(u, w), m.form(w, w);
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(m2);
    const Eigen::Vector2d l = eig.eigenvalues().cwiseMax(1e-300);
    const Vec3 d1 = eig.eigenvectors()(0, 0) * u + eig.eigenvectors()(1, 0) * w;
    raw.frame.push_back({d1, n.cross(d1), n});
    raw.aniso.push_back({1.0 / std::sqrt(l[0]), 1.0 / std::sqrt(l[1]), 1.0 / std::sqrt(l[1])});
    tangent[v] = metric_from_sizes(d1, raw.aniso[v][0], n.cross(d1), raw.aniso[v][1], n, raw.aniso[v][2]);
  }
  const double s = std::sqrt(predicted_triangles(mesh, tangent) / target);
  for (std::array<double, 3>& h : raw.aniso)
    for (double& x : h) x *= s;
  for (const std::array<double, 3>& h : raw.aniso) raw.size.push_back(std::min(h[0], h[1]));
}

RawField raw_field(const TriMesh& mesh, const SizingOptions& o, const SizeInputs& in) {
  const int np = mesh.num_points();
  const double n = o.points_per_circle;
  RawField raw;
  if (o.kind == SizeKind::flow) {
    flow_field(mesh, in, o.target_triangles, raw);
    return raw;
  }
  raw.size.assign(np, 0.0);
  const double infinite = std::numeric_limits<double>::infinity();
  for (int v = 0; v < np; ++v) {
    switch (o.kind) {
      case SizeKind::uniform: raw.size[v] = o.h > 0.0 ? o.h : 1.0; break;
      case SizeKind::distance: raw.size[v] = kTwoPi * in.distance->distance[v] / n; break;
      case SizeKind::curvature: {
        const double h = std::abs(in.curvature->mean(v));
        raw.size[v] = h > 0.0 ? kTwoPi / (h * n) : infinite;
        break;
      }
      case SizeKind::anisotropic: {
        const double k1 = std::abs(in.curvature->k1[v]), k2 = std::abs(in.curvature->k2[v]);
        const double h1 = k1 > 0.0 ? kTwoPi / (k1 * n) : infinite, h2 = k2 > 0.0 ? kTwoPi / (k2 * n) : infinite;
        raw.aniso.push_back({h1, h2, std::min(h1, h2)});
        const analysis::CurvatureField& c = *in.curvature;
        raw.frame.push_back(
            {c.dir1[v], c.dir2[v], c.normal[v].squaredNorm() > 0 ? c.normal[v] : Vec3(c.dir1[v].cross(c.dir2[v]))});
        raw.size[v] = std::min(h1, h2);
        break;
      }
      case SizeKind::flow: break;
    }
  }
  return raw;
}

// Clamped, chord-bounded metrics for scale s (sizes and clamps multiplied by s).
std::vector<Sym3> build_metrics(const TriMesh& mesh, const SizingOptions& o, const SizeInputs& in, const RawField& raw,
                                double hmin, double hmax, double s) {
  const int np = mesh.num_points();
  std::vector<Sym3> metrics(np);
  const double lo = s * hmin, hi = s * hmax;
  for (int v = 0; v < np; ++v) {
    if (!raw.aniso.empty()) {
      const auto& h = raw.aniso[v];
      const auto& f = raw.frame[v];
      const double h1 = std::clamp(s * h[0], lo, hi), h2 = std::clamp(s * h[1], lo, hi);
      metrics[v] = metric_from_sizes(f[0], h1, f[1], h2, f[2], std::min(h1, h2));
    } else {
      metrics[v] = isotropic_metric(std::clamp(s * raw.size[v], lo, hi));
    }
    if (o.max_chord_error > 0.0) {
      const Sym3 chord = chord_metric(*in.curvature, v, o.max_chord_error, !raw.aniso.empty());
      metrics[v] = intersect(metrics[v], lo > 0.0 ? clamp_sizes(chord, lo, std::numeric_limits<double>::infinity()) : chord);
    }
  }
  return metrics;
}

}  // namespace

Sym3 chord_metric(const analysis::CurvatureField& c, int v, double eps, bool anisotropic) {
  const double d1 = std::abs(c.k1[v]) / (8.0 * eps), d2 = std::abs(c.k2[v]) / (8.0 * eps), dmax = std::max(d1, d2);
  if (!anisotropic || c.normal[v].squaredNorm() == 0.0) return Sym3::from_matrix(dmax * Eigen::Matrix3d::Identity());
  const Vec3 &e1 = c.dir1[v], &e2 = c.dir2[v], &n = c.normal[v];
  return Sym3::from_matrix(d1 * e1 * e1.transpose() + d2 * e2 * e2.transpose() + dmax * n * n.transpose());
}

Sym3 stretched_chord_metric(const analysis::CurvatureField& c, int v, double eps, double stretch) {
  const bool first = std::abs(c.k1[v]) >= std::abs(c.k2[v]);
  const double d = std::max(std::abs(c.k1[v]), std::abs(c.k2[v])) / (8.0 * eps);
  if (c.normal[v].squaredNorm() == 0.0) return Sym3::from_matrix(d * Eigen::Matrix3d::Identity());
  const Vec3 &round = first ? c.dir1[v] : c.dir2[v], &along = first ? c.dir2[v] : c.dir1[v], &n = c.normal[v];
  return Sym3::from_matrix(d * round * round.transpose() + d / (stretch * stretch) * along * along.transpose() +
                           d * n * n.transpose());
}

SizeKind parse_size_kind(const std::string& name) {
  if (name == "uniform") return SizeKind::uniform;
  if (name == "distance") return SizeKind::distance;
  if (name == "curvature") return SizeKind::curvature;
  if (name == "anisotropic") return SizeKind::anisotropic;
  if (name == "flow") return SizeKind::flow;
  throw OptionError(
      fmt::format("unknown size field '{}': use uniform, distance, curvature, anisotropic or flow", name));
}

std::string size_kind_name(SizeKind kind) {
  switch (kind) {
    case SizeKind::uniform: return "uniform";
    case SizeKind::distance: return "distance";
    case SizeKind::curvature: return "curvature";
    case SizeKind::anisotropic: return "anisotropic";
    case SizeKind::flow: return "flow";
  }
  return "uniform";
}

void radius_range(const TriMesh& mesh, const SizeInputs& inputs, double& low, double& high) {
  std::vector<double> radii;
  if (inputs.distance && !inputs.distance->radius.empty()) {
    for (double r : inputs.distance->radius)
      if (r > 0.0 && std::isfinite(r)) radii.push_back(r);
  } else if (inputs.curvature) {
    for (int v = 0; v < inputs.curvature->size(); ++v)
      if (inputs.curvature->k2[v] > 0.0) radii.push_back(1.0 / inputs.curvature->k2[v]);
  }
  if (radii.empty()) throw InputError("cannot tell the vessel's radius range: give --hmin and --hmax");
  (void)mesh;
  low = percentile(radii, 0.05);
  high = percentile(radii, 0.95);
}

double predicted_triangles(const TriMesh& mesh, const std::vector<Sym3>& metrics) {
  const std::vector<double> area = analysis::point_areas(mesh, analysis::corner_areas(mesh));
  const std::vector<Vec3> normals = analysis::vertex_normals(mesh, analysis::NormalMethod::max);
  double sum = 0.0;
  for (int v = 0; v < mesh.num_points(); ++v)
    if (normals[v].squaredNorm() > 0.0) sum += area[v] * tangent_density(metrics[v], normals[v]);
  return 4.0 / std::sqrt(3.0) * sum;
}

SizeField make_size_field(const TriMesh& mesh, const SizingOptions& o, const SizeInputs& in, const Reporter& reporter) {
  validate(o, in, mesh.num_points());
  const std::string task = "building the size field";
  reporter.progress(task, 0.0);
  SizeField field;
  field.kind = o.kind;
  if (o.kind == SizeKind::uniform) {
    field.hmin = 0.0;
    field.hmax = std::numeric_limits<double>::infinity();
  } else {
    double low = in.radius_low, high = in.radius_high;
    if (!(low > 0.0) || !(high > 0.0)) radius_range(mesh, in, low, high);
    field.hmin = o.hmin > 0.0 ? o.hmin : low / 10.0;
    field.hmax = o.hmax > 0.0 ? o.hmax : high;
    if (field.hmin > field.hmax) field.hmin = field.hmax;
  }
  const RawField raw = raw_field(mesh, o, in);
  auto graded = [&](double s, SizeField& f) {
    f.metric = build_metrics(mesh, o, in, raw, field.hmin, field.hmax, s);
    if (o.kind == SizeKind::anisotropic || o.kind == SizeKind::flow) {
      f.gradation_passes = grade_metrics(mesh, f.metric, o.gradation);
    } else {
      std::vector<double> h(f.metric.size());
      for (size_t v = 0; v < h.size(); ++v) h[v] = 1.0 / std::sqrt(f.metric[v].v[0]);
      f.gradation_passes = grade_sizes(mesh, h, o.gradation);
      for (size_t v = 0; v < h.size(); ++v) f.metric[v] = isotropic_metric(h[v]);
    }
    f.predicted_triangles = predicted_triangles(mesh, f.metric);
  };
  double s = 1.0;
  graded(s, field);
  if (o.target_triangles > 0.0) {
    // The count goes as 1 / s^2 where nothing but scaled clamps bind; bisect on log s for
    // the rest (the chord bound does not scale).
    double lo = -30.0, hi = 30.0;  // bracket of log s
    for (int it = 0; it < 60; ++it) {
      const double ratio = field.predicted_triangles / o.target_triangles;
      if (std::abs(ratio - 1.0) < 1e-4) break;
      (ratio > 1.0 ? lo : hi) = std::log(s);
      const double model = std::log(s) + 0.5 * std::log(ratio);  // exact where the count goes as 1 / s^2
      s = std::exp(model > lo && model < hi ? model : 0.5 * (lo + hi));
      graded(s, field);
      reporter.progress(task, 0.1 + 0.8 * it / 60.0);
    }
    if (std::abs(field.predicted_triangles / o.target_triangles - 1.0) > 0.01)
      reporter.warning(fmt::format("the size field predicts {:.0f} triangles, not the {:.0f} asked for (the chord "
                                   "error bound keeps it finer)",
                                   field.predicted_triangles, o.target_triangles));
  }
  field.scale = s;
  field.hmin *= s;
  field.hmax *= s;
  field.size.resize(field.metric.size());
  for (size_t v = 0; v < field.metric.size(); ++v) {
    Vec3 sizes;
    Eigen::Matrix3d directions;
    metric_sizes(field.metric[v], sizes, directions);
    field.size[v] = sizes.minCoeff();
  }
  reporter.progress(task, 1.0);
  return field;
}

}  // namespace vesselmesh::sizing
