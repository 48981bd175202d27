#include "remesh/extend.h"

#include "mesh/connectivity.h"
#include "mesh/error.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace vesselmesh::remesh {

ExtensionMode parse_extension_mode(const std::string& text) {
  if (text == "straight") return ExtensionMode::straight;
  if (text == "smooth") return ExtensionMode::smooth;
  throw InputError(fmt::format("extension mode \"{}\": expected straight or smooth", text));
}

namespace {

double smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3.0 - 2.0 * x);
}

// The wall triangle holding the directed edge a -> b (the loop runs along the wall's own edges).
int triangle_with_edge(const TriMesh& mesh, const mesh::VertexTriangles& around, int a, int b) {
  for (int t : around.of(a)) {
    const Triangle& f = mesh.triangles[t];
    const int c = mesh::corner_of(f, a);
    if (f[(c + 1) % 3] == b) return t;
  }
  return -1;
}

}  // namespace

ExtensionResult extend_ends(const TriMesh& mesh, const std::vector<analysis::OpenEnd>& ends,
                            const ExtensionOptions& options) {
  if (!(options.length > 0.0))
    throw InputError(fmt::format("extension length {}: give a positive length (in radii of each end)", options.length));
  std::vector<int> chosen = options.ends;
  if (chosen.empty())
    for (int e = 0; e < static_cast<int>(ends.size()); ++e)
      if (!ends[e].capped) chosen.push_back(e);
  for (int e : chosen) {
    if (e < 0 || e >= static_cast<int>(ends.size()))
      throw InputError(fmt::format("end {}: the surface has {} ends (0 to {})", e, ends.size(), ends.size() - 1));
    if (ends[e].capped)
      throw InputError(fmt::format("end {} (centre {:.4g}, {:.4g}, {:.4g}) is capped: extensions start from open ends; "
                                   "leave it out or give the surface with that end open",
                                   e, ends[e].center.x(), ends[e].center.y(), ends[e].center.z()));
  }
  std::sort(chosen.begin(), chosen.end());
  chosen.erase(std::unique(chosen.begin(), chosen.end()), chosen.end());

  ExtensionResult result;
  result.mesh = mesh;
  TriMesh& out = result.mesh;
  const mesh::VertexTriangles around = mesh::build_vertex_triangles(mesh);
  for (int e : chosen) {
    const analysis::OpenEnd& end = ends[e];
    const std::vector<int>& loop = end.loop;
    const int m = static_cast<int>(loop.size());
    VM_CHECK(m >= 3, "an open end's loop has three points or more");
    const Vec3 c = end.center, n = end.normal.normalized();
    const double radius = end.radius, length = options.length * radius;

    // Per loop point: its offset from the centre split along n and across it, its direction
    // round the axis, and the wall's direction there (away from the inner points, across the
    // loop); per loop edge the wall triangle on it.
    double perimeter = 0.0;
    std::vector<int> edge_triangle(m);
    std::vector<Vec3> across(m), direction(m, Vec3::Zero());
    std::vector<double> along(m);
    for (int i = 0; i < m; ++i) {
      const int a = loop[i], b = loop[(i + 1) % m];
      perimeter += (mesh.points[b] - mesh.points[a]).norm();
      edge_triangle[i] = triangle_with_edge(mesh, around, a, b);
      VM_CHECK(edge_triangle[i] >= 0, "a loop edge lies on a wall triangle");
      const Vec3 q = mesh.points[a] - c;
      along[i] = q.dot(n);
      across[i] = q - along[i] * n;
    }
    for (int i = 0; i < m; ++i) {  // the wall's direction at loop point i from its two loop edges' triangles
      for (int k : {i, (i + m - 1) % m}) {
        const Triangle& f = mesh.triangles[edge_triangle[k]];
        const int a = loop[k], b = loop[(k + 1) % m];
        int inner = f[0];
        for (int v : f)
          if (v != a && v != b) inner = v;
        const Vec3 edge = (mesh.points[b] - mesh.points[a]).normalized();
        Vec3 away = mesh.points[loop[i]] - mesh.points[inner];
        away -= away.dot(edge) * edge;
        if (away.norm() > 0.0) direction[i] += away.normalized();
      }
    }
    const double spacing = 0.87 * perimeter / m;  // about the wall's triangle height there
    const int rings = std::max(2, static_cast<int>(std::ceil(length / spacing)));
    const double blend = std::min(0.5 * length, 2.0 * radius);
    // The circle's radius whose m-gon has the end's area pi R^2.
    const double angle = 2.0 * std::numbers::pi / m;
    const double circle = radius * std::sqrt(angle / std::sin(angle));

    std::vector<int> previous(loop.begin(), loop.end());
    for (int j = 1; j <= rings; ++j) {
      const double d = length * j / rings;
      const double w = smoothstep(d / blend);
      // The tube leaves each point along the wall (its derivative there t / (t . n)) and turns to
      // n by d = blend: phi(0) = 0, phi'(0) = 1, phi(blend) = phi'(blend) = 0.
      const double phi = d < blend ? d * (1.0 - d / blend) * (1.0 - d / blend) : 0.0;
      std::vector<int> ring(m);
      for (int i = 0; i < m; ++i) {
        const double r = across[i].norm();
        const Vec3 radial = r > 0.0 ? Vec3(across[i] / r) : Vec3::Zero();
        Vec3 point = c + (d + (1.0 - w) * along[i]) * n + (1.0 - w) * across[i] + w * circle * radial;
        if (options.mode == ExtensionMode::smooth && j < rings && direction[i].norm() > 0.0) {
          const Vec3 t = direction[i].normalized();
          const double rise = t.dot(n);
          if (rise > 0.2) point += phi * (t / rise - n);  // a wall nearly across n keeps the straight start
        }
        ring[i] = out.num_points();
        out.points.push_back(point);
      }
      // The band between the rings, each quad cut along its shorter diagonal, oriented as the wall.
      for (int i = 0; i < m; ++i) {
        const int i1 = (i + 1) % m;
        const int a0 = previous[i], a1 = previous[i1], b0 = ring[i], b1 = ring[i1];
        const int label = mesh.has_labels() ? mesh.labels[edge_triangle[i]] : 0;
        const bool first = (out.points[a1] - out.points[b0]).squaredNorm() <= (out.points[a0] - out.points[b1]).squaredNorm();
        if (first) {
          out.triangles.push_back({a1, a0, b0});
          out.triangles.push_back({a1, b0, b1});
        } else {
          out.triangles.push_back({a1, a0, b1});
          out.triangles.push_back({a0, b0, b1});
        }
        if (mesh.has_labels()) out.labels.insert(out.labels.end(), 2, label);
      }
      previous = std::move(ring);
    }
    ExtendedEnd x;
    x.end = e;
    x.old_center = c;
    x.center = c + length * n;
    x.normal = n;
    x.radius = radius;
    x.length = length;
    x.rings = rings;
    result.extended.push_back(x);
  }
  return result;
}

}  // namespace vesselmesh::remesh
