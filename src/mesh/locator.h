// Geometric queries against a fixed surface or set of segments, backed by CGAL AABB trees:
// the closest point on a triangle surface, inside/outside of a closed surface, and the
// closest point on a set of segments (a centerline). Build once, query many times; queries
// are const and may run concurrently once built.
#pragma once

#include "mesh/trimesh.h"

#include <array>
#include <memory>
#include <vector>

namespace vesselmesh::mesh {

class SurfaceLocator {
 public:
  struct Hit {
    Vec3 point = Vec3::Zero();  // closest point on the surface
    int triangle = -1;          // the triangle it lies on
    double distance = 0.0;
  };
  explicit SurfaceLocator(const TriMesh& mesh);
  ~SurfaceLocator();
  SurfaceLocator(SurfaceLocator&&) noexcept;
  SurfaceLocator& operator=(SurfaceLocator&&) noexcept;

  Hit closest(const Vec3& p) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Inside test for a closed surface (boundary loops must have been closed, e.g. by caps).
class InsideTest {
 public:
  explicit InsideTest(const TriMesh& closed_mesh);
  ~InsideTest();
  // True for points strictly inside; points on the surface count as outside.
  bool inside(const Vec3& p) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

class SegmentLocator {
 public:
  struct Hit {
    Vec3 point = Vec3::Zero();
    int segment = -1;
    double t = 0.0;  // position along the segment, 0 at its first end, 1 at its second
    double distance = 0.0;
  };
  explicit SegmentLocator(const std::vector<std::array<Vec3, 2>>& segments);
  ~SegmentLocator();
  Hit closest(const Vec3& p) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vesselmesh::mesh
