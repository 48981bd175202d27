#include "sizing/gradation.h"

#include "mesh/connectivity.h"
#include "mesh/error.h"
#include "sizing/metric.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <functional>
#include <queue>
#include <utility>

namespace vesselmesh::sizing {
namespace {

constexpr int kMaxPasses = 200;

// Passes over the edges, in edge order, until nothing changes; after the first pass only the
// edges of points that changed in the pass before are visited (an edge between two points
// that did not change cannot change either). `relax(from, to)` updates `to` from `from` along
// their edge and returns true if it changed.
template <typename Relax>
int sweep(const TriMesh& mesh, Relax relax) {
  const mesh::EdgeMap edges = mesh::build_edge_map(mesh);
  std::vector<char> active(mesh.points.size(), 1), next(mesh.points.size(), 0);
  int pass = 0;
  for (bool changed = true; changed && pass < kMaxPasses; ++pass) {
    changed = false;
    std::fill(next.begin(), next.end(), 0);
    for (int e = 0; e < edges.num_edges(); ++e) {
      const auto [a, b] = edges.edges[e];
      if (!active[a] && !active[b]) continue;
      if (relax(a, b)) next[b] = 1, changed = true;
      if (relax(b, a)) next[a] = 1, changed = true;
    }
    active.swap(next);
  }
  return pass;
}

}  // namespace

int grade_sizes(const TriMesh& mesh, std::vector<double>& sizes, double growth) {
  VM_CHECK(sizes.size() == mesh.points.size(), "one size per point");
  if (!(growth > 1.0)) return 0;
  const double slope = std::log(growth);
  return sweep(mesh, [&](int from, int to) {
    const double limit = sizes[from] + slope * (mesh.points[to] - mesh.points[from]).norm();
    if (sizes[to] <= limit) return false;
    sizes[to] = limit;
    return true;
  });
}

int grade_metrics(const TriMesh& mesh, std::vector<Sym3>& metrics, double growth) {
  VM_CHECK(metrics.size() == mesh.points.size(), "one metric per point");
  if (!(growth > 1.0)) return 0;
  const double slope = std::log(growth);
  return sweep(mesh, [&](int from, int to) {
    const Vec3 e = mesh.points[to] - mesh.points[from];
    const Sym3 spread = scale_sizes(metrics[from], 1.0 + metric_length(metrics[from], e) * slope);
    // Intersect only when the spread metric is finer in some direction (beyond round-off).
    const Eigen::Matrix3d difference = spread.matrix() - metrics[to].matrix();
    if (Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(difference, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff() <=
        1e-6 * metrics[to].matrix().norm())
      return false;
    metrics[to] = intersect(metrics[to], spread);
    return true;
  });
}

int grade_sizes(const std::vector<Vec3>& points, const mesh::PointGraph& graph, std::vector<double>& sizes,
                double growth) {
  VM_CHECK(sizes.size() == points.size() && graph.start.size() == points.size() + 1,
           "grade_sizes: one size and one graph row per point");
  if (!(growth > 1.0)) return 0;
  const double slope = std::log(growth);
  using Entry = std::pair<double, int>;  // (size, point): the least first, then the least index
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  for (int v = 0; v < static_cast<int>(sizes.size()); ++v) queue.emplace(sizes[v], v);
  std::vector<char> settled(sizes.size(), 0), lowered(sizes.size(), 0);
  while (!queue.empty()) {
    const auto [size, v] = queue.top();
    queue.pop();
    if (settled[v] || size > sizes[v]) continue;
    settled[v] = 1;
    for (int k = graph.start[v]; k < graph.start[v + 1]; ++k) {
      const int q = graph.next[k];
      const double limit = size + slope * (points[q] - points[v]).norm();
      if (settled[q] || !(limit < sizes[q])) continue;
      sizes[q] = limit;
      lowered[q] = 1;
      queue.emplace(limit, q);
    }
  }
  return static_cast<int>(std::count(lowered.begin(), lowered.end(), 1));
}

}  // namespace vesselmesh::sizing
