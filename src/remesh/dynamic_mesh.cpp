#include "remesh/dynamic_mesh.h"

#include "mesh/connectivity.h"
#include "mesh/error.h"
#include "sizing/metric.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace vesselmesh::remesh {

DynamicMesh::DynamicMesh(const SurfaceModel& model) {
  const TriMesh& in = model.input();
  for (int v = 0; v < in.num_points(); ++v) {
    const Projection p = model.project(in.points[v], model.triangle_at(v));
    add_point(in.points[v], model.metric(v), p.normal, model.kind(v), model.curve_of_point(v), model.triangle_at(v));
  }
  labelled_ = in.has_labels();
  for (int t = 0; t < in.num_triangles(); ++t) add_triangle(in.triangles[t], labelled_ ? in.labels[t] : 0);
  const analysis::Features& features = model.features();
  for (int e = 0; e < features.edges.num_edges(); ++e)
    if (features.curve_of_edge[e] >= 0) set_curve_edge(features.edges.edges[e][0], features.edges.edges[e][1], features.curve_of_edge[e]);
}

int DynamicMesh::add_point(const Vec3& p, const Sym3& m, const Vec3& n, PointKind k, int c, int input_triangle) {
  position.push_back(p);
  hint.push_back(input_triangle);
  dirty.push_back(1);
  metric.push_back(m);
  normal.push_back(n);
  kind.push_back(k);
  curve.push_back(c);
  point_alive.push_back(1);
  ball.emplace_back();
  return static_cast<int>(position.size()) - 1;
}

int DynamicMesh::add_triangle(const Triangle& f, int label) {
  const int t = static_cast<int>(triangles.size());
  triangles.push_back(f);
  labels.push_back(label);
  triangle_alive.push_back(1);
  for (int v : f) {
    ball[v].push_back(t);
    dirty[v] = 1;
  }
  return t;
}

void DynamicMesh::kill_triangle(int t) {
  triangle_alive[t] = 0;
  for (int v : triangles[t]) {
    std::erase(ball[v], t);
    dirty[v] = 1;
  }
}

void DynamicMesh::set_corner(int t, int corner, int point) {
  std::erase(ball[triangles[t][corner]], t);
  dirty[triangles[t][corner]] = 1;
  triangles[t][corner] = point;
  ball[point].push_back(t);
  for (int v : triangles[t]) dirty[v] = 1;
}

uint64_t DynamicMesh::key(int a, int b) {
  const auto [lo, hi] = std::minmax(a, b);
  return (static_cast<uint64_t>(lo) << 32) | static_cast<uint32_t>(hi);
}

int DynamicMesh::curve_of_edge(int a, int b) const {
  const auto it = curve_edges_.find(key(a, b));
  return it == curve_edges_.end() ? -1 : it->second;
}

void DynamicMesh::set_curve_edge(int a, int b, int c) {
  if (c < 0) curve_edges_.erase(key(a, b));
  else curve_edges_[key(a, b)] = c;
}

std::vector<int> DynamicMesh::triangles_of_edge(int a, int b) const {
  std::vector<int> out;
  for (int t : ball[a])
    if (mesh::corner_of(triangles[t], b) >= 0) out.push_back(t);
  return out;
}

bool DynamicMesh::connected(int a, int b) const {
  for (int t : ball[a])
    if (mesh::corner_of(triangles[t], b) >= 0) return true;
  return false;
}

std::vector<int> DynamicMesh::neighbours(int a) const {
  std::vector<int> out;
  for (int t : ball[a])
    for (int v : triangles[t])
      if (v != a) out.push_back(v);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

double DynamicMesh::edge_length(int a, int b) const {
  return sizing::edge_length(position[a], position[b], metric[a], metric[b]);
}

double DynamicMesh::quality(const Triangle& f) const {
  if (shapes_in_space) {
    const Sym3 unit{{1.0, 0.0, 0.0, 1.0, 0.0, 1.0}};
    return sizing::triangle_quality(position[f[0]], position[f[1]], position[f[2]], unit, unit, unit);
  }
  const double q = sizing::triangle_quality(position[f[0]], position[f[1]], position[f[2]], metric[f[0]],
                                            metric[f[1]], metric[f[2]]);
  if (caps_from <= 0.0) return q;
  const double largest = largest_angle(f);
  return largest <= caps_from ? q : q * std::max(0.0, (std::numbers::pi - largest) / (std::numbers::pi - caps_from));
}

// The angle opposite the longest edge, by the law of cosines (clamped: a flat triangle gives pi).
double DynamicMesh::largest_angle(const Triangle& f) const {
  const std::array<double, 3> side{(position[f[1]] - position[f[2]]).squaredNorm(),
                                   (position[f[2]] - position[f[0]]).squaredNorm(),
                                   (position[f[0]] - position[f[1]]).squaredNorm()};
  const int i = static_cast<int>(std::max_element(side.begin(), side.end()) - side.begin());
  const double a = side[(i + 1) % 3], b = side[(i + 2) % 3];
  if (!(a > 0.0 && b > 0.0)) return 0.0;
  return std::acos(std::clamp((a + b - side[i]) / (2.0 * std::sqrt(a * b)), -1.0, 1.0));
}

TriMesh DynamicMesh::to_trimesh(std::vector<Sym3>* metrics, std::vector<int>* hints) const {
  TriMesh out;
  std::vector<int> remap(position.size(), -1);
  for (size_t t = 0; t < triangles.size(); ++t) {
    if (!triangle_alive[t]) continue;
    Triangle f = triangles[t];
    for (int& v : f) {
      if (remap[v] < 0) {
        remap[v] = out.num_points();
        out.points.push_back(position[v]);
        if (metrics) metrics->push_back(metric[v]);
        if (hints) hints->push_back(hint[v]);
      }
      v = remap[v];
    }
    out.triangles.push_back(f);
    if (labelled_) out.labels.push_back(labels[t]);
  }
  return out;
}

}  // namespace vesselmesh::remesh
