#include "centerline/extract.h"

#include "centerline/voronoi.h"
#include "mesh/error.h"
#include "mesh/geometry.h"
#include "mesh/locator.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <queue>
#include <set>

namespace vesselmesh::centerline {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// An end made from a point the user gave.
analysis::OpenEnd end_at(const Vec3& p) {
  analysis::OpenEnd end;
  end.center = p;
  return end;
}

// Shortest paths from `source` with edge cost length x mean(1/R). Ties broken by index.
void dijkstra(const VoronoiGraph& g, int source, std::vector<double>& cost, std::vector<int>& previous) {
  cost.assign(g.size(), kInfinity);
  previous.assign(g.size(), -1);
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  cost[source] = 0.0;
  queue.emplace(0.0, source);
  while (!queue.empty()) {
    const auto [c, v] = queue.top();
    queue.pop();
    if (c > cost[v]) continue;
    for (int k = g.offsets[v]; k < g.offsets[v + 1]; ++k) {
      const int w = g.neighbours[k];
      const double step = (g.centers[w] - g.centers[v]).norm() * 0.5 * (1.0 / g.radius[v] + 1.0 / g.radius[w]);
      if (c + step < cost[w]) {
        cost[w] = c + step;
        previous[w] = v;
        queue.emplace(cost[w], w);
      }
    }
  }
}

int nearest_node(const VoronoiGraph& g, const Vec3& p) {
  int best = -1;
  double best_d = kInfinity;
  for (int v = 0; v < g.size(); ++v) {
    const double d = (g.centers[v] - p).squaredNorm();
    if (d < best_d) best_d = d, best = v;
  }
  return best;
}

std::vector<Vec3> resample(const std::vector<Vec3>& points, double step) {
  std::vector<double> s(points.size(), 0.0);
  for (size_t i = 1; i < points.size(); ++i) s[i] = s[i - 1] + (points[i] - points[i - 1]).norm();
  const double length = s.back();
  const int n = std::max(1, static_cast<int>(std::lround(length / step)));
  std::vector<Vec3> out;
  out.reserve(n + 1);
  size_t k = 0;
  for (int i = 0; i <= n; ++i) {
    const double target = length * i / n;
    while (k + 2 < points.size() && s[k + 1] < target) ++k;
    const double span = s[k + 1] - s[k];
    const double t = span > 0.0 ? std::clamp((target - s[k]) / span, 0.0, 1.0) : 0.0;
    out.push_back(points[k] + t * (points[k + 1] - points[k]));
  }
  out.front() = points.front();
  out.back() = points.back();
  return out;
}

void smooth(std::vector<Vec3>& points, int iterations, double factor) {
  std::vector<Vec3> next = points;
  for (int it = 0; it < iterations; ++it) {
    for (size_t i = 1; i + 1 < points.size(); ++i)
      next[i] = points[i] + factor * (0.5 * (points[i - 1] + points[i + 1]) - points[i]);
    points.swap(next);
  }
}

// The union of the node paths (-1: the inlet's end, -2 - k: outlet k's end) as a tree of
// branches that part where a node has more than one successor.
class BranchBuilder {
 public:
  explicit BranchBuilder(const std::vector<std::vector<int>>& paths) {
    for (size_t k = 0; k < paths.size(); ++k)
      for (size_t i = 0; i < paths[k].size(); ++i) {
        if (i + 1 < paths[k].size()) next_[paths[k][i]].insert(paths[k][i + 1]);
        first_outlet_.emplace(paths[k][i], static_cast<int>(k));  // kept: the smallest k
      }
  }

  // Node sequences of the branches, parents before children; parent index per branch.
  void build(std::vector<std::vector<int>>& branches, std::vector<int>& parents) {
    std::vector<std::pair<int, int>> stack = {{-1, -1}};  // (first node, parent branch)
    while (!stack.empty()) {
      const auto [start, parent] = stack.back();
      stack.pop_back();
      std::vector<int> nodes = {start};
      if (parent >= 0) nodes.insert(nodes.begin(), branches[parent].back());
      int v = start;
      while (next_.count(v) && next_.at(v).size() == 1) {
        v = *next_.at(v).begin();
        nodes.push_back(v);
      }
      const int id = static_cast<int>(branches.size());
      branches.push_back(nodes);
      parents.push_back(parent);
      if (!next_.count(v)) continue;
      // Children in the order of the first outlet each leads to, pushed in reverse.
      std::vector<int> children(next_.at(v).begin(), next_.at(v).end());
      std::sort(children.begin(), children.end(), [&](int a, int b) { return first_outlet_.at(a) < first_outlet_.at(b); });
      for (auto it = children.rbegin(); it != children.rend(); ++it) stack.emplace_back(*it, id);
    }
  }

 private:
  std::map<int, std::set<int>> next_;
  std::map<int, int> first_outlet_;  // the first outlet whose path passes the node
};

// The surface without its flat caps: the radius of the lumen is measured to its wall (a cap is
// a cut, not a wall, and would make the radius vanish at the ends).
TriMesh wall_of(const TriMesh& surface, const std::vector<analysis::OpenEnd>& ends) {
  std::vector<char> cap(surface.triangles.size(), 0);
  for (const auto& e : ends)
    for (int t : e.cap_triangles) cap[t] = 1;
  TriMesh wall{surface.points, {}, {}};
  for (int t = 0; t < surface.num_triangles(); ++t)
    if (!cap[t]) wall.triangles.push_back(surface.triangles[t]);
  return wall;
}

double default_step(const std::vector<analysis::OpenEnd>& ends, const VoronoiGraph& g) {
  double smallest = kInfinity;
  for (const auto& e : ends)
    if (e.radius > 0.0) smallest = std::min(smallest, e.radius);
  if (std::isfinite(smallest)) return 0.1 * smallest;
  std::vector<double> r = g.radius;
  std::nth_element(r.begin(), r.begin() + static_cast<std::ptrdiff_t>(r.size() / 2), r.end());
  return 0.1 * r[r.size() / 2];
}

}  // namespace

double Polyline::length() const {
  double l = 0.0;
  for (size_t i = 1; i < points.size(); ++i) l += (points[i] - points[i - 1]).norm();
  return l;
}

Centerlines extract(const TriMesh& surface, const CenterlineOptions& options, const Reporter& reporter) {
  Centerlines out;
  const std::vector<analysis::OpenEnd> found = analysis::open_ends(surface);
  if (found.empty() && (!options.source || options.targets.empty()))
    throw InputError("the surface has no open or capped end (a closed segmentation with rounded ends?): centerlines "
                     "need an inlet and outlets; cut the ends open, or give --source-point and --target-point");
  // End points.
  if (options.source) {
    out.ends.push_back(end_at(*options.source));
    out.inlet = 0;
  }
  if (!options.targets.empty()) {
    if (!options.source) {
      const int inlet = options.inlet.value_or(0);
      if (inlet < 0 || inlet >= static_cast<int>(found.size()))
        throw OptionError(fmt::format("inlet {} does not exist: the surface has {} end(s)", inlet, found.size()));
      out.ends.push_back(found[inlet]);
    }
    for (const Vec3& t : options.targets) out.ends.push_back(end_at(t));
  } else if (options.source) {
    out.ends.insert(out.ends.end(), found.begin(), found.end());
  } else {
    out.ends = found;
    out.inlet = options.inlet.value_or(0);
    if (out.inlet < 0 || out.inlet >= static_cast<int>(found.size()))
      throw OptionError(fmt::format("inlet {} does not exist: the surface has {} end(s)", out.inlet, found.size()));
  }
  for (int k = 0; k < static_cast<int>(out.ends.size()); ++k)
    if (k != out.inlet) out.outlets.push_back(k);
  if (out.outlets.empty())
    throw InputError(fmt::format("the surface has {} open or capped end(s); centerlines need an inlet and at least one "
                                 "outlet: give --source-point and --target-point",
                                 found.size()));
  if (options.resampling_step < 0.0 || !std::isfinite(options.resampling_step))
    throw OptionError(fmt::format("the resampling step must be positive, got {}", options.resampling_step));

  // The lumen, closed at its open ends for the inside test, and its Voronoi diagram.
  const mesh::InsideTest inside(analysis::fan_capped(surface, found));
  const VoronoiGraph graph = internal_voronoi(surface, inside, reporter);
  if (graph.size() == 0) throw InputError("no Voronoi vertex lies inside the surface: is it a closed lumen?");
  reporter.progress("tracing centerlines", 0.0);

  std::vector<int> node_of_end(out.ends.size());
  for (size_t k = 0; k < out.ends.size(); ++k) node_of_end[k] = nearest_node(graph, out.ends[k].center);
  std::vector<double> cost;
  std::vector<int> previous;
  dijkstra(graph, node_of_end[out.inlet], cost, previous);
  std::vector<std::vector<int>> node_paths;
  for (size_t k = 0; k < out.outlets.size(); ++k) {
    const int end = out.outlets[k];
    int v = node_of_end[end];
    if (!std::isfinite(cost[v]))
      throw InputError(fmt::format("end {} at {} cannot be reached from the inlet through the lumen (the Voronoi "
                                   "diagram is cut there: a pinched or self-touching surface?)",
                                   end, mesh::format_point(out.ends[end].center)));
    std::vector<int> path = {-2 - static_cast<int>(k)};
    for (; v != -1; v = previous[v]) path.push_back(v);
    path.push_back(-1);
    std::reverse(path.begin(), path.end());
    node_paths.push_back(std::move(path));
  }

  // Branches: resampled, smoothed, radius from the surface.
  std::vector<std::vector<int>> branch_nodes;
  std::vector<int> parents;
  BranchBuilder(node_paths).build(branch_nodes, parents);
  const double step = options.resampling_step > 0.0 ? options.resampling_step : default_step(out.ends, graph);
  const mesh::SurfaceLocator locator(wall_of(surface, found));
  auto position = [&](int node) {
    if (node == -1) return out.ends[out.inlet].center;
    if (node <= -2) return out.ends[out.outlets[-2 - node]].center;
    return graph.centers[node];
  };
  for (size_t b = 0; b < branch_nodes.size(); ++b) {
    Branch branch;
    branch.id = static_cast<int>(b);
    branch.parent = parents[b];
    std::vector<Vec3> raw;
    for (int node : branch_nodes[b]) raw.push_back(position(node));
    if (raw.size() < 2) raw.push_back(raw.back());
    branch.points = resample(raw, step);
    smooth(branch.points, options.smoothing_iterations, options.smoothing_factor);
    for (const Vec3& p : branch.points) branch.radius.push_back(locator.closest(p).distance);
    const int last = branch_nodes[b].back();
    branch.end = last <= -2 ? out.outlets[-2 - last] : -1;
    if (branch.parent >= 0) out.branches[branch.parent].children.push_back(branch.id);
    if (branch.end < 0) out.bifurcations.push_back(branch.points.back());
    out.branches.push_back(std::move(branch));
  }
  // Paths: the branches from the inlet to each outlet, joined.
  for (int end : out.outlets) {
    int b = -1;
    for (const Branch& branch : out.branches)
      if (branch.end == end) b = branch.id;
    std::vector<int> chain;
    for (; b >= 0; b = out.branches[b].parent) chain.push_back(b);
    Polyline path;
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
      const Branch& branch = out.branches[*it];
      const size_t skip = path.points.empty() ? 0 : 1;  // the junction point is shared
      path.points.insert(path.points.end(), branch.points.begin() + static_cast<std::ptrdiff_t>(skip), branch.points.end());
      path.radius.insert(path.radius.end(), branch.radius.begin() + static_cast<std::ptrdiff_t>(skip), branch.radius.end());
    }
    out.paths.push_back(std::move(path));
  }
  reporter.progress("tracing centerlines", 1.0);
  return out;
}

}  // namespace vesselmesh::centerline
