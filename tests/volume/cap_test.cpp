#include "volume/cap.h"

#include "mesh/error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>

namespace vesselmesh::volume {
namespace {

std::vector<Vec3> circle(int m, double r, const Vec3& centre = Vec3::Zero()) {
  std::vector<Vec3> loop;
  for (int i = 0; i < m; ++i) {
    const double a = 2 * std::numbers::pi * i / m;
    loop.push_back(centre + Vec3(r * std::cos(a), r * std::sin(a), 0));
  }
  return loop;
}

Vec3 corner(const std::vector<Vec3>& loop, const Cap& cap, int c) {
  const int m = static_cast<int>(loop.size());
  return c < m ? loop[c] : cap.points[c - m];
}

TEST(Cap, DiskIsAQualityTriangulationFacingTheNormal) {
  const auto loop = circle(60, 2.0, Vec3(1, 2, 3));
  const Cap cap = triangulate_cap(loop, Vec3(0, 0, 1));
  EXPECT_GT(cap.points.size(), 20u) << "not a fan";
  double area = 0.0, least_angle = 180.0;
  std::map<std::pair<int, int>, int> directed;
  for (const Triangle& f : cap.triangles) {
    const Vec3 a = corner(loop, cap, f[0]), b = corner(loop, cap, f[1]), c = corner(loop, cap, f[2]);
    const Vec3 normal = (b - a).cross(c - a);
    EXPECT_GT(normal.z(), 0.0);
    EXPECT_NEAR(normal.x(), 0.0, 1e-12);
    area += 0.5 * normal.norm();
    const Vec3 p[3] = {a, b, c};
    for (int i = 0; i < 3; ++i) {
      const Vec3 u = p[(i + 1) % 3] - p[i], w = p[(i + 2) % 3] - p[i];
      least_angle = std::min(least_angle, std::acos(u.normalized().dot(w.normalized())) * 180 / std::numbers::pi);
      ++directed[{f[i], f[(i + 1) % 3]}];
    }
  }
  // The polygon's area, 60 sin(2 pi / 60) r^2 / 2.
  EXPECT_NEAR(area, 0.5 * 60 * std::sin(2 * std::numbers::pi / 60) * 4.0, 1e-9);
  EXPECT_GE(least_angle, 20.0);
  // Each loop edge belongs to exactly one triangle, never split; inner edges twice, opposite.
  for (int i = 0; i < 60; ++i) {
    const int j = (i + 1) % 60;
    EXPECT_EQ(directed[std::pair(i, j)] + directed[std::pair(j, i)], 1) << "loop edge " << i;
  }
  for (const auto& [edge, count] : directed) {
    if (edge.first < 60 && edge.second < 60 && (std::abs(edge.first - edge.second) == 1 ||
                                                  std::abs(edge.first - edge.second) == 59))
      continue;
    EXPECT_EQ(count, 1);
    EXPECT_EQ(directed.count(std::pair(edge.second, edge.first)), 1u);
  }
  for (const Vec3& p : cap.points) {
    EXPECT_NEAR(p.z(), 3.0, 1e-12);
    EXPECT_LT((p - Vec3(1, 2, 3)).norm(), 2.0);
  }
}

TEST(Cap, SizedLikeItsLoop) {
  // A finer loop gives a finer cap: triangles scale with the square of the edge count.
  const Cap coarse = triangulate_cap(circle(30, 2.0), Vec3(0, 0, -1));
  const Cap fine = triangulate_cap(circle(90, 2.0), Vec3(0, 0, -1));
  const double ratio = static_cast<double>(fine.triangles.size()) / coarse.triangles.size();
  EXPECT_GT(ratio, 5.0);
  EXPECT_LT(ratio, 13.0);
}

TEST(Cap, ASelfCrossingLoopIsAnError) {
  // A figure eight.
  std::vector<Vec3> loop;
  for (int i = 0; i < 40; ++i) {
    const double t = 2 * std::numbers::pi * i / 40;
    loop.emplace_back(std::sin(t), std::sin(t) * std::cos(t), 0.0);
  }
  EXPECT_THROW(triangulate_cap(loop, Vec3(0, 0, 1)), InputError);
  EXPECT_THROW(triangulate_cap({Vec3(0, 0, 0), Vec3(1, 0, 0)}, Vec3(0, 0, 1)), InputError);
}

}  // namespace
}  // namespace vesselmesh::volume
