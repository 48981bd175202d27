#include "analysis/features.h"

#include "mesh/disjoint_sets.h"
#include "mesh/error.h"
#include "mesh/geometry.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace vesselmesh::analysis {
namespace {

// Crease candidates: interior edges whose two triangles' normals are further apart than the
// feature angle. Then the noise filter: candidates are grouped through shared points, and
// groups of fewer than `min_crease_edges` are dropped.
std::vector<char> find_creases(const TriMesh& mesh, const mesh::EdgeMap& edges, const FeatureOptions& options,
                               int& dropped) {
  const double crease_cos = std::cos(options.feature_angle_deg * std::numbers::pi / 180.0);
  std::vector<char> crease(edges.num_edges(), 0);
  mesh::DisjointSets groups(mesh.num_points());
  for (int e = 0; e < edges.num_edges(); ++e) {
    const auto ts = edges.triangles_of(e);
    if (ts.size() != 2) continue;
    const Vec3 n0 = mesh::triangle_area_vector(mesh, ts[0]), n1 = mesh::triangle_area_vector(mesh, ts[1]);
    const double a0 = n0.norm(), a1 = n1.norm();
    if (a0 > 0.0 && a1 > 0.0 && n0.dot(n1) < crease_cos * a0 * a1) {
      crease[e] = 1;
      groups.unite(edges.edges[e][0], edges.edges[e][1]);
    }
  }
  std::vector<int> size(mesh.num_points(), 0);
  for (int e = 0; e < edges.num_edges(); ++e)
    if (crease[e]) ++size[groups.find(edges.edges[e][0])];
  dropped = 0;
  for (int e = 0; e < edges.num_edges(); ++e)
    if (crease[e] && size[groups.find(edges.edges[e][0])] < options.min_crease_edges) {
      crease[e] = 0;
      ++dropped;
    }
  return crease;
}

// Per point, its triangles grouped into fans that no crease cuts; one copy per fan.
void split_fans(const TriMesh& mesh, Features& f) {
  const mesh::VertexTriangles around = mesh::build_vertex_triangles(mesh);
  f.corner_copy.assign(mesh.triangles.size(), {-1, -1, -1});
  f.copy_point.clear();
  for (int v = 0; v < mesh.num_points(); ++v) {
    const auto fan = around.of(v);
    mesh::DisjointSets sides(static_cast<int>(fan.size()));
    for (size_t i = 0; i < fan.size(); ++i) {
      const int c = mesh::corner_of(mesh.triangles[fan[i]], v);
      for (int e : {f.edges.triangle_edges[fan[i]][c], f.edges.triangle_edges[fan[i]][(c + 2) % 3]}) {
        if (e < 0 || f.crease[e]) continue;
        for (int u : f.edges.triangles_of(e)) {
          const auto j = std::find(fan.begin(), fan.end(), u) - fan.begin();
          if (j < static_cast<std::ptrdiff_t>(fan.size())) sides.unite(static_cast<int>(i), static_cast<int>(j));
        }
      }
    }
    std::vector<int> copy_of_root(fan.size(), -1);
    for (size_t i = 0; i < fan.size(); ++i) {
      int& copy = copy_of_root[sides.find(static_cast<int>(i))];
      if (copy < 0) {
        copy = f.num_copies();
        f.copy_point.push_back(v);
      }
      f.corner_copy[fan[i]][mesh::corner_of(mesh.triangles[fan[i]], v)] = copy;
    }
  }
}

}  // namespace

Features detect_features(const TriMesh& mesh, const FeatureOptions& options) {
  Features f;
  f.edges = mesh::build_edge_map(mesh);
  const mesh::EdgeMap& edges = f.edges;
  f.crease = find_creases(mesh, edges, options, f.dropped_creases);
  std::vector<char> feature(edges.num_edges(), 0);
  for (int e = 0; e < edges.num_edges(); ++e) {
    const auto ts = edges.triangles_of(e);
    const bool label_border = ts.size() == 2 && mesh.has_labels() && mesh.labels[ts[0]] != mesh.labels[ts[1]];
    feature[e] = ts.size() != 2 || label_border || f.crease[e];
    f.num_creases += f.crease[e];
  }
  split_fans(mesh, f);

  // Point kinds: on a feature, a curve point where exactly two feature edges meet without a
  // sharp turn, else a corner.
  std::vector<std::vector<int>> incident(mesh.points.size());
  for (int e = 0; e < edges.num_edges(); ++e)
    if (feature[e])
      for (int v : edges.edges[e]) incident[v].push_back(e);
  const double corner_cos = std::cos(options.corner_angle_deg * std::numbers::pi / 180.0);
  f.kind.assign(mesh.points.size(), PointKind::free);
  for (int v = 0; v < mesh.num_points(); ++v) {
    if (incident[v].empty()) continue;
    f.kind[v] = PointKind::corner;
    if (incident[v].size() != 2) continue;
    auto other = [&](int e) { return edges.edges[e][0] == v ? edges.edges[e][1] : edges.edges[e][0]; };
    const Vec3 in = mesh.points[v] - mesh.points[other(incident[v][0])];
    const Vec3 out = mesh.points[other(incident[v][1])] - mesh.points[v];
    if (in.dot(out) >= corner_cos * in.norm() * out.norm()) f.kind[v] = PointKind::curve;
  }

  // Curves: feature edges joined through curve points, numbered in edge order.
  mesh::DisjointSets chains(edges.num_edges());
  for (int v = 0; v < mesh.num_points(); ++v)
    if (f.kind[v] == PointKind::curve) chains.unite(incident[v][0], incident[v][1]);
  std::vector<int> curve_of_root(edges.num_edges(), -1);
  f.curve_of_edge.assign(edges.num_edges(), -1);
  f.curve_of_point.assign(mesh.points.size(), -1);
  for (int e = 0; e < edges.num_edges(); ++e) {
    if (!feature[e]) continue;
    int& c = curve_of_root[chains.find(e)];
    if (c < 0) c = f.num_curves++;
    f.curve_of_edge[e] = c;
    for (int v : edges.edges[e])
      if (f.kind[v] == PointKind::curve) f.curve_of_point[v] = c;
  }
  return f;
}

TriMesh split_at_creases(const TriMesh& mesh, const Features& features) {
  VM_CHECK(features.corner_copy.size() == mesh.triangles.size(), "features of another surface");
  TriMesh out;
  out.points.reserve(features.copy_point.size());
  for (int v : features.copy_point) out.points.push_back(mesh.points[v]);
  out.triangles = features.corner_copy;
  out.labels = mesh.labels;
  return out;
}

CurvatureField patch_curvature(const TriMesh& mesh, const Features& features, const CurvatureOptions& options,
                               const Reporter& reporter) {
  if (features.num_copies() == mesh.num_points()) return curvature(mesh, options, reporter);
  const CurvatureField patches = curvature(split_at_creases(mesh, features), options, reporter);
  std::vector<int> chosen(mesh.points.size(), -1);
  auto largest = [&](int copy) { return std::max(std::abs(patches.k1[copy]), std::abs(patches.k2[copy])); };
  for (int copy = 0; copy < features.num_copies(); ++copy) {
    int& c = chosen[features.copy_point[copy]];
    if (c < 0 || largest(copy) > largest(c)) c = copy;
  }
  CurvatureField out;
  for (int v = 0; v < mesh.num_points(); ++v) {
    const int c = chosen[v];
    out.k1.push_back(c < 0 ? 0.0 : patches.k1[c]);
    out.k2.push_back(c < 0 ? 0.0 : patches.k2[c]);
    out.dir1.push_back(c < 0 ? Vec3(Vec3::UnitX()) : patches.dir1[c]);
    out.dir2.push_back(c < 0 ? Vec3(Vec3::UnitY()) : patches.dir2[c]);
    out.normal.push_back(c < 0 ? Vec3(Vec3::Zero()) : patches.normal[c]);
  }
  return out;
}

}  // namespace vesselmesh::analysis
