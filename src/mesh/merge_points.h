// Merging coincident and near-coincident points.
//
// Both functions keep the first point (lowest index) of every group, at its own position,
// number the kept points in their original order, and return `remap`: old index -> new index.
// Deterministic: the result does not depend on hash order or thread count.
#pragma once

#include "mesh/trimesh.h"

#include <span>
#include <vector>

namespace vesselmesh::mesh {

// Points with bit-identical coordinates (+0.0 and -0.0 are the same). Linear time.
std::vector<int> merge_identical_points(std::vector<Vec3>& points);

// The same, one point at a time (readers that stream corners): insert() returns the index
// of the point among the distinct points inserted so far.
class IdenticalPointSet {
 public:
  explicit IdenticalPointSet(size_t expected_points = 0);
  int insert(const Vec3& p);
  const std::vector<Vec3>& points() const { return points_; }
  std::vector<Vec3> release() { return std::move(points_); }

 private:
  void grow();
  std::vector<Vec3> points_;
  std::vector<int> table_;  // open addressing, -1 = empty
  size_t mask_ = 0;
};

// Points closer than a tolerance: i and j merge when |p_i - p_j| <= min(tol_i, tol_j).
// Merging is transitive (a chain of close points becomes one point).
std::vector<int> merge_close_points(std::vector<Vec3>& points, std::span<const double> tolerance);

// Applies a point remap to triangle corners.
void remap_triangles(std::vector<Triangle>& triangles, const std::vector<int>& remap);

}  // namespace vesselmesh::mesh
