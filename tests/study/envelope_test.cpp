#include "study/envelope.h"

#include "analysis/open_ends.h"
#include "centerline/distance_map.h"
#include "centerline/extract.h"
#include "analysis/curvature.h"
#include "io/surface.h"
#include "mesh/clean.h"
#include "mesh/error.h"
#include "mesh/locator.h"
#include "remesh/adapt.h"
#include "sizing/metric.h"
#include "sizing/size_field.h"
#include "synth/shapes.h"
#include "volume/boundary_layer.h"

#include "test_support.h"
#include "volume/interior_size.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

namespace vesselmesh::study {
namespace {

TEST(Envelope, TriangleSizeIsTheEdgeOfTheEquilateralTriangleOfTheSameLeastAltitude) {
  // Equilateral of edge 2: its edge.
  EXPECT_NEAR(triangle_size({0, 0, 0}, {2, 0, 0}, {1, std::sqrt(3.0), 0}), 2.0, 1e-12);
  // A needle of legs 1 and 10 (an anisotropic mesh's 1 x 10 triangle): its least altitude, 10 / sqrt 101,
  // about the short leg.
  EXPECT_NEAR(triangle_size({0, 0, 0}, {10, 0, 0}, {0, 1, 0}), 2.0 / std::sqrt(3.0) * 10.0 / std::sqrt(101.0), 1e-12);
  EXPECT_EQ(triangle_size({0, 0, 0}, {0, 0, 0}, {0, 0, 0}), 0.0);
}

TEST(Envelope, AchievedSizesAreTheMeanOfTheTrianglesAround) {
  TriMesh m;
  m.points = {{0, 0, 0}, {2, 0, 0}, {1, std::sqrt(3.0), 0}, {10, 0, 0}, {5, 5, 5}};
  m.triangles = {{0, 1, 2}, {1, 3, 2}};
  const std::vector<double> s = achieved_sizes(m);
  const double second = triangle_size(m.points[1], m.points[3], m.points[2]);
  EXPECT_NEAR(s[0], 2.0, 1e-12);
  EXPECT_NEAR(s[1], 0.5 * (2.0 + second), 1e-12);
  EXPECT_NEAR(s[3], second, 1e-12);
  EXPECT_EQ(s[4], 0.0);  // used by no triangle
}

// Level k's scale: the coarsest level the envelope itself with the margin, each next factor finer.
// (Three levels or more; one or two are a reference without a grid convergence, a factor finer.)
TEST(Envelope, TheSeriesStartsAtTheEnvelope) {
  EXPECT_DOUBLE_EQ(envelope_level_scale(1.33, 1, 3), kEnvelopeMargin);
  EXPECT_NEAR(envelope_level_scale(1.33, 2, 3), 1.1 * 1.33, 1e-12);
  EXPECT_NEAR(envelope_level_scale(1.33, 3, 3), 1.1 * 1.33 * 1.33, 1e-12);  // the defaults' reference: 1.95
  EXPECT_NEAR(envelope_level_scale(1.5, 2, 4), 1.65, 1e-12);
  EXPECT_NEAR(envelope_level_scale(1.33, 1, 1), 1.1 * 1.33, 1e-12);  // the demo's one level
  EXPECT_NEAR(envelope_level_scale(1.33, 2, 2), 1.1 * 1.33 * 1.33, 1e-12);
}

// Level k's layer: the first height the compared layer's over the scale, over the same thickness,
// the heights growing from the wall by at most kMostLayerGrowth: exactly the scale where that
// growth does, else uniform layers a little finer.
TEST(Envelope, LevelLayersDivideTheFirstHeightByTheScale) {
  for (const int layers : {2, 4, 5})
    for (const double scale : {1.0, 1.1, 1.33, 1.1 * 1.33, 1.33 * 1.33, 1.33 * 1.33 * 1.33, 2.0, 3.7}) {
      const LevelLayers l = level_layers(layers, scale);
      EXPECT_GE(l.layers, layers);
      EXPECT_GE(l.growth, 1.0);
      EXPECT_LE(l.growth, kMostLayerGrowth + 1e-9) << layers << " " << scale;
      const std::vector<double> f = volume::layer_fractions(l.layers, l.growth);
      ASSERT_EQ(f.size(), static_cast<size_t>(l.layers) + 1);
      EXPECT_NEAR(f.back(), 1.0, 1e-12);
      const double asked = 1.0 / (layers * scale);
      if (l.growth > 1.0) {
        EXPECT_NEAR(f[1], asked, 1e-9) << layers << " layers, scale " << scale;
      }
      EXPECT_LE(f[1], asked * (1 + 1e-9)) << layers << " layers, scale " << scale;
      EXPECT_GE(f[1], asked * layers * scale / std::ceil(layers * scale - 1e-9) - 1e-12);
    }
  EXPECT_EQ(level_layers(4, 1.0).layers, 4);
  EXPECT_DOUBLE_EQ(level_layers(4, 1.0).growth, 1.0);
  EXPECT_EQ(level_layers(2, 1.1).layers, 2);  // growth 1.2 exactly, the most allowed: kept
  EXPECT_NEAR(level_layers(2, 1.1).growth, 1.2, 1e-12);
  EXPECT_EQ(level_layers(2, 1.33).layers, 3);  // growth 1.66 for two layers: three uniform ones
  EXPECT_EQ(level_layers(4, 1.33).layers, 5);  // 5.32: five growing by a little
  EXPECT_GT(level_layers(4, 1.33).growth, 1.0);
  EXPECT_EQ(level_layers(0, 2.0).layers, 0);
}

// Level k's layer under every compared flow kind's where their first height thinned it: two flow kinds
// asking 0.02 mm for z < 8 and 0.05 for z < 14 on a pipe of R = 3 (a layer of 0.3 mm: 0.075 mm first).
TEST(Envelope, LevelLayerStaysUnderTheFlowKindsThinnedLayers) {
  const TriMesh wall = synth::cylinder({.radius = 3.0, .length = 20.0, .resolution = 0.5, .jitter = 0.3});
  std::vector<volume::WallEnd> ends;
  for (const auto& end : analysis::open_ends(wall)) ends.push_back({end.loop, end.normal});
  const std::vector<double> radius(wall.points.size(), 3.0);
  std::vector<post::WallHeights> flows(2);
  for (int k = 0; k < 2; ++k) {
    flows[k].wall = wall;
    for (const Vec3& x : wall.points)
      flows[k].heights.push_back(k == 0 ? (x.z() < 8.0 ? 0.02 : 1.0) : (x.z() < 14.0 ? 0.05 : 1.0));
  }
  EXPECT_FALSE(level_first_height({}, 1.33)) << "no flow kind: no height asked";
  const auto first = [&](const volume::BoundaryLayerOptions& o) {
    const volume::BoundaryLayer layer = volume::build_boundary_layer(wall, radius, ends, o);
    std::vector<double> h;
    const int n = wall.num_points();
    for (int v = 0; v < n; ++v) h.push_back((layer.points[n + v] - wall.points[v]).norm());
    return h;
  };
  std::vector<std::vector<double>> compared;
  for (const post::WallHeights& f : flows)
    compared.push_back(first({.min_angle_deg = 0.0, .first_height = post::height_function(f)}));
  const std::vector<double> plain = first({.min_angle_deg = 0.0});
  for (const double scale : {1.1, 1.1 * 1.33, 1.1 * 1.33 * 1.33}) {
    const LevelLayers design = level_layers(4, scale);
    const std::vector<double> level = first({.layers = design.layers, .growth = design.growth, .min_angle_deg = 0.0,
                                             .first_height = level_first_height(flows, scale)});
    for (int v = 0; v < wall.num_points(); ++v) {
      for (const std::vector<double>& c : compared) EXPECT_LE(level[v], c[v] / scale * (1 + 1e-6)) << "scale " << scale;
      EXPECT_LE(level[v], plain[v] / scale * (1 + 1e-6));
      if (wall.points[v].z() < 7.0) {
        EXPECT_NEAR(level[v], 0.02 / scale, 0.02 * 0.02 / scale);
      }
    }
  }
}

// Level k's interior: the factor given, and the field's growth and core divided by the scale,
// so that factor x min(h + d ln g, max(h, core R)) over sizes h / s is the compared field over s.
TEST(Envelope, LevelInteriorIsTheFinestComparedFieldOverTheScale) {
  const volume::InteriorSizeOptions compared{.factor = 1.0, .gradation = 1.3, .core_fraction = 0.1};
  const double s = 1.7;
  const volume::InteriorSizeOptions o = level_interior(compared, 0.8, s);
  EXPECT_DOUBLE_EQ(o.factor, 0.8);
  const double h = 0.3, d = 0.9, R = 3.0;
  const auto field = [](const volume::InteriorSizeOptions& x, double hh, double dd, double rr) {
    return x.factor * std::min(hh + dd * std::log(x.gradation), std::max(hh, x.core_fraction * rr));
  };
  volume::InteriorSizeOptions finest = compared;
  finest.factor = 0.8;
  for (const double depth : {0.0, d, 3 * d, 10 * d})
    EXPECT_NEAR(field(o, h / s, depth, R), field(finest, h, depth, R) / s, 1e-12) << depth;
}

// The flow kinds' interiors (issue 52): the least of their factor x flow sizes where they have one,
// each level's under it by the scale, its core bound kept beside it.
TEST(Envelope, LevelInteriorStaysUnderTheFlowKindsInteriorsToo) {
  post::FluidSizes a, b;
  a.mesh = test::kuhn_box({2, 2, 2}, Vec3(2, 2, 2));  // [0, 2]^3, sizes 0.5
  a.sizes.assign(a.mesh.points.size(), 0.5);
  b.mesh = test::kuhn_box({2, 2, 2}, Vec3(4, 2, 2));  // [0, 4] x [0, 2]^2, sizes 0.4 + 0.1 x
  for (const Vec3& p : b.mesh.points) b.sizes.push_back(0.4 + 0.1 * p.x());
  const std::function<double(const Vec3&)> least = least_flow_interior({a, b}, {1.2, 0.9});
  EXPECT_NEAR(least(Vec3(1, 1, 1)), std::min(1.2 * 0.5, 0.9 * 0.5), 1e-12);
  EXPECT_NEAR(least(Vec3(0.2, 1, 1)), 0.9 * 0.42, 1e-12);
  EXPECT_NEAR(least(Vec3(3, 1, 1)), 0.9 * 0.7, 1e-12);  // outside the first
  EXPECT_EQ(least(Vec3(5, 1, 1)), 0.0);                 // outside both
  const volume::InteriorSizeOptions o =
      level_interior({.factor = 1.0, .gradation = 1.3, .core_fraction = 0.1}, 0.8, 1.7, least);
  EXPECT_TRUE(o.flow_keeps_core);
  EXPECT_NEAR(o.factor * o.flow(Vec3(3, 1, 1)), 0.9 * 0.7 / 1.7, 1e-12);
  EXPECT_FALSE(level_interior({}, 0.8, 1.7).flow);
}

// On the bundled bifurcation: the envelope of a uniform and a curvature mesh of 4000 triangles is no
// larger than either mesh's achieved size at any input point, and the level remeshed to it over
// 1.33 (remesh_level, as the study does: again to the calibrated sizes, and to the count) is, where
// sampled, no coarser than every compared mesh's size over 1.33 (within the remesher's band: its
// edges within [1/sqrt 2, sqrt 2] of the metric, means within 20 %), its count what its sizes
// predict, and not much finer either.
TEST(Envelope, LevelIsFinerThanEveryComparedMeshOnABifurcation) {
  TriMesh input = io::read_surface(std::string(VESSELMESH_DATA_DIR) + "/y_bifurcation.stl").mesh;
  mesh::clean(input);
  const analysis::CurvatureField curvature = analysis::curvature(input);
  const centerline::DistanceMap distance = centerline::distance_map(input, centerline::extract(input));
  remesh::RemeshOptions options;
  options.input_radius = &distance.radius;
  std::vector<TriMesh> compared;
  for (const sizing::SizeKind kind : {sizing::SizeKind::uniform, sizing::SizeKind::curvature}) {
    const sizing::SizeField field = sizing::make_size_field(input, {.kind = kind, .target_triangles = 4000},
                                                            {.curvature = &curvature, .distance = &distance});
    compared.push_back(remesh::adapt_to_count(input, field.metric, 4000, options).mesh);
  }
  const std::vector<double> envelope = envelope_sizes(input, {&compared[0], &compared[1]});
  ASSERT_EQ(envelope.size(), input.points.size());

  // A mesh's achieved size at a point: interpolated at its closest point.
  const auto size_at = [](const TriMesh& m, const std::vector<double>& sizes, const mesh::SurfaceLocator& on,
                          const Vec3& x) {
    const mesh::SurfaceLocator::Hit hit = on.closest(x);
    double sum = 0.0, weight = 0.0;
    for (int v : m.triangles[hit.triangle]) {
      const double w = 1.0 / ((m.points[v] - hit.point).norm() + 1e-9);
      sum += w * sizes[v];
      weight += w;
    }
    return sum / weight;
  };
  std::vector<std::vector<double>> achieved;
  std::vector<mesh::SurfaceLocator> on;
  for (const TriMesh& m : compared) {
    achieved.push_back(achieved_sizes(m));
    on.emplace_back(m);
  }
  // The envelope at an input point: no more than either mesh's interpolated size there (their corners'
  // sizes bound any interpolation).
  for (size_t v = 0; v < input.points.size(); ++v)
    for (size_t m = 0; m < compared.size(); ++m) {
      const Triangle& f = compared[m].triangles[on[m].closest(input.points[v]).triangle];
      const double most = std::max({achieved[m][f[0]], achieved[m][f[1]], achieved[m][f[2]]});
      ASSERT_LE(envelope[v], most * (1 + 1e-12)) << "input point " << v << ", mesh " << m;
    }
  // Where the curvature mesh is finer than the uniform one, the envelope follows it.
  int curvature_finer = 0;
  for (size_t v = 0; v < input.points.size(); ++v)
    if (size_at(compared[1], achieved[1], on[1], input.points[v]) < 0.9 * size_at(compared[0], achieved[0], on[0], input.points[v]))
      ++curvature_finer;
  EXPECT_GT(curvature_finer, 0);

  const double scale = 1.33;
  std::vector<double> target(input.points.size());
  for (size_t v = 0; v < target.size(); ++v) target[v] = envelope[v] / scale;
  struct Said : Reporter {
    mutable std::vector<std::string> lines;
    void info(std::string_view message) const override { lines.emplace_back(message); }
  } said;
  double predicted = 0.0;
  const TriMesh level = remesh_level(input, target, options, predicted, said).mesh;
  // Its count meets what its sizes predict, within the shortfall allowed and not much above it.
  EXPECT_GE(level.triangles.size(), (1.0 - kLevelCountShortfall) * predicted);
  EXPECT_LE(level.triangles.size(), 1.1 * predicted);
  // Here the calibrated surface alone fell short (the third pass refined it): else this test does
  // not see the pass.
  const auto third_pass = [](const std::string& line) {
    return line.find("short: its sizes times") != std::string::npos;
  };
  EXPECT_TRUE(std::any_of(said.lines.begin(), said.lines.end(), third_pass)) << said.lines.size() << " lines said";
  const std::vector<double> level_sizes = achieved_sizes(level);
  const mesh::SurfaceLocator on_level(level);
  int sampled = 0, coarser = 0;
  double worst = 0.0, ratios = 0.0;
  for (size_t v = 0; v < input.points.size(); v += 7, ++sampled) {
    const Vec3& x = input.points[v];
    const double finest = std::min(size_at(compared[0], achieved[0], on[0], x), size_at(compared[1], achieved[1], on[1], x));
    const double ratio = size_at(level, level_sizes, on_level, x) / (finest / scale);
    worst = std::max(worst, ratio);
    if (ratio > 1.2) ++coarser;
    ratios += std::log(ratio);
  }
  // On average the level meets its sizes or is finer, as its count asks: the mean ratio of its
  // achieved sizes (least altitudes) to the asked between 0.8 and 1.05 (0.86 measured: the count
  // pass's; the local calibration alone met them within 10 % and fell short of the count).
  const double mean_ratio = std::exp(ratios / sampled);
  EXPECT_GT(mean_ratio, 0.8);
  EXPECT_LT(mean_ratio, 1.05);
  EXPECT_GT(sampled, 100);
  // Pointwise sizes scatter with the triangles' shapes: at most 2 % of the samples over the band.
  EXPECT_LE(coarser, sampled / 50) << "worst ratio " << worst;
  EXPECT_GT(level.triangles.size(), compared[0].triangles.size() * scale * scale);
}

// The interior's factor: the compared fields go as factor x area-equivalent size; the series' factor
// makes factor x envelope the least of them. A wall of 10 x 10 cells at 1 and one of 20 x 20 at 1.5
// (half the size, 0.75 of the first's field), against an envelope of the first's sizes: 0.75; the
// envelope halved: 1.5.
TEST(Envelope, InteriorFactorMakesTheSeriesFieldTheLeastOfTheCompared) {
  const TriMesh input = test::unit_square(7), a = test::unit_square(10), b = test::unit_square(20, true);
  const std::vector<double> sizes = volume::area_equivalent_sizes(a);
  std::vector<double> envelope(input.points.size(), sizes[0]);
  EXPECT_NEAR(envelope_interior_factor(input, {&a}, {0.8}, envelope), 0.8, 1e-12);
  EXPECT_NEAR(envelope_interior_factor(input, {&a, &b}, {1.0, 1.5}, envelope), 0.75, 1e-12);
  for (double& e : envelope) e *= 0.5;
  EXPECT_NEAR(envelope_interior_factor(input, {&a, &b}, {1.0, 1.5}, envelope), 1.5, 1e-12);
}

TEST(Envelope, NeedsAComparedMesh) {
  TriMesh input;
  input.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  input.triangles = {{0, 1, 2}};
  EXPECT_THROW(envelope_sizes(input, {}), InputError);
}

}  // namespace
}  // namespace vesselmesh::study
