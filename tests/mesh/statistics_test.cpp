#include "mesh/statistics.h"

#include "synth/shapes.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace vesselmesh::mesh {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(Statistics, SphereIsClosedWithGenusZero) {
  const TriMesh m = synth::sphere({.radius = 4.0, .resolution = 0.4});
  const Statistics s = statistics(m);
  EXPECT_TRUE(s.closed);
  EXPECT_EQ(s.euler_characteristic, 2);
  EXPECT_EQ(s.genus, 0);
  EXPECT_EQ(s.boundary_loops, 0);
  // Inscribed polyhedron: area and volume a little below the sphere's, within 1 %.
  EXPECT_NEAR(s.area, 4 * kPi * 16, 0.01 * 4 * kPi * 16);
  EXPECT_LT(s.area, 4 * kPi * 16);
  EXPECT_NEAR(s.volume, 4.0 / 3.0 * kPi * 64, 0.01 * 4.0 / 3.0 * kPi * 64);
  EXPECT_NEAR(s.box_max.x(), 4.0, 0.05);
  EXPECT_NEAR(s.box_min.z(), -4.0, 0.05);
}

TEST(Statistics, TorusHasGenusOne) {
  const Statistics s = statistics(synth::torus({.major_radius = 10, .minor_radius = 3, .resolution = 0.8}));
  EXPECT_EQ(s.euler_characteristic, 0);
  EXPECT_EQ(s.genus, 1);
  EXPECT_NEAR(s.area, 4 * kPi * kPi * 30, 0.01 * 4 * kPi * kPi * 30);
}

TEST(Statistics, OpenPipeHasTwoLoopsAndItsEdgeLengths) {
  const TriMesh m = synth::cylinder({.radius = 3, .length = 20, .resolution = 0.5, .random_diagonals = false});
  const Statistics s = statistics(m);
  EXPECT_FALSE(s.closed);
  EXPECT_EQ(s.boundary_loops, 2);
  EXPECT_EQ(s.genus, 0);
  EXPECT_NEAR(s.area, 2 * kPi * 3 * 20, 0.01 * 2 * kPi * 3 * 20);
  EXPECT_LE(s.edge_length.max, 0.5 * std::sqrt(2.0) * 1.01);  // diagonals of 0.5 x 0.43 cells
  EXPECT_GT(s.edge_length.min, 0.3);
  EXPECT_GT(s.min_angle.min, 30.0);
  EXPECT_EQ(s.sliver_triangles, 0);
}

TEST(Statistics, AnglesOfARightTriangle) {
  TriMesh m;
  m.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  m.triangles = {{0, 1, 2}};
  const Statistics s = statistics(m);
  EXPECT_NEAR(s.min_angle.min, 45.0, 1e-9);
  EXPECT_NEAR(s.max_angle, 90.0, 1e-9);
  EXPECT_NEAR(s.edge_length.max, std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(s.area, 0.5, 1e-12);
}

}  // namespace
}  // namespace vesselmesh::mesh
