#include "analysis/mixed_areas.h"

#include "synth/shapes.h"
#include "mesh/geometry.h"

#include <gtest/gtest.h>

#include <numeric>

namespace vesselmesh::analysis {
namespace {

std::array<double, 3> areas_of(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 e[3] = {c - b, a - c, b - a};
  return triangle_corner_areas(e);
}

TEST(MixedAreas, EquilateralTriangleSplitsInThirds) {
  const auto a = areas_of(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, std::sqrt(3.0) / 2, 0));
  const double area = std::sqrt(3.0) / 4;
  for (double x : a) EXPECT_NEAR(x, area / 3, 1e-15);
}

TEST(MixedAreas, RightTriangleGivesTheVoronoiRegions) {
  // Right angle at corner 0 (not obtuse): the hypotenuse's midpoint is the circumcentre; the
  // right-angle corner gets half, the others a quarter each.
  const auto a = areas_of(Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 2, 0));
  EXPECT_NEAR(a[0], 1.0, 1e-15);
  EXPECT_NEAR(a[1], 0.5, 1e-15);
  EXPECT_NEAR(a[2], 0.5, 1e-15);
}

TEST(MixedAreas, ObtuseTriangleGivesHalfToTheObtuseCorner) {
  const auto a = areas_of(Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(2, 0.5, 0));  // obtuse at corner 2
  EXPECT_NEAR(a[2], 0.5, 1e-15);
  EXPECT_NEAR(a[0], 0.25, 1e-15);
  EXPECT_NEAR(a[1], 0.25, 1e-15);
}

TEST(MixedAreas, PointAreasAddUpToTheSurface) {
  const TriMesh m = synth::sphere({.radius = 3, .resolution = 0.3, .jitter = 0.4});
  const auto corners = corner_areas(m);
  for (int t = 0; t < m.num_triangles(); ++t)
    EXPECT_NEAR(corners[t][0] + corners[t][1] + corners[t][2], mesh::triangle_area(m, t), 1e-12);
  const std::vector<double> points = point_areas(m, corners);
  EXPECT_NEAR(std::accumulate(points.begin(), points.end(), 0.0), mesh::surface_area(m), 1e-9);
  for (double a : points) EXPECT_GT(a, 0.0);
}

TEST(MixedAreas, DegenerateTriangleHasNoArea) {
  const auto a = areas_of(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0));
  for (double x : a) EXPECT_EQ(x, 0.0);
}

}  // namespace
}  // namespace vesselmesh::analysis
