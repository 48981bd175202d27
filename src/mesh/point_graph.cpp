#include "mesh/point_graph.h"

#include "mesh/error.h"

#include <algorithm>

namespace vesselmesh::mesh {
namespace {

// Calls add(a, b) for every ordered pair of distinct corners of every cell.
template <typename Add>
void each_pair(const std::vector<Tet>& tets, const std::vector<Prism>& prisms, const Add& add) {
  const auto cell = [&](const auto& corners) {
    for (int a : corners)
      for (int b : corners)
        if (a != b) add(a, b);
  };
  for (const Tet& t : tets) cell(t);
  for (const Prism& p : prisms) cell(p);
}

// Rows sorted and their repeats removed, in place.
void compact(PointGraph& g) {
  const int n = static_cast<int>(g.start.size()) - 1;
  int kept = 0;
  for (int v = 0; v < n; ++v) {
    const auto begin = g.next.begin() + g.start[v], end = g.next.begin() + g.start[v + 1];
    std::sort(begin, end);
    const auto last = std::unique(begin, end);
    g.start[v] = kept;
    kept = static_cast<int>(std::move(begin, last, g.next.begin() + kept) - g.next.begin());
  }
  g.start[n] = kept;
  g.next.resize(static_cast<size_t>(kept));
  g.next.shrink_to_fit();
}

}  // namespace

PointGraph point_graph(int points, const std::vector<Tet>& tets, const std::vector<Prism>& prisms) {
  PointGraph g;
  g.start.assign(static_cast<size_t>(points) + 1, 0);
  each_pair(tets, prisms, [&](int a, int b) {
    VM_CHECK(a >= 0 && a < points && b >= 0 && b < points, "point_graph: a cell's point is out of range");
    ++g.start[a + 1];
  });
  for (int v = 0; v < points; ++v) g.start[v + 1] += g.start[v];
  g.next.resize(static_cast<size_t>(g.start[points]));
  std::vector<int> fill(g.start.begin(), g.start.end() - 1);
  each_pair(tets, prisms, [&](int a, int b) { g.next[fill[a]++] = b; });
  compact(g);
  return g;
}

PointGraph renumbered(const PointGraph& graph, const std::vector<int>& order) {
  const int n = static_cast<int>(order.size());
  VM_CHECK(static_cast<int>(graph.start.size()) == n + 1, "renumbered: an order over the graph's points");
  std::vector<int> position(n);
  for (int k = 0; k < n; ++k) position[order[k]] = k;
  PointGraph g;
  g.start.assign(static_cast<size_t>(n) + 1, 0);
  g.next.reserve(graph.next.size());
  for (int k = 0; k < n; ++k) {
    const int v = order[k];
    for (int i = graph.start[v]; i < graph.start[v + 1]; ++i) g.next.push_back(position[graph.next[i]]);
    std::sort(g.next.begin() + g.start[k], g.next.end());
    g.start[k + 1] = static_cast<int>(g.next.size());
  }
  return g;
}

}  // namespace vesselmesh::mesh
