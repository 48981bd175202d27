#include "remesh/adapt.h"

#include "analysis/curvature.h"
#include "analysis/open_ends.h"
#include "centerline/distance_map.h"
#include "centerline/extract.h"
#include "io/surface.h"
#include "mesh/clean.h"
#include "mesh/connectivity.h"
#include "mesh/error.h"
#include "mesh/geometry.h"
#include "mesh/statistics.h"
#include "sizing/metric.h"
#include "sizing/size_field.h"
#include "synth/bifurcation.h"
#include "synth/shapes.h"
#include "test_support.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <optional>
#include <set>

namespace vesselmesh::remesh {
namespace {

const double kShort = 1.0 / std::sqrt(2.0), kLong = std::sqrt(2.0);

std::vector<Sym3> metric_of(const TriMesh& m, const std::function<Sym3(const Vec3&)>& at) {
  std::vector<Sym3> out;
  for (const Vec3& p : m.points) out.push_back(at(p));
  return out;
}

// The fraction of edges of unit length and the mean quality, both measured with the analytic
// metric at the output's points (not with what the remesher reports).
struct Figures {
  double in_range = 0.0, mean_quality = 0.0;
};
Figures figures(const TriMesh& m, const std::function<Sym3(const Vec3&)>& at) {
  const std::vector<Sym3> metric = metric_of(m, at);
  const mesh::EdgeMap edges = mesh::build_edge_map(m);
  Figures f;
  for (const auto& [a, b] : edges.edges) {
    const double l = sizing::edge_length(m.points[a], m.points[b], metric[a], metric[b]);
    f.in_range += l >= kShort && l <= kLong;
  }
  f.in_range /= edges.num_edges();
  for (const Triangle& t : m.triangles)
    f.mean_quality += sizing::triangle_quality(m.points[t[0]], m.points[t[1]], m.points[t[2]], metric[t[0]],
                                               metric[t[1]], metric[t[2]]);
  f.mean_quality /= m.num_triangles();
  return f;
}

// How far inside a curved surface of radius r the input's flat triangles lie, at most: the
// depth of a triangle's circumcircle, l^2 / (2 r) for its circumradius l (< the longest edge).
double facet_depth(const TriMesh& input, double r) {
  const double l = mesh::statistics(input).edge_length.max;
  return l * l / (2.0 * r);
}

// The largest angle of any triangle (degrees) and how many triangles have one over `over`.
std::pair<double, int> largest_angle(const TriMesh& m, double over) {
  double largest = 0.0;
  int count = 0;
  for (int t = 0; t < m.num_triangles(); ++t) {
    const auto angles = mesh::triangle_angles(m, t);
    const double a = *std::max_element(angles.begin(), angles.end()) * 180.0 / std::numbers::pi;
    largest = std::max(largest, a);
    count += a > over;
  }
  return {largest, count};
}

Vec3 normal_of(const TriMesh& m, int t) {
  const Triangle& f = m.triangles[t];
  return (m.points[f[1]] - m.points[f[0]]).cross(m.points[f[2]] - m.points[f[0]]).normalized();
}

TEST(Remesh, SphereIsotropicMeetsTheQualityTargets) {
  const TriMesh input = synth::sphere({.radius = 5.0, .resolution = 0.4, .jitter = 0.3});
  const auto metric = [](const Vec3&) { return sizing::isotropic_metric(1.0); };
  const RemeshResult r = adapt(input, metric_of(input, metric));
  const Figures f = figures(r.mesh, metric);
  EXPECT_GE(f.in_range, 0.95);
  EXPECT_GE(f.mean_quality, 0.9);
  EXPECT_NEAR(r.stats.edges_in_unit_range, f.in_range, 1e-12);
  const mesh::Statistics s = mesh::statistics(r.mesh);
  EXPECT_GE(s.min_angle.min, 20.0);
  EXPECT_NEAR(r.stats.min_angle_deg, s.min_angle.min, 1e-9);
  EXPECT_TRUE(s.closed);
  EXPECT_EQ(s.components, 1);
  EXPECT_EQ(s.genus, 0);
  EXPECT_GT(s.volume, 0.0);  // still outward
  // About area / (sqrt 3 / 4) = 726 triangles of unit side.
  EXPECT_GT(r.stats.triangles, 500);
  EXPECT_LT(r.stats.triangles, 1000);
  // Every point on the smooth surface the input's facets stand for (they lie up to `depth`
  // inside the sphere): on the sphere to a tenth of that; every triangle facing out.
  const double depth = facet_depth(input, 5.0);
  for (const Vec3& p : r.mesh.points) EXPECT_NEAR(p.norm(), 5.0, 0.1 * depth);
  for (int t = 0; t < r.mesh.num_triangles(); ++t) {
    const Triangle& g = r.mesh.triangles[t];
    const Vec3 c = (r.mesh.points[g[0]] + r.mesh.points[g[1]] + r.mesh.points[g[2]]) / 3.0;
    EXPECT_GT(normal_of(r.mesh, t).dot(c.normalized()), 0.9) << "triangle " << t;
  }
  // The default bound: 2 % of the radius (here 1 / |k| = 5 mm).
  EXPECT_LE(r.stats.hausdorff, 0.1);
  EXPECT_EQ(r.stats.hausdorff_relative, -1.0);  // no radii given
}

// A cylinder of radius 3 along z, 30 long, its points jittered.
TriMesh jittered_cylinder() {
  return synth::cylinder({.radius = 3.0, .length = 30.0, .resolution = 0.4, .jitter = 0.3});
}
// Sizes `along` on the z axis, `across` round it and through the wall.
std::function<Sym3(const Vec3&)> axial_metric(double along, double across) {
  return [=](const Vec3& p) {
    const Vec3 radial = Vec3(p.x(), p.y(), 0.0).normalized();
    return sizing::metric_from_sizes(Vec3::UnitZ(), along, Vec3::UnitZ().cross(radial), across, radial, across);
  };
}

TEST(Remesh, CylinderAnisotropicFollowsTheMetric) {
  const TriMesh input = jittered_cylinder();
  // Long along the axis (2 mm), short around (0.6 mm): the paper's anisotropic mesh of a pipe.
  const auto metric = axial_metric(2.0, 0.6);
  const RemeshResult r = adapt(input, metric_of(input, metric));
  const Figures f = figures(r.mesh, metric);
  EXPECT_GE(f.in_range, 0.9);
  EXPECT_GE(f.mean_quality, 0.85);
  // Open ends stay: two loops, their points on the end planes and on the input's rim.
  const mesh::Statistics s = mesh::statistics(r.mesh);
  EXPECT_EQ(s.boundary_loops, 2);
  EXPECT_EQ(s.genus, 0);
  const mesh::EdgeMap edges = mesh::build_edge_map(r.mesh);
  int boundary_points = 0;
  for (const auto& loop : mesh::boundary_loops(r.mesh, edges))
    for (int v : loop) {
      const Vec3& p = r.mesh.points[v];
      EXPECT_TRUE(std::abs(p.z()) < 1e-9 || std::abs(p.z() - 30.0) < 1e-9) << p.transpose();
      EXPECT_NEAR(std::hypot(p.x(), p.y()), 3.0, facet_depth(input, 3.0));
      ++boundary_points;
    }
  // Around each rim: 2 pi R / 0.6 = 31 edges.
  EXPECT_NEAR(boundary_points, 2 * 31, 10);
  // Stretched: the mean edge is longer along the axis than around it.
  double axial = 0.0, around = 0.0;
  for (const auto& [a, b] : edges.edges) {
    const Vec3 e = r.mesh.points[b] - r.mesh.points[a];
    axial += std::abs(e.z());
    around += std::hypot(e.x(), e.y());
  }
  EXPECT_GT(axial, 1.3 * around);
}


// An equilateral triangle of a metric stretched 8 times, laid with an edge along the stretch, is a
// cap of 155 degrees in space (2 atan(8 / sqrt 3)); the boundary layer copies it up and no
// tetrahedron on the copy reaches 10 degrees. Where the metric is stretched the remesher judges
// caps worse than their quality in the metric says, and makes needles across the stretch instead.
TEST(Remesh, AStretchedMetricMakesNeedlesRatherThanCaps) {
  const TriMesh input = jittered_cylinder();
  const auto metric = axial_metric(3.2, 0.4);
  const RemeshResult r = adapt(input, metric_of(input, metric));
  const auto [largest, caps] = largest_angle(r.mesh, 140.0);
  // Judged in the metric alone: 165.7 degrees, 556 of 990 triangles over 140; now 154.9, 239 of 991.
  EXPECT_LT(largest, 158.0);
  EXPECT_LT(caps, 0.3 * r.mesh.num_triangles());
  // Still the metric's mesh.
  const Figures f = figures(r.mesh, metric);
  EXPECT_GE(f.in_range, 0.85);
  EXPECT_GE(f.mean_quality, 0.85);
}

TEST(Remesh, TorusKeepsItsGenus) {
  const TriMesh input = synth::torus({.major_radius = 10.0, .minor_radius = 3.0, .resolution = 0.4, .jitter = 0.3});
  RemeshOptions options;
  options.hausdorff = 0.1;
  options.hausdorff_relative = 0.0;
  const auto metric = [](const Vec3&) { return sizing::isotropic_metric(1.0); };
  const RemeshResult r = adapt(input, metric_of(input, metric), options);
  const mesh::Statistics s = mesh::statistics(r.mesh);
  EXPECT_TRUE(s.closed);
  EXPECT_EQ(s.genus, 1);
  EXPECT_LE(r.stats.hausdorff, 0.1);
  EXPECT_GE(s.min_angle.min, 20.0);
  EXPECT_GE(figures(r.mesh, metric).in_range, 0.95);
  // Points on the torus: distance to the core circle is the minor radius.
  const double depth = facet_depth(input, 3.0);
  for (const Vec3& p : r.mesh.points) EXPECT_NEAR(std::hypot(std::hypot(p.x(), p.y()) - 10.0, p.z()), 3.0, depth);
}

TEST(Remesh, CapsStayFlatTheirRimsStayAndLabelsFollow) {
  const TriMesh input = synth::cylinder({.radius = 3.0, .length = 20.0, .resolution = 0.4, .capped = true, .jitter = 0.3});
  const auto metric = [](const Vec3&) { return sizing::isotropic_metric(0.8); };
  const RemeshResult r = adapt(input, metric_of(input, metric));
  const double depth = facet_depth(input, 3.0);
  ASSERT_TRUE(r.mesh.has_labels());
  std::set<int> labels(r.mesh.labels.begin(), r.mesh.labels.end());
  EXPECT_EQ(labels, (std::set<int>{1, 2, 3}));
  for (int t = 0; t < r.mesh.num_triangles(); ++t) {
    const Triangle& g = r.mesh.triangles[t];
    const Vec3 c = (r.mesh.points[g[0]] + r.mesh.points[g[1]] + r.mesh.points[g[2]]) / 3.0;
    const int label = r.mesh.labels[t];
    for (int v : g) {
      const Vec3& p = r.mesh.points[v];
      if (label == 2) {
        EXPECT_NEAR(p.z(), 0.0, 1e-9);
      } else if (label == 3) {
        EXPECT_NEAR(p.z(), 20.0, 1e-9);
      } else {
        EXPECT_NEAR(std::hypot(p.x(), p.y()), 3.0, depth);
      }
    }
    const Vec3 expected = label == 2 ? Vec3(-Vec3::UnitZ()) : label == 3 ? Vec3(Vec3::UnitZ()) : Vec3(c.x(), c.y(), 0).normalized();
    EXPECT_GT(normal_of(r.mesh, t).dot(expected), 0.5) << "triangle " << t << " label " << label;
  }
  const mesh::Statistics s = mesh::statistics(r.mesh);
  EXPECT_TRUE(s.closed);
  EXPECT_EQ(s.genus, 0);
  EXPECT_GE(s.min_angle.min, 20.0);
}

TEST(Remesh, HausdorffBoundHoldsOnACoarseMetric) {
  const TriMesh input = synth::sphere({.radius = 5.0, .resolution = 0.4, .jitter = 0.3});
  RemeshOptions options;
  options.hausdorff = 0.05;
  options.hausdorff_relative = 0.0;
  const RemeshResult r = adapt(input, metric_of(input, [](const Vec3&) { return sizing::isotropic_metric(4.0); }), options);
  EXPECT_LE(r.stats.hausdorff, 0.05 + 1e-12);
  // Measured independently: a triangle's centroid lies inside the sphere by its sagitta.
  for (const Triangle& g : r.mesh.triangles) {
    const Vec3 c = (r.mesh.points[g[0]] + r.mesh.points[g[1]] + r.mesh.points[g[2]]) / 3.0;
    EXPECT_LT(5.0 - c.norm(), 0.05 + facet_depth(input, 5.0));
  }
  // Without the bound the same metric strays farther.
  options.hausdorff = 0.0;
  const RemeshResult loose = adapt(input, metric_of(input, [](const Vec3&) { return sizing::isotropic_metric(4.0); }), options);
  EXPECT_GT(loose.stats.hausdorff, 0.1);
}

TEST(Remesh, DeterministicRunAfterRun) {
  const TriMesh input = synth::cylinder({.radius = 3.0, .length = 15.0, .resolution = 0.4, .capped = true, .jitter = 0.3});
  const std::vector<Sym3> metric = metric_of(input, [](const Vec3& p) { return sizing::isotropic_metric(0.5 + 0.05 * p.z()); });
  const RemeshResult a = adapt(input, metric), b = adapt(input, metric);
  ASSERT_EQ(a.mesh.points.size(), b.mesh.points.size());
  EXPECT_TRUE(a.mesh.points == b.mesh.points);
  EXPECT_TRUE(a.mesh.triangles == b.mesh.triangles);
  EXPECT_TRUE(a.mesh.labels == b.mesh.labels);
}

TEST(Remesh, TargetCountIsReachedWithinThreePercent) {
  const TriMesh input = synth::sphere({.radius = 5.0, .resolution = 0.4, .jitter = 0.3});
  const std::vector<Sym3> metric = metric_of(input, [](const Vec3&) { return sizing::isotropic_metric(1.0); });
  const RemeshResult r = adapt_to_count(input, metric, 1500.0);
  EXPECT_NEAR(r.stats.triangles, 1500.0, 45.0);
}

// fit_count on an engine whose count is a given function of the metric's scale (the metric is
// the identity scaled: its first entry is the scale).
struct CountingEngine {
  std::function<int(double)> count;
  mutable std::vector<double> scales = {};
  int tightened = 0;  // what the engine says the distance bound did
  RemeshResult operator()(const std::vector<Sym3>& metric) const {
    scales.push_back(metric[0].v[0]);
    RemeshResult r;
    r.stats.triangles = count(metric[0].v[0]);
    r.stats.tightened = tightened;
    return r;
  }
};

// The log, kept.
struct KeptLog : Reporter {
  mutable std::string text, warnings;
  void info(std::string_view message) const override { text += std::string(message) + "\n"; }
  void warning(std::string_view message) const override { warnings += std::string(message) + "\n"; }
};

// A count a bound holds (it barely moves with the scale): two weak steps in a row end the loop,
// the log saying which bound (issue 31),
// the closest run kept; one weak step alone (scatter) does not.
TEST(FitCount, EndsWhenABoundHoldsTheCount) {
  const std::vector<Sym3> identity(4, Sym3::from_matrix(Eigen::Matrix3d::Identity()));
  CountingEngine held{[](double s) { return static_cast<int>(16000.0 * std::pow(s, 0.05)); }};
  const KeptLog log;
  const RemeshResult r = fit_count(std::cref(held), identity, 8000.0, log);
  EXPECT_EQ(held.scales.size(), 3u);  // the first run and two weak steps (6 corrections allowed)
  EXPECT_EQ(r.stats.triangles, held.count(held.scales.back()));
  EXPECT_LT(r.stats.triangles, 16000);
  // Which bound, said (a warning, and the result's note): none acted (the mesh within the
  // field's unit band already, as a structured pipe near its own count), or the distance bound
  // where it tightened the metric.
  EXPECT_NE(r.count_note.find("no bound acted"), std::string::npos) << r.count_note;
  EXPECT_EQ(r.count_note.find("the distance bound"), std::string::npos) << r.count_note;
  EXPECT_EQ(log.warnings, r.count_note + "\n");
  CountingEngine bounded{held.count, {}, 12};
  const KeptLog bounded_log;
  const RemeshResult b = fit_count(std::cref(bounded), identity, 8000.0, bounded_log);
  EXPECT_NE(b.count_note.find("the distance bound holds it (--hausdorff-relative"), std::string::npos) << b.count_note;
  EXPECT_NE(bounded_log.warnings.find("the distance bound holds it"), std::string::npos);
  // The count where the steps stopped moving it is the least this kind has within the bound (issue
  // 51): given, and said; not where no bound acted, nor where the loop reached its target.
  EXPECT_EQ(b.least_count, b.stats.triangles);
  EXPECT_NE(b.count_note.find(fmt::format("the least count this kind has within the bound is about {} ",
                                          b.stats.triangles)),
            std::string::npos)
      << b.count_note;
  EXPECT_EQ(r.least_count, 0);
  // Weak once (scatter), then proportional again: the target is reached.
  CountingEngine scattered{[](double s) { return s > 0.8 ? 11526 : static_cast<int>(11526.0 * s / 0.8); }};
  const RemeshResult t = fit_count(std::cref(scattered), identity, 10000.0);
  EXPECT_NEAR(t.stats.triangles, 10000, 200);
  EXPECT_TRUE(t.count_note.empty()) << t.count_note;
  EXPECT_EQ(t.least_count, 0);
}

// A scattered count that leaves the bracket as it was would repeat a scale: the loop ends instead.
TEST(FitCount, NeverRepeatsAScale) {
  const std::vector<Sym3> identity(4, Sym3::from_matrix(Eigen::Matrix3d::Identity()));
  CountingEngine engine{[](double s) { return s < 1.2 ? 6000 : (s < 1.9 ? 5000 : 18000); }};
  const RemeshResult r = fit_count(std::cref(engine), identity, 12000.0);
  std::vector<double> sorted = engine.scales;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(std::adjacent_find(sorted.begin(), sorted.end()), sorted.end());
  EXPECT_EQ(engine.scales.size(), 3u);  // 1, 2, then the interpolated one
  EXPECT_EQ(r.stats.triangles, 6000);   // the closest of 6000, 18000 and 5000
  EXPECT_NE(r.count_note.find("jumps from 6000 (the field scaled by 1) to 18000 (by 2)"), std::string::npos)
      << r.count_note;
  // A structured input: every edge crosses the band at once, the count a step (the pipe of
  // regular diagonals at 0.6 mm: 1638 triangles, its own, up to a scale, 3108 beyond); the note says
  // between which counts it jumps. Without a bracket, the count's scatter.
  CountingEngine step{[](double s) { return s < 0.8 ? 1638 : 3108; }};
  const RemeshResult st = fit_count(std::cref(step), identity, 2000.0);
  EXPECT_EQ(st.stats.triangles, 1638);
  EXPECT_NE(st.count_note.find("jumps from 1638"), std::string::npos) << st.count_note;
  EXPECT_NE(st.count_note.find("to 3108"), std::string::npos) << st.count_note;
  CountingEngine flat_above{[](double s) { return s < 0.5 ? 2600 : 2700; }};
  const RemeshResult fa = fit_count(std::cref(flat_above), identity, 2000.0);
  EXPECT_FALSE(fa.count_note.empty());
  EXPECT_EQ(fa.count_note.find("jumps"), std::string::npos) << fa.count_note;
}

TEST(Remesh, AMetricOfAnotherSurfaceIsAnError) {
  const TriMesh input = synth::sphere({.radius = 5.0, .resolution = 1.0});
  EXPECT_THROW(adapt(input, std::vector<Sym3>(3, sizing::isotropic_metric(1.0))), InputError);
  RemeshOptions options;
  options.hausdorff = -1.0;
  EXPECT_THROW(adapt(input, metric_of(input, [](const Vec3&) { return sizing::isotropic_metric(1.0); }), options),
               OptionError);
}

// The local radius of the distance bound, as `vesselmesh remesh` takes it: the distance map's
// where the surface has ends to trace centerlines between; else (a closed surface: no distance
// kind either) the inner poles'.
struct LocalRadius {
  std::optional<centerline::DistanceMap> distance;
  std::vector<double> radius;
};
LocalRadius local_radius(const TriMesh& input) {
  LocalRadius r;
  try {
    r.distance = centerline::distance_map(input, centerline::extract(input));
    r.radius = r.distance->radius;
  } catch (const InputError&) {
    r.radius = centerline::pole_radius(input);
  }
  return r;
}

// A faceted segmentation of `fine`, as a coarse image gives: remeshed onto its own facets to edges of
// `size`, with no distance bound.
TriMesh faceted(const TriMesh& fine, double size) {
  RemeshOptions coarse;
  coarse.hausdorff_relative = 0.0;
  coarse.reconstruction = Reconstruction::facets;
  return adapt(fine, metric_of(fine, [size](const Vec3&) { return sizing::isotropic_metric(size); }), coarse).mesh;
}

// Issue 31's class of inputs: a coarse, faceted segmentation of a bifurcation whose daughters'
// radii (0.8, 0.6 mm) are about its edges (0.55 mm).
TriMesh coarse_faceted_bifurcation() {
  return faceted(synth::bifurcation({.radius = 2.3, .daughter_radius = {0.8, 0.6}, .parent_length = 10.0,
                                     .daughter_length = 8.0, .blend = 0.6, .resolution = 0.3}),
                 0.55);
}

// Needles and near-duplicate points, as an edited segmentation has them: every so many edges
// split a thousandth of the way from one end (each triangle split once at most).
TriMesh with_needles(const TriMesh& input, int every) {
  TriMesh out = input;
  const mesh::EdgeMap edges = mesh::build_edge_map(input);
  const mesh::VertexTriangles incidence = mesh::build_vertex_triangles(input);
  std::vector<char> used(input.triangles.size(), 0);
  for (int e = 0; e < edges.num_edges(); e += every) {
    const auto [a, b] = edges.edges[e];
    std::vector<int> around;
    for (int t : incidence.of(a))
      if (mesh::corner_of(input.triangles[t], b) >= 0) around.push_back(t);
    if (around.size() != 2 || used[around[0]] || used[around[1]]) continue;
    const int p = out.num_points();
    out.points.push_back(input.points[a] + 1e-3 * (input.points[b] - input.points[a]));
    for (int t : around) {
      used[t] = 1;
      Triangle f = out.triangles[t];
      Triangle g = f;
      f[mesh::corner_of(f, b)] = p;  // a, p, c and p, b, c in the triangle's own order
      g[mesh::corner_of(g, a)] = p;
      out.triangles[t] = f;
      out.triangles.push_back(g);
    }
  }
  return out;
}

// The four kinds at `target` triangles with the default distance bound (the local radius from
// the distance map, else the inner poles, as `vesselmesh remesh`): the count within 3 %,
// isotropic smallest angle >= 20 degrees, anisotropic mean quality >= 0.85, and the distance to
// the smooth surface within 2 % of the radius.
void expect_four_kinds_meet_the_targets(const TriMesh& input, double target, const std::string& what) {
  const analysis::CurvatureField curvature = analysis::curvature(input);
  const auto [distance, radius] = local_radius(input);
  for (sizing::SizeKind kind : {sizing::SizeKind::uniform, sizing::SizeKind::distance, sizing::SizeKind::curvature,
                                sizing::SizeKind::anisotropic}) {
    if (kind == sizing::SizeKind::distance && !distance) continue;
    const std::string name = what + " " + sizing::size_kind_name(kind);
    const sizing::SizeField field = sizing::make_size_field(
        input, {.kind = kind, .target_triangles = target},
        {.curvature = &curvature, .distance = distance ? &*distance : nullptr});
    RemeshOptions options;
    options.input_radius = &radius;
    const KeptLog log;
    const RemeshResult r = adapt_to_count(input, field.metric, target, options, log);
    const RemeshStats& s = r.stats;
    SCOPED_TRACE(log.text);
    // Within 3 %, or (above it) the note says the distance bound holds the count, and where.
    if (std::abs(s.triangles / target - 1.0) > 0.03) {
      EXPECT_GT(s.triangles, target) << name;
      EXPECT_NE(r.count_note.find("the distance bound holds it"), std::string::npos) << name << ": " << r.count_note;
      EXPECT_NE(r.count_note.find("near input point"), std::string::npos) << name << ": " << r.count_note;
      EXPECT_LT(s.triangles, 1.15 * target) << name;  // (the facets held it at 2.5 times)
    } else {
      EXPECT_TRUE(r.count_note.empty()) << name << ": " << r.count_note;
    }
    if (kind == sizing::SizeKind::anisotropic) {
      EXPECT_GE(s.mean_quality, 0.85) << name;
      // Few caps (the layer copies them): 15-33 % of the triangles over 150 degrees on these inputs
      // when judged in the metric alone, 1.6-5.3 % now.
      EXPECT_LT(largest_angle(r.mesh, 150.0).second, 0.08 * s.triangles) << name;
    } else
      EXPECT_GE(s.min_angle_deg, 20.0) << name;
    EXPECT_LE(s.hausdorff_relative, 0.02 + 1e-9) << name;
    EXPECT_GE(s.hausdorff_facets, s.hausdorff) << name;  // the facets lie off the smooth surface
  }
}

// Issue 31: the distance bound measured against the smooth surface, not the facets. On the
// facets (as mmgs and as before) the same command gives 2.5 times the count asked: the bound
// refines to reproduce the facets' creases.
TEST(Remesh, CoarseFacetedSegmentationMeetsTheCountAndTheAngles) {
  const TriMesh input = coarse_faceted_bifurcation();
  ASSERT_GT(mesh::statistics(input).edge_length.mean, 0.5);
  expect_four_kinds_meet_the_targets(input, 20000.0, "open");
  // The same on the facets: the count held far above the target by the bound.
  const analysis::CurvatureField curvature = analysis::curvature(input);
  const std::vector<double> radius = centerline::distance_map(input, centerline::extract(input)).radius;
  RemeshOptions facets;
  facets.reconstruction = Reconstruction::facets;
  facets.input_radius = &radius;
  const sizing::SizeField uniform = sizing::make_size_field(
      input, {.kind = sizing::SizeKind::uniform, .target_triangles = 12000.0}, {.curvature = &curvature});
  const RemeshResult held = adapt_to_count(input, uniform.metric, 12000.0, facets);
  EXPECT_GT(held.stats.triangles, 1.5 * 12000.0);
  EXPECT_DOUBLE_EQ(held.stats.hausdorff, held.stats.hausdorff_facets);
}

// The same closed by flat caps of a few triangles each (fans from the ends' centres: the
// smallest of 6 triangles), and with needles and near-duplicate points through the doctor as
// `vesselmesh remesh` reads them.
TEST(Remesh, CappedAndNeedleSegmentationsMeetTheCountAndTheAngles) {
  const TriMesh open = coarse_faceted_bifurcation();
  TriMesh capped = analysis::fan_capped(open, analysis::open_ends(open));
  mesh::clean(capped, {.find_self_intersections = false});
  ASSERT_TRUE(mesh::statistics(capped).closed);
  expect_four_kinds_meet_the_targets(capped, 20000.0, "capped");
  TriMesh needles = with_needles(synth::bifurcation({.radius = 2.3, .daughter_radius = {0.8, 0.6},
                                                     .parent_length = 10.0, .daughter_length = 8.0, .blend = 0.6,
                                                     .resolution = 0.3, .jitter = 0.45}),
                                 7);
  mesh::clean(needles, {.find_self_intersections = false});
  ASSERT_LT(mesh::statistics(needles).edge_length.min, 1e-3);
  ASSERT_LT(mesh::statistics(needles).min_angle.min, 1.0);
  expect_four_kinds_meet_the_targets(needles, 20000.0, "needles");
}

// Issue 51: a bifurcation with a thin daughter (radius 0.36 mm beside 2.3 and 2.0), where the
// distance bound, not the field, sizes the mesh.
synth::BifurcationOptions thin_branch() {
  return {.radius = 2.3, .daughter_radius = {2.0, 0.36}, .parent_length = 10.0, .daughter_length = 12.0,
          .blend = 0.3, .resolution = 0.12};
}

// The triangles whose centroids lie on the thin daughter (within twice its radius of its axis),
// from `from` to `to` along it (mm from the junction).
int thin_daughter_triangles(const TriMesh& mesh, double from, double to) {
  const synth::BifurcationOptions o = thin_branch();
  const double a = o.angle_deg[1] * std::numbers::pi / 180.0;
  const Vec3 axis(-std::sin(a), 0.0, std::cos(a));
  int count = 0;
  for (const Triangle& f : mesh.triangles) {
    const Vec3 c = (mesh.points[f[0]] + mesh.points[f[1]] + mesh.points[f[2]]) / 3.0;
    const double t = c.dot(axis);
    count += t > from && t < to && (c - t * axis).norm() < 2.0 * o.daughter_radius[1];
  }
  return count;
}

// What the bound needs on that stretch: a polygon of n sides within 2 % of the radius of the circle
// (r (1 - cos(pi / n)) <= 0.02 r: n = 16), its side the edge of equilateral triangles over the tube.
double thin_daughter_need(double from, double to) {
  const double r = thin_branch().daughter_radius[1];
  const double sides = std::ceil(std::numbers::pi / std::acos(1.0 - 0.02));
  const double h = 2.0 * std::numbers::pi * r / sides;
  return 2.0 * std::numbers::pi * r * (to - from) / (std::sqrt(3.0) / 4.0 * h * h);
}

// The isotropic kinds asked far fewer triangles than the thin daughter needs: its triangles at
// least 0.8 times what the bound needs there (the bound held) and at most 1.25 times (issue 51;
// 1.21 measured with the bound's chord metric longer along the tube, 1.8 to 1.9 with it
// isotropic); angles >= 20 degrees (the
// curvature kind's were 17 at the open ends' rims, where a plane cut's needles made the curvature
// 2600 / mm), >= 26 at the count the bound sets (the triangles stretched along the daughter judged
// in space by the last flips and moves: 27.2-27.5 degrees, 24.2-25.7 judged in the metric); the
// least count reported, and every kind within 3 % of a count above it.
TEST(Remesh, AThinBranchHoldsTheBoundAndTheAnglesAndCountsAboveItsLeast) {
  const TriMesh input = synth::bifurcation(thin_branch());
  const analysis::CurvatureField curvature = analysis::curvature(input);
  const auto [distance, radius] = local_radius(input);
  ASSERT_TRUE(distance);
  const double from = 3.0, to = 10.0, need = thin_daughter_need(from, to);
  for (sizing::SizeKind kind : {sizing::SizeKind::uniform, sizing::SizeKind::distance, sizing::SizeKind::curvature,
                                sizing::SizeKind::anisotropic}) {
    const std::string name = sizing::size_kind_name(kind);
    RemeshOptions options;
    options.input_radius = &radius;
    const auto run = [&](double target) {
      const sizing::SizeField field = sizing::make_size_field(input, {.kind = kind, .target_triangles = target},
                                                              {.curvature = &curvature, .distance = &*distance});
      return adapt_to_count(input, field.metric, target, options);
    };
    double above = 8000.0;
    if (kind != sizing::SizeKind::anisotropic) {
      const RemeshResult few = run(2000.0);
      const int on_thin = thin_daughter_triangles(few.mesh, from, to);
      EXPECT_LE(on_thin, 1.25 * need) << name;
      EXPECT_GE(on_thin, 0.8 * need) << name;
      EXPECT_LE(few.stats.hausdorff_relative, 0.02 + 1e-9) << name;
      EXPECT_GE(few.stats.min_angle_deg, 26.0) << name;
      ASSERT_GT(few.least_count, 2000) << name << ": " << few.count_note;
      above = std::max(above, 1.05 * few.least_count);
    }
    const RemeshResult r = run(above);
    EXPECT_NEAR(r.stats.triangles, above, 0.03 * above) << name << ": " << r.count_note;
    if (kind != sizing::SizeKind::anisotropic) {
      EXPECT_GE(r.stats.min_angle_deg, 20.0) << name;
    }
    EXPECT_LE(r.stats.hausdorff_relative, 0.02 + 1e-9) << name;
  }
}

// The same closed by flat caps, from a faceted segmentation of it (about 7 edges round the thin
// daughter, as a segmentation of a thin coronary branch has): the isotropic kinds keep their
// angles at 20000 triangles and at the least count (a real capped coronary tree gave 12 degrees).
TEST(Remesh, ACappedFacetedThinBranchKeepsItsAngles) {
  const TriMesh open = faceted(synth::bifurcation(thin_branch()), 0.3);
  TriMesh capped = analysis::fan_capped(open, analysis::open_ends(open));
  mesh::clean(capped, {.find_self_intersections = false});
  ASSERT_TRUE(mesh::statistics(capped).closed);
  const analysis::CurvatureField curvature = analysis::curvature(capped);
  const std::vector<double> radius = local_radius(capped).radius;
  for (sizing::SizeKind kind : {sizing::SizeKind::uniform, sizing::SizeKind::curvature}) {
    RemeshOptions options;
    options.input_radius = &radius;
    const auto run = [&](double target) {
      const sizing::SizeField field =
          sizing::make_size_field(capped, {.kind = kind, .target_triangles = target}, {.curvature = &curvature});
      return adapt_to_count(capped, field.metric, target, options);
    };
    for (double target : {20000.0, 2000.0}) {
      const RemeshResult r = run(target);
      const std::string name = fmt::format("{} at {}", sizing::size_kind_name(kind), target);
      EXPECT_GE(r.stats.min_angle_deg, 20.0) << name;
      EXPECT_LE(r.stats.hausdorff_relative, 0.02 + 1e-9) << name;
      if (target < 20000.0) {
        EXPECT_GT(r.least_count, 0) << name << ": " << r.count_note;
      }
    }
  }
}

// Issue 51: the aortic arch's uniform mesh at 20,000 triangles, whose bound stretches it along the
// small supra-aortic branches (to 1.55 times): its smallest angle 29.2 degrees with the last flips
// and moves judging shapes in space, 24.8 when they judged them in the metric (there 36-43 degrees:
// well shaped in the metric, stretched in space), 29.2 before the stretch; the count, the bound and
// the metric's shapes as they were.
TEST(Remesh, TheAorticArchsStretchedUniformMeshIsWellShapedInSpace) {
  VESSELMESH_REQUIRE_SHARED(path, "vessels/gmsh_aortic_arch_open_cm.stl");
  io::SurfaceFile file = io::read_surface(path, {.units = io::Unit::cm});
  mesh::clean(file.mesh, {.find_self_intersections = false});
  const TriMesh& input = file.mesh;
  const analysis::CurvatureField curvature = analysis::curvature(input);
  const auto [distance, radius] = local_radius(input);
  ASSERT_TRUE(distance);
  constexpr double kTarget = 20000.0;
  const sizing::SizeField field = sizing::make_size_field(input, {.kind = sizing::SizeKind::uniform,
                                                                  .target_triangles = kTarget},
                                                          {.curvature = &curvature, .distance = &*distance});
  RemeshOptions options;
  options.input_radius = &radius;
  const RemeshResult r = adapt_to_count(input, field.metric, kTarget, options);
  EXPECT_GE(r.stats.min_angle_deg, 28.0);
  EXPECT_GE(r.stats.mean_quality, 0.9);
  EXPECT_NEAR(r.stats.triangles, kTarget, 0.03 * kTarget) << r.count_note;
  EXPECT_LE(r.stats.hausdorff_relative, 0.02 + 1e-9);
}

// The quality targets on the real vessels, for the four size kinds at a common triangle count.
struct Vessel {
  std::string file, units;
};
void PrintTo(const Vessel& v, std::ostream* os) { *os << v.file << " (" << v.units << ")"; }

class RealVessel : public testing::TestWithParam<Vessel> {};

TEST_P(RealVessel, AllFourKindsMeetTheTargets) {
  VESSELMESH_REQUIRE_SHARED(path, "vessels/" + GetParam().file);
  io::SurfaceFile file = io::read_surface(path, {.units = io::parse_unit(GetParam().units)});
  mesh::clean(file.mesh, {.find_self_intersections = false});
  const TriMesh& input = file.mesh;
  const mesh::Statistics before = mesh::statistics(input);
  const analysis::CurvatureField curvature = analysis::curvature(input);
  const auto [distance, radius] = local_radius(input);
  const std::set<int> labels(input.labels.begin(), input.labels.end());
  for (sizing::SizeKind kind : {sizing::SizeKind::uniform, sizing::SizeKind::distance, sizing::SizeKind::curvature,
                                sizing::SizeKind::anisotropic}) {
    if (kind == sizing::SizeKind::distance && !distance) continue;
    const std::string name = sizing::size_kind_name(kind);
    const sizing::SizeField field = sizing::make_size_field(
        input, {.kind = kind, .target_triangles = 8000.0},
        {.curvature = &curvature, .distance = distance ? &*distance : nullptr});
    RemeshOptions options;
    options.input_radius = &radius;
    const RemeshResult r = adapt(input, field.metric, options);
    const RemeshStats& s = r.stats;
    if (kind == sizing::SizeKind::anisotropic) {
      EXPECT_GE(s.edges_in_unit_range, 0.90) << name;
      EXPECT_GE(s.mean_quality, 0.85) << name;
    } else {
      EXPECT_GE(s.edges_in_unit_range, 0.95) << name;
      EXPECT_GE(s.mean_quality, 0.90) << name;
      EXPECT_GE(s.min_angle_deg, 20.0) << name;
    }
    EXPECT_LE(s.hausdorff_relative, 0.02 + 1e-9) << name;
    // The input's topology and labels.
    const mesh::Statistics after = mesh::statistics(r.mesh);
    EXPECT_EQ(after.components, before.components) << name;
    EXPECT_EQ(after.boundary_loops, before.boundary_loops) << name;
    EXPECT_EQ(after.genus, before.genus) << name;
    EXPECT_EQ(std::set<int>(r.mesh.labels.begin(), r.mesh.labels.end()), labels) << name;
    // At least the count the field predicts, before any correction: the distance bound adds
    // points where the field is coarser than the vessel's curvature (or the input's facets)
    // allow, up to 3.8 times on the faceted SimVascular model at this coarse target.
    EXPECT_GT(s.triangles, 0.75 * 8000.0) << name;
  }
}

// The sizing issue's target count: after correction, within 3 % for every kind.
TEST_P(RealVessel, TargetCountWithinThreePercent) {
  VESSELMESH_REQUIRE_SHARED(path, "vessels/" + GetParam().file);
  io::SurfaceFile file = io::read_surface(path, {.units = io::parse_unit(GetParam().units)});
  mesh::clean(file.mesh, {.find_self_intersections = false});
  const TriMesh& input = file.mesh;
  const analysis::CurvatureField curvature = analysis::curvature(input);
  std::optional<centerline::DistanceMap> distance;
  try {
    distance = centerline::distance_map(input, centerline::extract(input));
  } catch (const InputError&) {
    GTEST_SKIP() << "no ends: the target count is checked on the vessels with ends";
  }
  if (input.has_labels()) GTEST_SKIP() << "checked on three vessels without labels";
  constexpr double kTarget = 10000.0;
  for (sizing::SizeKind kind : {sizing::SizeKind::uniform, sizing::SizeKind::distance, sizing::SizeKind::curvature,
                                sizing::SizeKind::anisotropic}) {
    const sizing::SizeField field = sizing::make_size_field(
        input, {.kind = kind, .target_triangles = kTarget}, {.curvature = &curvature, .distance = &*distance});
    // The paper's comparison: the size field alone decides, no distance bound (with one, the
    // count cannot fall below what the bound needs: the carotid then lands 7-28 % above).
    RemeshOptions options;
    options.hausdorff_relative = 0.0;
    const KeptLog log;
    const RemeshResult r = adapt_to_count(input, field.metric, kTarget, options, log);
    EXPECT_NEAR(r.stats.triangles, kTarget, 0.03 * kTarget) << sizing::size_kind_name(kind) << "\n" << log.text;
  }
}

INSTANTIATE_TEST_SUITE_P(Vessels, RealVessel,
                         testing::Values(Vessel{"vmtk_aorta_iliac_bifurcation_open_mm.stl", "mm"},
                                         Vessel{"vmtk_aorta_iliac_bifurcation_closed_mm.stl", "mm"},
                                         Vessel{"gmsh_aortic_arch_open_cm.stl", "cm"},
                                         Vessel{"gmsh_carotid_bifurcation_open_m.stl", "m"},
                                         Vessel{"simvascular_demo_aorta_iliacs_capped_cm.vtp", "cm"}),
                         [](const testing::TestParamInfo<Vessel>& param) { return test::test_name(param.param.file); });

}  // namespace
}  // namespace vesselmesh::remesh
