#include "mesh/clean.h"

#include "mesh/connectivity.h"
#include "mesh/error.h"
#include "mesh/geometry.h"
#include "mesh/merge_points.h"
#include "mesh/self_intersections.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace vesselmesh::mesh {
namespace {

constexpr const char* kDefectKinds[] = {
    "near_duplicate_points", "degenerate_triangles",  "duplicate_triangles",
    "non_manifold_edges",    "non_manifold_vertices", "inconsistent_orientation",
    "inward_components",     "extra_components",      "zero_area_triangles",
    "unreferenced_points",   "self_intersections"};
constexpr const char* kRepairKinds[] = {
    "merged_points",          "removed_degenerate_triangles", "removed_duplicate_triangles",
    "split_vertices",         "flipped_triangles",            "removed_components",
    "removed_component_triangles", "flipped_zero_area_edges",  "removed_zero_area_triangles",
    "removed_unreferenced_points"};

// Signed volume of each component, open ends closed by fans from their loop centroids.
std::vector<double> component_volumes(const TriMesh& m, const std::vector<int>& component,
                                      int num_components) {
  const EdgeMap edges = build_edge_map(m);
  std::vector<int> vertex_component(m.points.size(), -1);
  std::vector<Vec3> reference(num_components, Vec3::Zero());
  std::vector<double> weight(num_components, 0.0);
  for (int t = 0; t < m.num_triangles(); ++t) {
    for (int v : m.triangles[t]) vertex_component[v] = component[t];
    reference[component[t]] += triangle_centroid(m, t);
    weight[component[t]] += 1.0;
  }
  for (int c = 0; c < num_components; ++c) reference[c] /= std::max(weight[c], 1.0);
  // Coordinates relative to each component's centre keep the sum accurate far from the origin.
  auto tet = [&](int c, const Vec3& a, const Vec3& b, const Vec3& d) {
    const Vec3& r = reference[c];
    return (a - r).dot((b - r).cross(d - r)) / 6.0;
  };
  std::vector<double> volume(num_components, 0.0);
  for (int t = 0; t < m.num_triangles(); ++t) {
    const Triangle& f = m.triangles[t];
    volume[component[t]] += tet(component[t], m.points[f[0]], m.points[f[1]], m.points[f[2]]);
  }
  for (const std::vector<int>& loop : boundary_loops(m, edges)) {
    const int c = vertex_component[loop.front()];
    Vec3 centre = Vec3::Zero();
    for (int v : loop) centre += m.points[v];
    centre /= static_cast<double>(loop.size());
    for (size_t i = 0; i < loop.size(); ++i) {  // the cap runs against the wall's edges
      const Vec3& a = m.points[loop[i]];
      const Vec3& b = m.points[loop[(i + 1) % loop.size()]];
      volume[c] += tet(c, centre, b, a);
    }
  }
  return volume;
}

class Doctor {
 public:
  Doctor(TriMesh& mesh, const CleanOptions& options, const Reporter& reporter)
      : m_(mesh), options_(options), reporter_(reporter) {}

  CleanReport run() {
    report_.input_points = m_.num_points();
    report_.input_triangles = m_.num_triangles();
    for (const char* kind : kDefectKinds) report_.defects[kind] = 0;
    for (const char* kind : kRepairKinds) report_.repairs[kind] = 0;
    report_.point_origin.resize(m_.points.size());
    std::iota(report_.point_origin.begin(), report_.point_origin.end(), 0);
    report_.triangle_origin.resize(m_.triangles.size());
    std::iota(report_.triangle_origin.begin(), report_.triangle_origin.end(), 0);

    void (Doctor::*const steps[])() = {
        &Doctor::check_input,           &Doctor::merge_near_duplicates, &Doctor::remove_degenerate_and_duplicates,
        &Doctor::check_manifold,        &Doctor::orient_consistently,   &Doctor::keep_largest_component,
        &Doctor::orient_outward,        &Doctor::mend_zero_area,        &Doctor::remove_unreferenced,
        &Doctor::find_self_intersections};
    const double n = std::size(steps);
    for (size_t i = 0; i < std::size(steps); ++i) {
      reporter_.progress("checking the surface", i / n);
      (this->*steps[i])();
    }
    reporter_.progress("checking the surface", 1.0);
    if (m_.triangles.empty()) throw InputError("the surface has no triangle with a non-zero area");
    return std::move(report_);
  }

 private:
  void note(const std::string& line) {
    report_.notes.push_back(line);
    reporter_.info(line);
  }

  std::string at_point(int v) const { return format_point(m_.points[v]); }
  std::string at_triangle(int t) const { return format_point(triangle_centroid(m_, t)); }

  // Lists up to max_locations items as "a, b, c and N more".
  template <typename Describe>
  std::string list_locations(const std::vector<int>& items, Describe describe) const {
    std::string text;
    const size_t shown = std::min(items.size(), static_cast<size_t>(options_.max_locations));
    for (size_t i = 0; i < shown; ++i) text += (i ? "; " : "") + describe(items[i]);
    if (items.size() > shown) text += fmt::format(" and {} more", items.size() - shown);
    return text;
  }

  void check_input() {
    const int np = m_.num_points();
    for (int v = 0; v < np; ++v) {
      if (!m_.points[v].allFinite())
        throw InputError(fmt::format("point {} has a non-finite coordinate ({}, {}, {})", v,
                                     m_.points[v].x(), m_.points[v].y(), m_.points[v].z()));
    }
    for (int t = 0; t < m_.num_triangles(); ++t)
      for (int v : m_.triangles[t])
        if (v < 0 || v >= np)
          throw InputError(fmt::format("triangle {} refers to point {}, but there are {} points", t,
                                       v, np));
    if (m_.has_labels() && m_.labels.size() != m_.triangles.size())
      throw InputError(fmt::format("{} labels for {} triangles", m_.labels.size(),
                                   m_.triangles.size()));
    if (m_.triangles.empty()) throw InputError("the surface has no triangles");
  }

  // Keeps the triangles whose flag is set, in order, with their labels and origins.
  void keep_triangles(const std::vector<char>& keep) {
    size_t out = 0;
    for (size_t t = 0; t < m_.triangles.size(); ++t) {
      if (!keep[t]) continue;
      m_.triangles[out] = m_.triangles[t];
      if (m_.has_labels()) m_.labels[out] = m_.labels[t];
      report_.triangle_origin[out] = report_.triangle_origin[t];
      ++out;
    }
    m_.triangles.resize(out);
    if (m_.has_labels()) m_.labels.resize(out);
    report_.triangle_origin.resize(out);
  }

  // Applies a point remap (old -> new, first occurrence keeps its origin) after a compaction.
  void remap_points(const std::vector<int>& remap, int new_count) {
    std::vector<int> origin(new_count, -1);
    for (size_t i = 0; i < remap.size(); ++i)
      if (remap[i] >= 0 && origin[remap[i]] == -1) origin[remap[i]] = report_.point_origin[i];
    report_.point_origin = std::move(origin);
    remap_triangles(m_.triangles, remap);
  }

  void merge_near_duplicates() {
    const int np = m_.num_points();
    std::vector<double> length_sum(np, 0.0);
    std::vector<int> length_count(np, 0);
    for (const Triangle& f : m_.triangles)
      for (int i = 0; i < 3; ++i) {
        const double l = (m_.points[f[i]] - m_.points[f[(i + 1) % 3]]).norm();
        for (int v : {f[i], f[(i + 1) % 3]}) length_sum[v] += l, ++length_count[v];
      }
    std::vector<double> tolerance(np, 0.0);
    for (int v = 0; v < np; ++v)
      if (length_count[v]) tolerance[v] = options_.merge_tolerance * length_sum[v] / length_count[v];
    const std::vector<Vec3> before = m_.points;
    const std::vector<int> remap = merge_close_points(m_.points, tolerance);
    const int merged = np - m_.num_points();
    if (merged == 0) return;
    std::vector<int> moved;  // points merged into an earlier one
    std::vector<char> seen(m_.points.size(), 0);
    for (int v = 0; v < np; ++v) {
      if (seen[remap[v]]) moved.push_back(v);
      seen[remap[v]] = 1;
    }
    remap_points(remap, m_.num_points());
    report_.defects["near_duplicate_points"] = merged;
    report_.repairs["merged_points"] = merged;
    note(fmt::format("merged {} near-duplicate point(s) (closer than {:g} of the local edge "
                     "length): {}",
                     merged, options_.merge_tolerance,
                     list_locations(moved, [&](int v) { return format_point(before[v]); })));
  }

  void remove_degenerate_and_duplicates() {
    const int nt = m_.num_triangles();
    std::vector<char> keep(nt, 1);
    std::vector<int> degenerate;
    for (int t = 0; t < nt; ++t) {
      const Triangle& f = m_.triangles[t];
      if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) keep[t] = 0, degenerate.push_back(t);
    }
    // Duplicates: the same three points in any order; the first one stays.
    std::vector<std::pair<Triangle, int>> sorted;
    sorted.reserve(nt);
    for (int t = 0; t < nt; ++t) {
      if (!keep[t]) continue;
      Triangle key = m_.triangles[t];
      std::sort(key.begin(), key.end());
      sorted.emplace_back(key, t);
    }
    std::sort(sorted.begin(), sorted.end());
    std::vector<int> duplicate;
    for (size_t i = 1; i < sorted.size(); ++i)
      if (sorted[i].first == sorted[i - 1].first) keep[sorted[i].second] = 0, duplicate.push_back(sorted[i].second);
    std::sort(duplicate.begin(), duplicate.end());
    report_removed("degenerate_triangles", "triangle(s) with a repeated corner", degenerate);
    report_removed("duplicate_triangles", "duplicate triangle(s)", duplicate);
    keep_triangles(keep);
    if (m_.triangles.empty()) throw InputError("the surface has no triangle with three distinct corners");
  }

  // Counts removed triangles as defect `kind` and repair "removed_<kind>", with a note.
  void report_removed(const std::string& kind, const char* description, const std::vector<int>& triangles) {
    if (triangles.empty()) return;
    report_.defects[kind] = static_cast<int>(triangles.size());
    report_.repairs["removed_" + kind] = static_cast<int>(triangles.size());
    note(fmt::format("removed {} {}: {}", triangles.size(), description, list_locations(triangles, [&](int t) {
                       return fmt::format("triangle {} at {}", report_.triangle_origin[t], at_triangle(t));
                     })));
  }

  void check_manifold() {
    const EdgeMap edges = build_edge_map(m_);
    std::vector<int> bad;
    for (int e = 0; e < edges.num_edges(); ++e)
      if (edges.valence(e) > 2) bad.push_back(e);
    if (!bad.empty()) {
      report_.defects["non_manifold_edges"] = static_cast<int>(bad.size());
      const auto& e = edges.edges[bad.front()];
      throw InputError(fmt::format(
          "{} non-manifold edge(s), where more than two triangles meet; the first joins points "
          "{} {} and {} {} and is shared by {} triangles. A lumen surface must be a 2-manifold: "
          "remove the extra sheets or fins (e.g. MeshLab: Select Non Manifold Edges, Delete) and "
          "try again",
          bad.size(), report_.point_origin[e[0]], at_point(e[0]), report_.point_origin[e[1]],
          at_point(e[1]), edges.valence(bad.front())));
    }
    split_non_manifold_vertices(edges);
  }

  // A vertex whose triangles form several fans (joined only at the vertex) gets one copy
  // per extra fan, so that every vertex is a disk or half-disk.
  void split_non_manifold_vertices(const EdgeMap& edges) {
    const VertexTriangles vt = build_vertex_triangles(m_);
    const int np = m_.num_points();
    std::vector<int> split;
    int copies = 0;
    for (int v = 0; v < np; ++v) {
      const std::span<const int> around = vt.of(v);
      if (around.size() < 2) continue;
      std::vector<int> group(around.size());
      std::iota(group.begin(), group.end(), 0);
      auto root = [&](int i) { while (group[i] != i) i = group[i] = group[group[i]]; return i; };
      for (size_t i = 0; i < around.size(); ++i) {
        const int t = around[i];
        const int c = corner_of(m_.triangles[t], v);
        for (int e : {edges.triangle_edges[t][c], edges.triangle_edges[t][(c + 2) % 3]}) {
          if (edges.valence(e) != 2) continue;
          const auto ts = edges.triangles_of(e);
          const int u = ts[0] == t ? ts[1] : ts[0];
          const size_t j = std::find(around.begin(), around.end(), u) - around.begin();
          const int a = root(static_cast<int>(i)), b = root(static_cast<int>(j));
          if (a != b) group[std::max(a, b)] = std::min(a, b);
        }
      }
      // Fans in the order of their lowest triangle; the first keeps the vertex.
      std::vector<int> copy_of_root(around.size(), -1);
      copy_of_root[root(0)] = v;
      for (size_t i = 0; i < around.size(); ++i) {
        const int r = root(static_cast<int>(i));
        if (copy_of_root[r] == -1) {
          copy_of_root[r] = m_.num_points();
          m_.points.push_back(m_.points[v]);
          report_.point_origin.push_back(report_.point_origin[v]);
          ++copies;
          if (split.empty() || split.back() != v) split.push_back(v);
        }
        Triangle& f = m_.triangles[around[i]];
        f[corner_of(f, v)] = copy_of_root[r];
      }
    }
    if (split.empty()) return;
    report_.defects["non_manifold_vertices"] = static_cast<int>(split.size());
    report_.repairs["split_vertices"] = copies;
    note(fmt::format("split {} non-manifold vertex(es), where separate fans of triangles touch at "
                     "one point, into {} extra point(s): {}",
                     split.size(), copies, list_locations(split, [&](int v) {
                       return fmt::format("point {} at {}", report_.point_origin[v], at_point(v));
                     })));
  }

  void orient_consistently() {
    const EdgeMap edges = build_edge_map(m_);
    const int nt = m_.num_triangles();
    std::vector<signed char> flip(nt, -1);
    std::vector<int> stack, members;
    int inconsistent = 0;
    for (int seed = 0; seed < nt; ++seed) {
      if (flip[seed] != -1) continue;
      flip[seed] = 0;
      stack.assign(1, seed);
      members.clear();
      while (!stack.empty()) {
        const int t = stack.back();
        stack.pop_back();
        members.push_back(t);
        for (int i = 0; i < 3; ++i) {
          const int e = edges.triangle_edges[t][i];
          if (edges.valence(e) != 2) continue;
          const auto ts = edges.triangles_of(e);
          const int u = ts[0] == t ? ts[1] : ts[0];
          // Same direction of the shared edge in both triangles: one of them must turn.
          const int a = m_.triangles[t][i];
          const int cu = corner_of(m_.triangles[u], a);
          const bool same = m_.triangles[u][(cu + 1) % 3] == m_.triangles[t][(i + 1) % 3];
          const signed char want = static_cast<signed char>(flip[t] ^ (same ? 1 : 0));
          if (flip[u] == -1) {
            flip[u] = want;
            stack.push_back(u);
          } else if (flip[u] != want) {
            throw InputError(fmt::format(
                "the surface is not orientable (it has a Moebius-like twist) near triangle {} at "
                "{}; a lumen surface must have an inside and an outside",
                report_.triangle_origin[t], at_triangle(t)));
          }
        }
      }
      // Turn the smaller part of the component.
      const auto flipped = std::count_if(members.begin(), members.end(), [&](int t) { return flip[t] == 1; });
      if (2 * flipped > static_cast<long>(members.size()))
        for (int t : members) flip[t] ^= 1;
      inconsistent += static_cast<int>(std::min<long>(flipped, members.size() - flipped));
    }
    if (inconsistent == 0) return;
    for (int t = 0; t < nt; ++t)
      if (flip[t] == 1) std::swap(m_.triangles[t][1], m_.triangles[t][2]);
    report_.defects["inconsistent_orientation"] = inconsistent;
    report_.repairs["flipped_triangles"] += inconsistent;
    note(fmt::format("turned {} triangle(s) whose orientation disagreed with their neighbours",
                     inconsistent));
  }

  void keep_largest_component() {
    const EdgeMap edges = build_edge_map(m_);
    int count = 0;
    const std::vector<int> component = triangle_components(m_, edges, &count);
    report_.input_components = count;
    if (count <= 1) return;
    std::vector<int> size(count, 0), first(count, -1);
    for (int t = 0; t < m_.num_triangles(); ++t) {
      ++size[component[t]];
      if (first[component[t]] == -1) first[component[t]] = t;
    }
    const int largest = static_cast<int>(std::max_element(size.begin(), size.end()) - size.begin());
    std::vector<int> others;
    for (int c = 0; c < count; ++c)
      if (c != largest) others.push_back(c);
    report_.defects["extra_components"] = count - 1;
    const std::string where = list_locations(others, [&](int c) {
      return fmt::format("{} triangle(s) near {}", size[c], at_triangle(first[c]));
    });
    if (!options_.keep_largest_component) {
      note(fmt::format("{} connected components; besides the largest ({} triangles): {}", count,
                       size[largest], where));
      return;
    }
    std::vector<char> keep(m_.num_triangles());
    for (int t = 0; t < m_.num_triangles(); ++t) keep[t] = component[t] == largest;
    keep_triangles(keep);
    report_.repairs["removed_components"] = count - 1;
    report_.repairs["removed_component_triangles"] =
        std::accumulate(size.begin(), size.end(), 0) - size[largest];
    note(fmt::format("kept the largest of {} connected components ({} triangles) and removed: {}",
                     count, size[largest], where));
  }

  void orient_outward() {
    if (!options_.orient_outward) return;
    const EdgeMap edges = build_edge_map(m_);
    int count = 0;
    const std::vector<int> component = triangle_components(m_, edges, &count);
    const std::vector<double> volume = component_volumes(m_, component, count);
    std::vector<int> inward;
    for (int c = 0; c < count; ++c)
      if (volume[c] < 0.0) inward.push_back(c);
    if (inward.empty()) return;
    int turned = 0;
    for (int t = 0; t < m_.num_triangles(); ++t)
      if (volume[component[t]] < 0.0) std::swap(m_.triangles[t][1], m_.triangles[t][2]), ++turned;
    report_.defects["inward_components"] = static_cast<int>(inward.size());
    report_.repairs["flipped_triangles"] += turned;
    note(fmt::format("the surface was oriented inward (signed volume {:.6g}, with the open ends "
                     "closed); turned all {} triangles to face outward",
                     volume[inward.front()], turned));
  }

  bool zero_area(const Triangle& f) const {
    const Vec3& a = m_.points[f[0]];
    const Vec3& b = m_.points[f[1]];
    const Vec3& c = m_.points[f[2]];
    const double longest = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    return (b - a).cross(c - a).norm() <= options_.zero_area_tolerance * longest;
  }

  // One round of edge flips; returns the number of triangles mended.
  int mend_zero_area_round(std::vector<int>& unrepaired) {
    const EdgeMap edges = build_edge_map(m_);
    const VertexTriangles vt = build_vertex_triangles(m_);
    const int nt = m_.num_triangles();
    std::vector<char> keep(nt, 1), touched(nt, 0);
    int mended = 0;
    for (int t = 0; t < nt; ++t) {
      if (touched[t] || !zero_area(m_.triangles[t])) continue;
      const Triangle f = m_.triangles[t];
      int longest = 0;  // edge between corners i and i+1
      double best = -1.0;
      for (int i = 0; i < 3; ++i) {
        const double l = (m_.points[f[(i + 1) % 3]] - m_.points[f[i]]).squaredNorm();
        if (l > best) best = l, longest = i;
      }
      const int e = edges.triangle_edges[t][longest];
      if (edges.is_boundary(e)) {  // the crack it leaves is part of the boundary
        keep[t] = 0, touched[t] = 1, ++mended;
        report_.repairs["removed_zero_area_triangles"]++;
        continue;
      }
      const auto ts = edges.triangles_of(e);
      const int u = ts[0] == t ? ts[1] : ts[0];
      if (touched[u] || edges.valence(e) != 2 || !try_flip(t, u, longest, vt)) {
        if (std::find(unrepaired.begin(), unrepaired.end(), t) == unrepaired.end()) unrepaired.push_back(t);
        continue;
      }
      touched[t] = touched[u] = 1;
      ++mended;
      report_.repairs["flipped_zero_area_edges"]++;
    }
    keep_triangles(keep);
    return mended;
  }

  // Flips the edge between corners i, i+1 of t = (a, b, c) with its neighbour u = (b, a, d):
  // t becomes (a, d, c) and u becomes (d, b, c), if both are proper and face like u did.
  bool try_flip(int t, int u, int i, const VertexTriangles& vt) {
    const Triangle f = m_.triangles[t];
    const int a = f[i], b = f[(i + 1) % 3], c = f[(i + 2) % 3];
    const Triangle g = m_.triangles[u];
    const int d = g[(corner_of(g, a) + 1) % 3];
    if (d == c) return false;
    for (int s : vt.of(c))
      if (corner_of(m_.triangles[s], d) != -1) return false;  // edge c-d exists already
    const Triangle t_new{a, d, c}, u_new{d, b, c};
    if (zero_area(t_new) || zero_area(u_new)) return false;
    auto normal = [&](const Triangle& h) {
      return Vec3((m_.points[h[1]] - m_.points[h[0]]).cross(m_.points[h[2]] - m_.points[h[0]]));
    };
    const Vec3 nu = normal(g);
    if (normal(t_new).dot(nu) <= 0.0 || normal(u_new).dot(nu) <= 0.0) return false;
    m_.triangles[t] = t_new;
    m_.triangles[u] = u_new;
    return true;
  }

  void mend_zero_area() {
    int found = 0;
    for (const Triangle& f : m_.triangles) found += zero_area(f);
    if (found == 0) return;
    report_.defects["zero_area_triangles"] = found;
    std::vector<int> unrepaired;
    for (int round = 0; round < 10; ++round) {
      unrepaired.clear();
      if (mend_zero_area_round(unrepaired) == 0) break;
    }
    std::vector<int> left;
    for (int t = 0; t < m_.num_triangles(); ++t)
      if (zero_area(m_.triangles[t])) left.push_back(t);
    note(fmt::format("{} zero-area triangle(s): {} mended by an edge flip, {} removed on the "
                     "boundary{}",
                     found, report_.repairs["flipped_zero_area_edges"],
                     report_.repairs["removed_zero_area_triangles"],
                     left.empty() ? std::string()
                                  : fmt::format(", {} left as they are: {}", left.size(),
                                                list_locations(left, [&](int t) {
                                                  return fmt::format("triangle at {}", at_triangle(t));
                                                }))));
    if (!left.empty())
      reporter_.warning(fmt::format("{} zero-area triangle(s) could not be mended", left.size()));
  }

  void remove_unreferenced() {
    const int np = m_.num_points();
    std::vector<char> used(np, 0);
    for (const Triangle& f : m_.triangles)
      for (int v : f) used[v] = 1;
    std::vector<int> remap(np, -1);
    int kept = 0;
    for (int v = 0; v < np; ++v)
      if (used[v]) m_.points[kept] = m_.points[v], remap[v] = kept++;
    if (kept == np) return;
    m_.points.resize(kept);
    remap_points(remap, kept);
    report_.defects["unreferenced_points"] = np - kept;
    report_.repairs["removed_unreferenced_points"] = np - kept;
    note(fmt::format("removed {} point(s) that no triangle uses", np - kept));
  }

  void find_self_intersections() {
    if (!options_.find_self_intersections) return;
    report_.self_intersections = self_intersecting_pairs(m_);
    const int count = static_cast<int>(report_.self_intersections.size());
    report_.defects["self_intersections"] = count;
    if (count == 0) return;
    std::vector<int> index(count);
    std::iota(index.begin(), index.end(), 0);
    note(fmt::format("{} pair(s) of triangles intersect each other (not repaired): {}", count,
                     list_locations(index, [&](int i) {
                       const auto [s, t] = report_.self_intersections[i];
                       return fmt::format("triangles {} and {} near {}", s, t, at_triangle(s));
                     })));
    reporter_.warning(fmt::format("the surface intersects itself ({} triangle pairs)", count));
  }

  TriMesh& m_;
  const CleanOptions& options_;
  const Reporter& reporter_;
  CleanReport report_;
};

}  // namespace

int CleanReport::total_repairs() const {
  int total = 0;
  for (const auto& [kind, count] : repairs) total += count;
  return total;
}

CleanReport clean(TriMesh& mesh, const CleanOptions& options, const Reporter& reporter) {
  if (!(options.merge_tolerance >= 0.0 && options.merge_tolerance < 0.5))
    throw OptionError(fmt::format("merge tolerance {} is outside [0, 0.5)", options.merge_tolerance));
  return Doctor(mesh, options, reporter).run();
}

double signed_volume(const TriMesh& mesh) {
  if (mesh.triangles.empty()) return 0.0;
  const std::vector<int> component(mesh.triangles.size(), 0);
  return component_volumes(mesh, component, 1).front();
}

}  // namespace vesselmesh::mesh
