// The cap of an open end: a planar quality triangulation of its closed loop, sized like the
// loop's edges, with no point added on the loop (so it meets the wall or the layer exactly).
// Constrained Delaunay refinement (CGAL Mesh_2: angles >= 20.7 degrees away from the loop,
// edges up to 1.2 x the loop's mean edge; the loop's edges are never split) and Lloyd
// smoothing of the added points. Not a fan.
#pragma once

#include "mesh/trimesh.h"

#include <vector>

namespace vesselmesh::volume {

struct Cap {
  std::vector<Vec3> points;  // the points added inside, in the loop's mean plane
  // Corner c < m is loop point c, corner c >= m is points[c - m] (m = loop size). Oriented so
  // that the right-hand normal is `normal`.
  std::vector<Triangle> triangles;
};

// `loop`: the loop's points in order; `normal`: the side the cap faces. InputError when the
// loop, seen along the normal, crosses or touches itself.
Cap triangulate_cap(const std::vector<Vec3>& loop, const Vec3& normal);

}  // namespace vesselmesh::volume
