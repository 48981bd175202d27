#include "volume/boundary_layer.h"

#include "analysis/open_ends.h"
#include "mesh/connectivity.h"
#include "mesh/error.h"
#include "synth/shapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <numbers>

namespace vesselmesh::volume {
namespace {

struct Pipe {
  TriMesh wall;
  std::vector<WallEnd> ends;
};

Pipe pipe(double radius = 3.0, double length = 20.0, double resolution = 0.5) {
  Pipe p;
  p.wall = synth::cylinder({.radius = radius, .length = length, .resolution = resolution, .jitter = 0.3});
  for (const auto& end : analysis::open_ends(p.wall)) p.ends.push_back({end.loop, end.normal});
  return p;
}

double axis_distance(const Vec3& p) { return std::hypot(p.x(), p.y()); }

// The least dihedral angle (degrees) over the tetrahedra the layer's prisms split into.
double least_layer_angle(const BoundaryLayer& layer) {
  double least = 180.0;
  for (const Prism& prism : layer.prisms)
    for (const Tet& t : mesh::split_prism(prism))
      least = std::min(least, mesh::least_dihedral_angle(layer.points[t[0]], layer.points[t[1]], layer.points[t[2]],
                                                         layer.points[t[3]]) *
                                  180.0 / std::numbers::pi);
  return least;
}

TEST(LayerFractions, UniformAndGeometric) {
  const auto uniform = layer_fractions(4, 1.0);
  ASSERT_EQ(uniform.size(), 5u);
  for (int k = 0; k <= 4; ++k) EXPECT_NEAR(uniform[k], k / 4.0, 1e-15);
  // Heights 1, 2, 4: fractions 0, 1/7, 3/7, 1.
  const auto geometric = layer_fractions(3, 2.0);
  EXPECT_NEAR(geometric[1], 1.0 / 7.0, 1e-15);
  EXPECT_NEAR(geometric[2], 3.0 / 7.0, 1e-15);
  EXPECT_DOUBLE_EQ(geometric[3], 1.0);
}

TEST(BoundaryLayer, PipeLayersAreConcentricAndEndFlush) {
  // R = 3, thickness 10 % of the radius: the inner surface at r = 2.7, levels at 3 - 0.075 k.
  const Pipe p = pipe();
  const std::vector<double> radius(p.wall.points.size(), 3.0);
  const BoundaryLayer layer = build_boundary_layer(p.wall, radius, p.ends, {.min_angle_deg = 0.0});
  const int n = p.wall.num_points();
  ASSERT_EQ(layer.levels, 5);
  ASSERT_EQ(layer.points.size(), 5u * n);
  EXPECT_EQ(layer.prisms.size(), 4u * p.wall.triangles.size());
  EXPECT_EQ(layer.shrunk_vertices, 0);
  double worst = 0.0;
  for (int k = 0; k < 5; ++k)
    for (int v = 0; v < n; ++v)
      worst = std::max(worst, std::abs(axis_distance(layer.points[k * n + v]) - (3.0 - 0.075 * k)));
  // Smoothed Max normals of a jittered pipe are radial to within about a degree.
  EXPECT_LT(worst, 0.3 * 0.02) << "levels off their radius by " << worst << " mm";
  // The ends' loops stay in their planes z = 0 and z = 20.
  ASSERT_EQ(layer.inner_loops.size(), 2u);
  for (const auto& loop : layer.inner_loops) {
    const double z = layer.points[loop.front()].z();
    EXPECT_TRUE(std::abs(z) < 1e-9 || std::abs(z - 20.0) < 1e-9);
    for (int v : loop) EXPECT_NEAR(layer.points[v].z(), z, 1e-9);
  }
  // Each strip: 2 triangles per loop edge and layer.
  for (size_t e = 0; e < 2; ++e) EXPECT_EQ(layer.end_strips[e].size(), 2u * 4u * p.ends[e].loop.size());
}

TEST(BoundaryLayer, TheFirstHeightAskedRaisesTheGrowthGradedAlongTheWall) {
  // R = 3, 4 uniform layers of 0.3 mm (0.075 mm first): asked 0.03 mm for z < 8, nothing beyond. The
  // layers there grow from 0.03 mm over the same thickness (growth g with (g - 1) / (g^4 - 1) = 0.1);
  // beyond, the height asked rises at the shrink's slope (0.2 a mm along the wall) to the 0.075 mm.
  const Pipe p = pipe();
  const std::vector<double> radius(p.wall.points.size(), 3.0);
  BoundaryLayerOptions o{.min_angle_deg = 0.0};
  o.first_height = [](const Vec3& x) { return x.z() < 8.0 ? 0.03 : 0.0; };
  const BoundaryLayer layer = build_boundary_layer(p.wall, radius, p.ends, o);
  const int n = p.wall.num_points();
  int changed = 0;
  for (int v = 0; v < n; ++v) {
    const double z = p.wall.points[v].z(), first = (layer.points[n + v] - layer.points[v]).norm();
    const double inner = (layer.points[4 * n + v] - layer.points[v]).norm();
    EXPECT_NEAR(inner, 0.3, 0.3 * 0.01) << "the thickness kept at z = " << z;
    // Graded along the wall's edges: paths at least z - 8 long, at most an edge (0.5, jittered) longer.
    const double asked = 0.03 + 0.2 * std::max(0.0, z - 8.0);
    EXPECT_LE(first, std::min(0.075, asked + 0.2 * 0.8) * 1.01) << "at z = " << z;
    EXPECT_GE(first, std::min(0.075, asked) * 0.99) << "at z = " << z;
    for (int k = 1; k < 4; ++k)  // growing from the wall
      EXPECT_GE((layer.points[(k + 1) * n + v] - layer.points[k * n + v]).norm(),
                (layer.points[k * n + v] - layer.points[(k - 1) * n + v]).norm() * (1 - 1e-6));
    changed += first < 0.075 * (1 - 1e-6);
  }
  EXPECT_EQ(layer.capped_vertices, changed);
  EXPECT_GT(changed, n / 3);
  // Below what growth 2 gives (0.3 / 15 = 0.02 mm), the thickness is cut: 0.01 mm x 15 = 0.15 mm.
  o.first_height = [](const Vec3& x) { return x.z() < 8.0 ? 0.01 : 0.0; };
  const BoundaryLayer cut = build_boundary_layer(p.wall, radius, p.ends, o);
  for (int v = 0; v < n; ++v)
    if (p.wall.points[v].z() < 7.0) {
      EXPECT_NEAR((cut.points[n + v] - cut.points[v]).norm(), 0.01, 0.01 * 0.01);
      EXPECT_NEAR(cut.thickness[v], 0.15, 0.15 * 0.01);
    }
  // A height asked above the first layer's changes nothing.
  o.first_height = [](const Vec3&) { return 1.0; };
  EXPECT_EQ(build_boundary_layer(p.wall, radius, p.ends, o).capped_vertices, 0);
}

TEST(BoundaryLayer, GrowthMakesLayersThickerInward) {
  const Pipe p = pipe();
  const std::vector<double> radius(p.wall.points.size(), 3.0);
  const BoundaryLayer layer = build_boundary_layer(p.wall, radius, p.ends, {.layers = 3, .growth = 2.0, .min_angle_deg = 0.0});
  const int n = p.wall.num_points();
  const int v = p.wall.triangles[100][0];
  const double h1 = (layer.points[n + v] - layer.points[v]).norm();
  const double h2 = (layer.points[2 * n + v] - layer.points[n + v]).norm();
  const double h3 = (layer.points[3 * n + v] - layer.points[2 * n + v]).norm();
  EXPECT_NEAR(h2 / h1, 2.0, 1e-9);
  EXPECT_NEAR(h3 / h2, 2.0, 1e-9);
  EXPECT_NEAR(h1 + h2 + h3, 0.3, 1e-9);
}

TEST(BoundaryLayer, ThickensWhereTheWallIsCoarseSoItsTetrahedraKeepTheAngle) {
  // Wall edges of 1.2 mm against a first layer of 0.075 mm (R = 3, 10 %, 4 layers): its
  // tetrahedra would have about atan(0.075 / 1.04) = 4.1 degrees. As asked, the thickness is
  // exact and the angle is missed; with the 5-degree goal the layer grows where it must, by
  // about tan(5 deg) / tan(4.1 deg), stays under half the radius and meets the angle.
  const Pipe p = pipe(3.0, 20.0, 1.2);
  const std::vector<double> radius(p.wall.points.size(), 3.0);
  const BoundaryLayer asked = build_boundary_layer(p.wall, radius, p.ends, {.min_angle_deg = 0.0});
  EXPECT_LT(least_layer_angle(asked), 5.0);
  EXPECT_EQ(asked.thickened_vertices, 0);
  for (double t : asked.thickness) EXPECT_NEAR(t, 0.3, 1e-12);

  const BoundaryLayer layer = build_boundary_layer(p.wall, radius, p.ends, {});
  const double least = least_layer_angle(layer);
  EXPECT_GE(least, 5.0);
  EXPECT_NEAR(layer.least_angle, least, 1e-9);
  EXPECT_EQ(layer.under_angle_prisms, 0);
  EXPECT_EQ(layer.shrunk_vertices, 0);
  EXPECT_GT(layer.thickened_vertices, 0);
  EXPECT_GT(layer.most_fraction, 1.1);
  EXPECT_LT(layer.most_fraction, 2.5);
  for (double t : layer.thickness) {
    EXPECT_GE(t, 0.3 - 1e-12);
    EXPECT_LE(t, 1.5 + 1e-12);
  }
  EXPECT_EQ(layer.prisms.size(), 4u * p.wall.triangles.size());
}

TEST(BoundaryLayer, HeldAtHalfTheRadiusItCountsThePrismsUnderTheAngle) {
  // 50 layers of 0.006 mm on edges of 0.5 mm would need 1.9 mm of layer for 5 degrees: more
  // than half the 3 mm radius. The layer stops there and says how many prisms stay under.
  const Pipe p = pipe();
  const std::vector<double> radius(p.wall.points.size(), 3.0);
  const BoundaryLayer layer = build_boundary_layer(p.wall, radius, p.ends, {.layers = 50});
  for (double t : layer.thickness) EXPECT_LE(t, 1.5 * (1.0 + 1e-12));
  EXPECT_GT(layer.under_angle_prisms, 0);
  const double least = least_layer_angle(layer);
  EXPECT_LT(least, 5.0);
  EXPECT_NEAR(layer.least_angle, least, 1e-9);
}

TEST(BoundaryLayer, ShrinksSmoothlyWhereColumnsWouldCross) {
  // A radius three times too large asks for a layer 4.5 mm thick in a 3 mm pipe: the columns
  // meet at the axis, so the layer must shrink everywhere, stay valid and say so.
  const Pipe p = pipe();
  const std::vector<double> radius(p.wall.points.size(), 9.0);
  const BoundaryLayer layer = build_boundary_layer(p.wall, radius, p.ends, {.thickness_ratio = 0.5});
  const int n = p.wall.num_points();
  EXPECT_EQ(layer.shrunk_vertices, n);
  EXPECT_LT(layer.least_fraction, 3.0 / 4.5);
  for (int v = 0; v < n; ++v) {
    EXPECT_LT(layer.thickness[v], 3.0);
    EXPECT_GT(axis_distance(layer.points[4 * n + v]), 0.0);
  }
  for (const Prism& prism : layer.prisms)
    for (const Tet& t : mesh::split_prism(prism))
      EXPECT_GT(mesh::tet_volume6(layer.points[t[0]], layer.points[t[1]], layer.points[t[2]], layer.points[t[3]]), 0.0);
}

TEST(BoundaryLayer, ALayerThatCannotBeBuiltIsAnErrorNamingThePlace) {
  const Pipe p = pipe();
  const std::vector<double> radius(p.wall.points.size(), 9.0);
  try {
    build_boundary_layer(p.wall, radius, p.ends, {.thickness_ratio = 0.5, .min_thickness_fraction = 0.9});
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot be built near wall point"), std::string::npos) << e.what();
  }
}

TEST(BoundaryLayer, RejectsBadOptions) {
  const Pipe p = pipe();
  const std::vector<double> radius(p.wall.points.size(), 3.0);
  EXPECT_THROW(build_boundary_layer(p.wall, radius, p.ends, {.layers = 0}), OptionError);
  EXPECT_THROW(build_boundary_layer(p.wall, radius, p.ends, {.thickness_ratio = 0.8}), OptionError);
  EXPECT_THROW(build_boundary_layer(p.wall, radius, p.ends, {.growth = 0.0}), OptionError);
  EXPECT_THROW(build_boundary_layer(p.wall, radius, p.ends, {.min_angle_deg = -1.0}), OptionError);
  EXPECT_THROW(build_boundary_layer(p.wall, radius, p.ends, {.split_angle_deg = 31.0}), OptionError);
  std::vector<double> missing = radius;
  missing[7] = 0.0;
  EXPECT_THROW(build_boundary_layer(p.wall, missing, p.ends, {}), InputError);
}

TEST(SplitLongEdges, HalvesEachLongEdgeOnceKeepingTheShapeTheEndsAndTheOrientation) {
  Pipe p = pipe(3.0, 20.0, 0.8);
  const int points = p.wall.num_points(), triangles = p.wall.num_triangles();
  auto area = [](const TriMesh& m) {
    double a = 0.0;
    for (const Triangle& f : m.triangles)
      a += 0.5 * (m.points[f[1]] - m.points[f[0]]).cross(m.points[f[2]] - m.points[f[0]]).norm();
    return a;
  };
  const double area_before = area(p.wall);
  const auto loops_before = mesh::boundary_loops(p.wall, mesh::build_edge_map(p.wall));
  std::vector<double> radius(points);
  for (int v = 0; v < points; ++v) radius[v] = 2.0 + p.wall.points[v].z() / 20.0;
  std::vector<int> all(triangles);
  for (int t = 0; t < triangles; ++t) all[t] = t;
  const int split = split_long_edges(p.wall, radius, all);
  // Every triangle asked, each split at most once: a triangle and its neighbour share a split.
  EXPECT_GT(split, triangles / 4);
  EXPECT_LE(2 * split, triangles);
  EXPECT_EQ(p.wall.num_points(), points + split);
  EXPECT_EQ(p.wall.num_triangles(), triangles + 2 * split);
  ASSERT_EQ(static_cast<int>(radius.size()), p.wall.num_points());
  for (int v = points; v < p.wall.num_points(); ++v)  // linear in z: the mean is exact at the midpoint
    EXPECT_NEAR(radius[v], 2.0 + p.wall.points[v].z() / 20.0, 1e-12);
  EXPECT_NEAR(area(p.wall), area_before, 1e-9 * area_before);
  // The ends' loops as they were; every directed edge once (oriented, manifold).
  const mesh::EdgeMap edges = mesh::build_edge_map(p.wall);
  EXPECT_EQ(mesh::boundary_loops(p.wall, edges), loops_before);
  std::set<std::pair<int, int>> directed;
  for (const Triangle& f : p.wall.triangles)
    for (int i = 0; i < 3; ++i) EXPECT_TRUE(directed.insert({f[i], f[(i + 1) % 3]}).second);
  for (int e = 0; e < edges.num_edges(); ++e) EXPECT_LE(edges.valence(e), 2);
  // Nothing asked, nothing split; the same list in another order, the same mesh.
  Pipe q = pipe(3.0, 20.0, 0.8), r = pipe(3.0, 20.0, 0.8);
  std::vector<double> rq(points, 3.0), rr(points, 3.0);
  EXPECT_EQ(split_long_edges(q.wall, rq, {}), 0);
  EXPECT_EQ(q.wall.num_triangles(), triangles);
  const std::vector<int> reversed(all.rbegin(), all.rend());
  split_long_edges(q.wall, rq, all);
  split_long_edges(r.wall, rr, reversed);
  EXPECT_EQ(q.wall.triangles, r.wall.triangles);
}

}  // namespace
}  // namespace vesselmesh::volume
