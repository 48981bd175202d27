#include "mesh/geometry.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace vesselmesh::mesh
