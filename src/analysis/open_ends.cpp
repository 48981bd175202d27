#include "analysis/open_ends.h"

#include "mesh/connectivity.h"
#include "mesh/geometry.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <unordered_map>

namespace vesselmesh::analysis {
namespace {

using mesh::build_edge_map;
using mesh::boundary_loops;
using mesh::EdgeMap;
using mesh::triangle_area_vector;
using mesh::triangle_centroid;

double loop_length(const TriMesh& mesh, const std::vector<int>& loop) {
  double length = 0.0;
  for (size_t i = 0; i < loop.size(); ++i)
    length += (mesh.points[loop[(i + 1) % loop.size()]] - mesh.points[loop[i]]).norm();
  return length;
}

OpenEnd end_of_loop(const TriMesh& mesh, std::vector<int> loop) {
  OpenEnd end;
  Vec3 mean = Vec3::Zero();
  for (int v : loop) mean += mesh.points[v];
  mean /= static_cast<double>(loop.size());
  Vec3 vector_area = Vec3::Zero();
  for (size_t i = 0; i < loop.size(); ++i)
    vector_area += 0.5 * (mesh.points[loop[i]] - mean).cross(mesh.points[loop[(i + 1) % loop.size()]] - mean);
  end.area = vector_area.norm();
  // The closing surface runs against the wall's edges, so its outward normal is reversed.
  end.normal = end.area > 0.0 ? Vec3(-vector_area / end.area) : Vec3::Zero();
  const Vec3 axis = end.area > 0.0 ? Vec3(vector_area / end.area) : Vec3::Zero();
  double weight = 0.0;
  Vec3 centre = Vec3::Zero();
  for (size_t i = 0; i < loop.size(); ++i) {
    const Vec3& a = mesh.points[loop[i]];
    const Vec3& b = mesh.points[loop[(i + 1) % loop.size()]];
    const double w = 0.5 * (a - mean).cross(b - mean).dot(axis);
    centre += w * (mean + a + b) / 3.0;
    weight += w;
  }
  end.center = std::abs(weight) > 0.0 ? Vec3(centre / weight) : mean;
  end.radius = std::sqrt(end.area / std::numbers::pi);
  end.perimeter = loop_length(mesh, loop);
  end.loop = std::move(loop);
  return end;
}

// Triangles grouped into patches that meet only at creases (or at the boundary).
std::vector<int> smooth_patches(const TriMesh& mesh, const EdgeMap& edges, double crease_cos,
                                const std::vector<Vec3>& normals, int* count) {
  std::vector<int> patch(mesh.triangles.size(), -1);
  std::vector<int> stack;
  int n = 0;
  for (int seed = 0; seed < mesh.num_triangles(); ++seed) {
    if (patch[seed] != -1) continue;
    patch[seed] = n;
    stack.assign(1, seed);
    while (!stack.empty()) {
      const int t = stack.back();
      stack.pop_back();
      for (int e : edges.triangle_edges[t]) {
        if (edges.valence(e) != 2) continue;
        const auto ts = edges.triangles_of(e);
        const int u = ts[0] == t ? ts[1] : ts[0];
        if (patch[u] == -1 && normals[t].dot(normals[u]) >= crease_cos) {
          patch[u] = n;
          stack.push_back(u);
        }
      }
    }
    ++n;
  }
  *count = n;
  return patch;
}

// The cap's border as one loop in the wall's direction, or empty when it is not one loop or
// not bordered by a crease all round.
std::vector<int> cap_border(const TriMesh& mesh, const EdgeMap& edges, const std::vector<int>& patch,
                            int p, const std::vector<int>& triangles) {
  std::unordered_map<int, int> next;  // wall direction: b -> a for each cap half-edge a -> b
  for (int t : triangles) {
    const Triangle& f = mesh.triangles[t];
    for (int i = 0; i < 3; ++i) {
      const int e = edges.triangle_edges[t][i];
      if (edges.valence(e) != 2) return {};  // touches an open boundary: not a cap
      const auto ts = edges.triangles_of(e);
      const int u = ts[0] == t ? ts[1] : ts[0];
      if (patch[u] == p) continue;
      if (!next.emplace(f[(i + 1) % 3], f[i]).second) return {};  // pinched border
    }
  }
  if (next.size() < 3) return {};
  std::vector<int> loop;
  int start = next.begin()->first;
  for (const auto& [a, b] : next) start = std::min(start, a);
  for (int v = start;;) {
    loop.push_back(v);
    const auto it = next.find(v);
    if (it == next.end()) return {};
    v = it->second;
    if (v == start) break;
    if (loop.size() > next.size()) return {};
  }
  return loop.size() == next.size() ? loop : std::vector<int>{};
}

std::vector<OpenEnd> find_caps(const TriMesh& mesh, const EdgeMap& edges, const OpenEndsOptions& options) {
  const int nt = mesh.num_triangles();
  std::vector<Vec3> area_vectors(nt), normals(nt);
  double total_area = 0.0;
  for (int t = 0; t < nt; ++t) {
    area_vectors[t] = 0.5 * triangle_area_vector(mesh, t);
    const double a = area_vectors[t].norm();
    normals[t] = a > 0.0 ? Vec3(area_vectors[t] / a) : Vec3::Zero();
    total_area += a;
  }
  int count = 0;
  const double crease_cos = std::cos(options.cap_crease_angle_deg * std::numbers::pi / 180.0);
  const std::vector<int> patch = smooth_patches(mesh, edges, crease_cos, normals, &count);
  if (count < 2) return {};
  std::vector<std::vector<int>> members(count);
  for (int t = 0; t < nt; ++t) members[patch[t]].push_back(t);

  std::vector<OpenEnd> caps;
  for (int p = 0; p < count; ++p) {
    const std::vector<int>& tris = members[p];
    if (static_cast<int>(tris.size()) < options.cap_min_triangles) continue;
    Vec3 sum = Vec3::Zero(), centre = Vec3::Zero();
    double area = 0.0;
    for (int t : tris) {
      sum += area_vectors[t];
      area += area_vectors[t].norm();
      centre += area_vectors[t].norm() * triangle_centroid(mesh, t);
    }
    if (area <= 0.0 || area > 0.5 * total_area || sum.norm() <= 0.0) continue;
    centre /= area;
    const Vec3 normal = sum.normalized();
    const double diameter = 2.0 * std::sqrt(area / std::numbers::pi);
    double off_plane = 0.0;
    for (int t : tris)
      for (int v : mesh.triangles[t]) off_plane = std::max(off_plane, std::abs((mesh.points[v] - centre).dot(normal)));
    if (off_plane > options.cap_flatness * diameter) continue;
    std::vector<int> loop = cap_border(mesh, edges, patch, p, tris);
    if (loop.empty()) continue;
    OpenEnd cap;
    cap.capped = true;
    cap.center = centre;
    cap.normal = normal;
    cap.area = area;
    cap.radius = std::sqrt(area / std::numbers::pi);
    cap.perimeter = loop_length(mesh, loop);
    cap.loop = std::move(loop);
    cap.cap_triangles = tris;
    if (mesh.has_labels()) {
      const int label = mesh.labels[tris.front()];
      const bool uniform = std::all_of(tris.begin(), tris.end(), [&](int t) { return mesh.labels[t] == label; });
      cap.label = uniform ? label : -1;
    }
    caps.push_back(std::move(cap));
  }
  return caps;
}

}  // namespace

std::vector<OpenEnd> open_ends(const TriMesh& mesh, const OpenEndsOptions& options) {
  const EdgeMap edges = build_edge_map(mesh);
  std::vector<OpenEnd> ends;
  for (std::vector<int>& loop : boundary_loops(mesh, edges)) ends.push_back(end_of_loop(mesh, std::move(loop)));
  if (options.detect_caps)
    for (OpenEnd& cap : find_caps(mesh, edges, options)) ends.push_back(std::move(cap));
  std::stable_sort(ends.begin(), ends.end(), [](const OpenEnd& a, const OpenEnd& b) { return a.area > b.area; });
  return ends;
}

TriMesh fan_capped(const TriMesh& mesh, const std::vector<OpenEnd>& ends) {
  TriMesh closed{mesh.points, mesh.triangles, {}};
  for (const OpenEnd& end : ends) {
    if (end.capped) continue;
    const int centre = closed.num_points();
    closed.points.push_back(end.center);
    for (size_t i = 0; i < end.loop.size(); ++i)  // against the wall's edge a -> b
      closed.triangles.push_back({centre, end.loop[(i + 1) % end.loop.size()], end.loop[i]});
  }
  return closed;
}

std::vector<std::string> default_end_names(int ends, int inlet) {
  std::vector<std::string> names;
  int outlet = 0;
  for (int e = 0; e < ends; ++e) names.push_back(e == inlet ? "inlet" : "outlet_" + std::to_string(++outlet));
  return names;
}

}  // namespace vesselmesh::analysis
