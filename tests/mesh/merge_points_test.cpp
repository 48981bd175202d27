#include "mesh/merge_points.h"

#include <gtest/gtest.h>

namespace vesselmesh::mesh {
namespace {

TEST(MergePoints, IdenticalPointsMergeInOrderOfFirstAppearance) {
  std::vector<Vec3> points = {Vec3(1, 2, 3), Vec3(0, 0, 0), Vec3(1, 2, 3), Vec3(-0.0, 0, 0), Vec3(1, 2, 3.0000001)};
  const std::vector<int> remap = merge_identical_points(points);
  EXPECT_EQ(remap, (std::vector<int>{0, 1, 0, 1, 2}));  // -0.0 equals +0.0; 3.0000001 is distinct
  ASSERT_EQ(points.size(), 3u);
  EXPECT_EQ(points[2].z(), 3.0000001);
}

TEST(MergePoints, IdenticalPointSetGrowsAndKeepsIndices) {
  IdenticalPointSet set(1);
  for (int i = 0; i < 1000; ++i) EXPECT_EQ(set.insert(Vec3(i, 0, 0)), i);
  for (int i = 0; i < 1000; ++i) EXPECT_EQ(set.insert(Vec3(i, 0, 0)), i);
  EXPECT_EQ(set.points().size(), 1000u);
}

TEST(MergePoints, ClosePointsUseTheSmallerTolerance) {
  std::vector<Vec3> points = {Vec3(0, 0, 0), Vec3(1e-3, 0, 0), Vec3(1, 0, 0), Vec3(1 + 5e-4, 0, 0)};
  const std::vector<double> tolerance = {2e-3, 2e-3, 1e-3, 1e-4};
  const std::vector<int> remap = merge_close_points(points, tolerance);
  EXPECT_EQ(remap, (std::vector<int>{0, 0, 1, 2}));  // the last pair is farther than min(1e-3, 1e-4)
  EXPECT_EQ(points[0], Vec3(0, 0, 0));                // the first point keeps its position
}

TEST(MergePoints, ChainsMergeTransitively) {
  std::vector<Vec3> points = {Vec3(0, 0, 0), Vec3(0.9, 0, 0), Vec3(1.8, 0, 0), Vec3(5, 0, 0)};
  const std::vector<int> remap = merge_close_points(points, std::vector<double>(4, 1.0));
  EXPECT_EQ(remap, (std::vector<int>{0, 0, 0, 1}));
}

TEST(MergePoints, ZeroToleranceKeepsDistinctPoints) {
  std::vector<Vec3> points = {Vec3(0, 0, 0), Vec3(1e-300, 0, 0)};
  const std::vector<int> remap = merge_close_points(points, std::vector<double>(2, 0.0));
  EXPECT_EQ(points.size(), 2u);
  EXPECT_EQ(remap, (std::vector<int>{0, 1}));
}

}  // namespace
}  // namespace vesselmesh::mesh
