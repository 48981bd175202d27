#include "mesh/reorder.h"

#include "mesh/error.h"
#include "mesh/point_graph.h"

#include <algorithm>
#include <numeric>

namespace vesselmesh::mesh {
namespace {

}  // namespace

std::vector<int> cuthill_mckee_order(const TetMesh& mesh) {
  const PointGraph g = point_graph(mesh.num_points(), mesh.tets, mesh.prisms);
  const int n = mesh.num_points();
  std::vector<int> order;
  order.reserve(n);
  std::vector<char> placed(n, 0);
  std::vector<int> level(n, -1), touched, neighbours;
  // Breadth-first levels from `root` over the points not yet placed; returns the last level's
  // point of least degree (ties: least index) and sets `depth`.
  auto farthest = [&](int root, int& depth) {
    for (int v : touched) level[v] = -1;
    touched.assign(1, root);
    level[root] = 0;
    for (size_t k = 0; k < touched.size(); ++k) {
      const int v = touched[k];
      for (int i = g.start[v]; i < g.start[v + 1]; ++i) {
        const int w = g.next[i];
        if (placed[w] || level[w] >= 0) continue;
        level[w] = level[v] + 1;
        touched.push_back(w);
      }
    }
    depth = level[touched.back()];
    int best = touched.back();
    for (int v : touched)
      if (level[v] == depth && (g.degree(v) < g.degree(best) || (g.degree(v) == g.degree(best) && v < best))) best = v;
    return best;
  };
  std::vector<int> by_degree(n);
  std::iota(by_degree.begin(), by_degree.end(), 0);
  std::stable_sort(by_degree.begin(), by_degree.end(), [&](int a, int b) { return g.degree(a) < g.degree(b); });
  for (int seed : by_degree) {
    if (placed[seed] || g.degree(seed) == 0) continue;
    // A pseudo-peripheral root: sweep until the depth stops growing (a few sweeps).
    int root = seed, depth = 0;
    for (int sweep = 0; sweep < 8; ++sweep) {
      int next_depth = 0;
      const int far = farthest(root, next_depth);
      if (sweep > 0 && next_depth <= depth) break;
      depth = next_depth;
      root = far;
    }
    const size_t first = order.size();
    order.push_back(root);
    placed[root] = 1;
    for (size_t k = first; k < order.size(); ++k) {
      const int v = order[k];
      neighbours.clear();
      for (int i = g.start[v]; i < g.start[v + 1]; ++i)
        if (!placed[g.next[i]]) neighbours.push_back(g.next[i]);
      std::sort(neighbours.begin(), neighbours.end(), [&](int a, int b) {
        return g.degree(a) != g.degree(b) ? g.degree(a) < g.degree(b) : a < b;
      });
      for (int w : neighbours) {
        placed[w] = 1;
        order.push_back(w);
      }
    }
  }
  std::reverse(order.begin(), order.end());
  for (int v = 0; v < n; ++v)
    if (!placed[v]) order.push_back(v);  // points of no cell keep their place at the end
  return order;
}

namespace {

// Cells renumbered and sorted by their sorted new corners; `data` lists follow them.
template <typename Cell>
void renumber_cells(std::vector<Cell>& cells, const std::vector<int>& new_of, std::vector<std::vector<int>*> data) {
  std::vector<Cell> sorted_corners(cells.size());
  for (size_t c = 0; c < cells.size(); ++c) {
    for (int& v : cells[c]) v = new_of[v];
    sorted_corners[c] = cells[c];
    std::sort(sorted_corners[c].begin(), sorted_corners[c].end());
  }
  std::vector<int> by(cells.size());
  std::iota(by.begin(), by.end(), 0);
  std::stable_sort(by.begin(), by.end(), [&](int a, int b) { return sorted_corners[a] < sorted_corners[b]; });
  std::vector<Cell> out(cells.size());
  for (size_t c = 0; c < by.size(); ++c) out[c] = cells[by[c]];
  cells = std::move(out);
  for (std::vector<int>* list : data) {
    if (list->size() != by.size()) continue;  // absent (empty) data
    std::vector<int> moved(list->size());
    for (size_t c = 0; c < by.size(); ++c) moved[c] = (*list)[by[c]];
    *list = std::move(moved);
  }
}

}  // namespace

TetMesh renumbered(const TetMesh& mesh, const std::vector<int>& order) {
  const int n = mesh.num_points();
  VM_CHECK(static_cast<int>(order.size()) == n, "renumbered: one entry per point");
  std::vector<int> new_of(n, -1);
  for (int k = 0; k < n; ++k) {
    VM_CHECK(order[k] >= 0 && order[k] < n && new_of[order[k]] < 0, "renumbered: the order is not a permutation");
    new_of[order[k]] = k;
  }
  TetMesh out = mesh;
  for (int k = 0; k < n; ++k) out.points[k] = mesh.points[order[k]];
  renumber_cells(out.tets, new_of, {&out.tet_layer, &out.tet_column});
  renumber_cells(out.prisms, new_of, {&out.prism_layer, &out.prism_column});
  for (Triangle& f : out.boundary)
    for (int& v : f) v = new_of[v];
  return out;
}

int point_bandwidth(const TetMesh& mesh) {
  int width = 0;
  auto cells = [&](const auto& list) {
    for (const auto& c : list) {
      const auto [lo, hi] = std::minmax_element(c.begin(), c.end());
      width = std::max(width, *hi - *lo);
    }
  };
  cells(mesh.tets);
  cells(mesh.prisms);
  return width;
}

}  // namespace vesselmesh::mesh
