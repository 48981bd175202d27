#include "mesh/connectivity.h"

#include "mesh/error.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <numeric>

namespace vesselmesh::mesh {

EdgeMap build_edge_map(const TriMesh& mesh) {
  // Each edge (a, b), a < b, is found from its smaller end: for every point a in order, the
  // half-edges of its triangles that lead to a larger point, sorted by (b, half-edge). Small
  // per-point sorts instead of one global sort; the result is lexicographic all the same.
  const int nt = mesh.num_triangles();
  const VertexTriangles around = build_vertex_triangles(mesh);
  EdgeMap map;
  map.triangle_edges.resize(nt);
  map.edge_triangles.reserve(static_cast<size_t>(nt) * 3);
  map.edges.reserve(static_cast<size_t>(nt) * 3 / 2 + 16);
  map.triangle_offsets.reserve(static_cast<size_t>(nt) * 3 / 2 + 17);
  map.triangle_offsets.push_back(0);
  std::vector<std::pair<int, int>> leaving;  // (other end b, half-edge 3t + i)
  for (int a = 0; a < mesh.num_points(); ++a) {
    leaving.clear();
    for (int t : around.of(a)) {
      const Triangle& f = mesh.triangles[t];
      for (int i = 0; i < 3; ++i) {
        const int u = f[i], v = f[(i + 1) % 3];
        if (std::min(u, v) == a && std::max(u, v) != a) leaving.emplace_back(std::max(u, v), 3 * t + i);
      }
    }
    std::sort(leaving.begin(), leaving.end());
    for (size_t k = 0; k < leaving.size();) {
      const int b = leaving[k].first;
      const int e = map.num_edges();
      map.edges.push_back({a, b});
      for (; k < leaving.size() && leaving[k].first == b; ++k) {
        const int h = leaving[k].second;
        map.triangle_edges[h / 3][h % 3] = e;
        // A triangle can use an edge twice only if it is degenerate; list it once.
        if (map.edge_triangles.size() == static_cast<size_t>(map.triangle_offsets.back()) ||
            map.edge_triangles.back() != h / 3)
          map.edge_triangles.push_back(h / 3);
      }
      map.triangle_offsets.push_back(static_cast<int>(map.edge_triangles.size()));
    }
  }
  // Half-edges from a point to itself (a triangle with a repeated corner) form no edge.
  for (int t = 0; t < nt; ++t)
    for (int i = 0; i < 3; ++i)
      if (mesh.triangles[t][i] == mesh.triangles[t][(i + 1) % 3]) map.triangle_edges[t][i] = -1;
  return map;
}

namespace {

VertexTriangles incidence(const TriMesh& mesh, bool corners) {
  VertexTriangles vt;
  vt.offsets.assign(mesh.points.size() + 1, 0);
  for (const Triangle& f : mesh.triangles)
    for (int v : f) ++vt.offsets[v + 1];
  std::partial_sum(vt.offsets.begin(), vt.offsets.end(), vt.offsets.begin());
  vt.triangles.resize(vt.offsets.back());
  std::vector<int> fill(vt.offsets.begin(), vt.offsets.end() - 1);
  for (int t = 0; t < mesh.num_triangles(); ++t)
    for (int c = 0; c < 3; ++c) vt.triangles[fill[mesh.triangles[t][c]]++] = corners ? 3 * t + c : t;
  return vt;
}

}  // namespace

VertexTriangles build_vertex_triangles(const TriMesh& mesh) { return incidence(mesh, false); }

VertexTriangles build_vertex_corners(const TriMesh& mesh) { return incidence(mesh, true); }

void gather_ring(const TriMesh& mesh, const VertexTriangles& corners, int v, size_t min_ring, std::vector<int>& stamp,
                 std::vector<int>& ring, int max_rings, int min_rings) {
  const int mark = v + 1;
  auto add = [&](int w) {
    if (stamp[w] != mark) stamp[w] = mark, ring.push_back(w);
  };
  ring.clear();
  stamp[v] = mark;
  for (int corner : corners.of(v)) {
    const Triangle& f = mesh.triangles[corner / 3];
    add(f[(corner % 3 + 1) % 3]);
    add(f[(corner % 3 + 2) % 3]);
  }
  size_t first = 0;
  for (int rings = 1; rings < max_rings && (rings < min_rings || ring.size() < min_ring); ++rings) {
    const size_t last = ring.size();
    for (size_t i = first; i < last; ++i)
      for (int corner : corners.of(ring[i]))
        for (int w : mesh.triangles[corner / 3]) add(w);
    first = last;
  }
}

std::vector<std::vector<int>> boundary_loops(const TriMesh& mesh, const EdgeMap& edges) {
  // next[a] = b for every boundary half-edge a -> b.
  std::vector<int> next(mesh.points.size(), -1);
  for (int e = 0; e < edges.num_edges(); ++e) {
    if (!edges.is_boundary(e)) continue;
    const Triangle& f = mesh.triangles[edges.triangles_of(e)[0]];
    const int ca = corner_of(f, edges.edges[e][0]);
    const bool forward = f[(ca + 1) % 3] == edges.edges[e][1];
    const int a = forward ? edges.edges[e][0] : edges.edges[e][1];
    const int b = forward ? edges.edges[e][1] : edges.edges[e][0];
    if (next[a] != -1) {
      const Vec3& p = mesh.points[a];
      throw InputError(fmt::format(
          "the boundary is not a simple loop at vertex {} ({:.6g}, {:.6g}, {:.6g}): two boundary "
          "edges leave it (a non-manifold vertex or inconsistent orientation); clean the mesh first",
          a, p.x(), p.y(), p.z()));
    }
    next[a] = b;
  }
  std::vector<std::vector<int>> loops;
  std::vector<char> visited(mesh.points.size(), 0);
  for (int start = 0; start < mesh.num_points(); ++start) {
    if (next[start] == -1 || visited[start]) continue;
    std::vector<int> loop;
    for (int v = start; !visited[v]; v = next[v]) {
      if (next[v] == -1) {
        const Vec3& p = mesh.points[v];
        throw InputError(fmt::format(
            "the boundary ends at vertex {} ({:.6g}, {:.6g}, {:.6g}) without closing a loop "
            "(inconsistent orientation); clean the mesh first",
            v, p.x(), p.y(), p.z()));
      }
      visited[v] = 1;
      loop.push_back(v);
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

std::vector<int> triangle_components(const TriMesh& mesh, const EdgeMap& edges,
                                     int* num_components) {
  const int nt = mesh.num_triangles();
  std::vector<int> component(nt, -1);
  std::vector<int> stack;
  int count = 0;
  for (int seed = 0; seed < nt; ++seed) {
    if (component[seed] != -1) continue;
    component[seed] = count;
    stack.push_back(seed);
    while (!stack.empty()) {
      const int t = stack.back();
      stack.pop_back();
      for (int e : edges.triangle_edges[t])
        for (int u : e < 0 ? std::span<const int>() : edges.triangles_of(e))
          if (component[u] == -1) {
            component[u] = count;
            stack.push_back(u);
          }
    }
    ++count;
  }
  if (num_components) *num_components = count;
  return component;
}

}  // namespace vesselmesh::mesh
