// Pairs of triangles of a surface that intersect each other other than along the edge or
// vertex they share. Exact predicates (CGAL Polygon_mesh_processing::self_intersections).
#pragma once

#include "mesh/trimesh.h"

#include <utility>
#include <vector>

namespace vesselmesh::mesh {

// Input: a manifold, consistently oriented surface (after mesh::clean).
// Output: pairs (s, t), s < t, sorted. Empty when the surface does not intersect itself.
std::vector<std::pair<int, int>> self_intersecting_pairs(const TriMesh& mesh);

}  // namespace vesselmesh::mesh
