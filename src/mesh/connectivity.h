// Connectivity built on demand from a TriMesh: edges with the triangles that use them,
// vertex-to-triangle incidence, boundary loops and connected components.
// Everything here is a snapshot: rebuild it after the mesh changes.
#pragma once

#include "mesh/trimesh.h"

#include <span>
#include <vector>

namespace vesselmesh::mesh {

struct EdgeMap {
  // Undirected edges (a, b), a < b, in lexicographic order.
  std::vector<std::array<int, 2>> edges;
  // Triangles using edge e: edge_triangles[triangle_offsets[e] .. triangle_offsets[e+1]), ascending.
  std::vector<int> triangle_offsets;
  std::vector<int> edge_triangles;
  // triangle_edges[t][i] is the edge between corners i and (i+1)%3 of triangle t, or -1 where
  // the two corners are the same point (a degenerate triangle; mesh::clean removes those).
  std::vector<std::array<int, 3>> triangle_edges;

  int num_edges() const { return static_cast<int>(edges.size()); }
  int valence(int e) const { return triangle_offsets[e + 1] - triangle_offsets[e]; }
  std::span<const int> triangles_of(int e) const {
    return {edge_triangles.data() + triangle_offsets[e], static_cast<size_t>(valence(e))};
  }
  bool is_boundary(int e) const { return valence(e) == 1; }
};

// Linear time: edges are gathered per point from vertex-triangle incidence.
EdgeMap build_edge_map(const TriMesh& mesh);

struct VertexTriangles {
  std::vector<int> offsets;    // size num_points + 1
  std::vector<int> triangles;  // ascending per vertex
  std::span<const int> of(int v) const {
    return {triangles.data() + offsets[v], static_cast<size_t>(offsets[v + 1] - offsets[v])};
  }
};

VertexTriangles build_vertex_triangles(const TriMesh& mesh);

// The same listing corners instead of triangles: 3 t + c where mesh.triangles[t][c] == v, so
// a point's loop over its triangles also knows its place in each.
VertexTriangles build_vertex_corners(const TriMesh& mesh);

// Neighbours of v (v itself left out): its 1-ring (each incident triangle's other two corners),
// grown ring by ring to `min_rings` rings, and on while smaller than min_ring, `max_rings` at most. `corners` from
// build_vertex_corners. `stamp` (one per point, owned by the calling thread) marks the points
// taken: `stamp[w] == v + 1`, so membership costs O(1) however large the ring.
void gather_ring(const TriMesh& mesh, const VertexTriangles& corners, int v, size_t min_ring, std::vector<int>& stamp,
                 std::vector<int>& ring, int max_rings = 2, int min_rings = 1);

// Boundary loops of a manifold, consistently oriented surface: each loop lists its vertices
// in the direction of the triangles' own edges (a -> b where a triangle has the edge a -> b).
// Loops are ordered by their smallest vertex id and start at it. Throws InputError naming
// the vertex where the boundary is not a simple loop (non-manifold or inconsistent input).
std::vector<std::vector<int>> boundary_loops(const TriMesh& mesh, const EdgeMap& edges);

// Connected components through shared edges. Returns the component id of every triangle;
// ids are numbered in the order of each component's lowest triangle index.
std::vector<int> triangle_components(const TriMesh& mesh, const EdgeMap& edges,
                                     int* num_components = nullptr);

// Position of corner `v` in triangle `f` (0..2), or -1.
inline int corner_of(const Triangle& f, int v) {
  return f[0] == v ? 0 : f[1] == v ? 1 : f[2] == v ? 2 : -1;
}

}  // namespace vesselmesh::mesh
