#include "mesh/geometry.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace vesselmesh::mesh {
namespace {

// The closest point by brute force: the best of a fine barycentric grid (error below the grid step).
Vec3 sampled_closest(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  constexpr int n = 400;
  Vec3 best = a;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j) {
      const Vec3 q = a + (double(i) / n) * (b - a) + (double(j) / n) * (c - a);
      if ((q - p).squaredNorm() < (best - p).squaredNorm()) best = q;
    }
  return best;
}

TEST(Geometry, ClosestPointOnTriangleInEveryRegion) {
  const Vec3 a(0, 0, 0), b(2, 0, 0), c(0.5, 1.5, 0);
  // Inside (straight below), beyond each corner, beyond each edge.
  EXPECT_TRUE(closest_point_on_triangle(Vec3(0.6, 0.5, 3.0), a, b, c).isApprox(Vec3(0.6, 0.5, 0.0)));
  EXPECT_TRUE(closest_point_on_triangle(Vec3(-1, -1, 1), a, b, c).isApprox(a));
  EXPECT_TRUE(closest_point_on_triangle(Vec3(3, -1, -1), a, b, c).isApprox(b));
  EXPECT_TRUE(closest_point_on_triangle(Vec3(0.5, 3, 0), a, b, c).isApprox(c));
  EXPECT_TRUE(closest_point_on_triangle(Vec3(1, -2, 0.5), a, b, c).isApprox(Vec3(1, 0, 0)));
  // Random points against brute force.
  std::mt19937 random(7);
  std::uniform_real_distribution<double> u(-2.0, 3.0);
  for (int k = 0; k < 200; ++k) {
    const Vec3 p(u(random), u(random), u(random));
    const Vec3 q = closest_point_on_triangle(p, a, b, c);
    EXPECT_NEAR((q - p).norm(), (sampled_closest(p, a, b, c) - p).norm(), 1e-2) << p.transpose();
    EXPECT_LE((q - p).norm(), (sampled_closest(p, a, b, c) - p).norm() + 1e-12) << p.transpose();
  }
  // A degenerate triangle gives a point, not NaN.
  EXPECT_TRUE(closest_point_on_triangle(Vec3(1, 1, 1), a, a, a).allFinite());
}

TEST(Geometry, BarycentricCoordinatesAreClampedToTheTriangle) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  const auto l = barycentric(Vec3(0.25, 0.5, 0.3), a, b, c);  // above the plane: its projection
  EXPECT_NEAR(l[0], 0.25, 1e-12);
  EXPECT_NEAR(l[1], 0.25, 1e-12);
  EXPECT_NEAR(l[2], 0.5, 1e-12);
  const auto out = barycentric(Vec3(2, 2, 0), a, b, c);
  EXPECT_GE(std::min({out[0], out[1], out[2]}), 0.0);
  EXPECT_NEAR(out[0] + out[1] + out[2], 1.0, 1e-12);
}

}  // namespace
}  // namespace vesselmesh::mesh
