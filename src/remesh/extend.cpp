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
    // The rings: m points each, evenly spaced along the loop's arc length (parameter t in [0, 1),
    // t = 0 at loop point 0), every other ring shifted by half a spacing (near-equilateral
    // triangles); the loop's own points may be uneven (an edited segmentation's), the rings are not.
    std::vector<double> at(m + 1, 0.0);  // loop point i's parameter
    for (int i = 0; i < m; ++i) at[i + 1] = at[i] + (mesh.points[loop[(i + 1) % m]] - mesh.points[loop[i]]).norm() / perimeter;
    at[m] = 1.0;
    const auto edge_at = [&](double t) {  // the loop edge holding parameter t (mod 1)
      t -= std::floor(t);
      return std::clamp(static_cast<int>(std::upper_bound(at.begin(), at.end(), t) - at.begin()) - 1, 0, m - 1);
    };
    // The loop's sense about n and a frame across n: a ring's circle point at parameter t is at the
    // angle 2 pi t from loop point 0's direction, in the loop's sense.
    double turn = 0.0;
    for (int i = 0; i < m; ++i) turn += across[i].cross(across[(i + 1) % m]).dot(n);
    const Vec3 eu = across[0].norm() > 0.0 ? Vec3(across[0].normalized()) : Vec3(n.unitOrthogonal());
    const Vec3 ev = (turn >= 0.0 ? 1.0 : -1.0) * n.cross(eu);

    const double spacing = 0.87 * perimeter / m;  // about the wall's triangle height there
    const int rings = std::max(2, static_cast<int>(std::ceil(length / spacing)));
    const double blend = std::min(0.5 * length, 2.0 * radius);
    // The circle's radius whose m-gon has the end's area pi R^2.
    const double angle = 2.0 * std::numbers::pi / m;
    const double circle = radius * std::sqrt(angle / std::sin(angle));

    // A band between two rings (points and their parameters, increasing from the first), each
    // triangle oriented as the wall: the two rings zipped by parameter.
    const auto band = [&](const std::vector<int>& lower, const std::vector<double>& lower_at, const std::vector<int>& upper,
                          const std::vector<double>& upper_at) {
      const int nl = static_cast<int>(lower.size()), nu = static_cast<int>(upper.size());
      int i = 0, k = 0;
      while (i < nl || k < nu) {
        const double next_lower = i + 1 < nl ? lower_at[i + 1] : 1.0 + lower_at[0];
        const double next_upper = k + 1 < nu ? upper_at[k + 1] : 1.0 + upper_at[0];
        const int a = lower[i % nl], b = upper[k % nu];
        double t = 0.0;
        if (k >= nu || (i < nl && next_lower <= next_upper)) {  // along the lower ring
          out.triangles.push_back({lower[(i + 1) % nl], a, b});
          t = 0.5 * (lower_at[i] + next_lower);
          ++i;
        } else {  // along the upper ring
          out.triangles.push_back({a, b, upper[(k + 1) % nu]});
          t = 0.5 * (upper_at[k] + next_upper);
          ++k;
        }
        if (mesh.has_labels()) out.labels.push_back(mesh.labels[edge_triangle[edge_at(t)]]);
      }
    };

    std::vector<int> previous(loop.begin(), loop.end());
    std::vector<double> previous_at(at.begin(), at.end() - 1);
    for (int j = 1; j <= rings; ++j) {
      const double d = length * j / rings;
      const double w = smoothstep(d / blend);
      // The tube leaves each point along the wall (its derivative there t / (t . n)) and turns to
      // n by d = blend: phi(0) = 0, phi'(0) = 1, phi(blend) = phi'(blend) = 0.
      const double phi = d < blend ? d * (1.0 - d / blend) * (1.0 - d / blend) : 0.0;
      std::vector<int> ring(m);
      std::vector<double> ring_at(m);
      for (int k = 0; k < m; ++k) {
        const double t = (k + (j % 2 == 1 ? 0.5 : 0.0)) / m;
        ring_at[k] = t;
        // The loop's shape at t, between its points.
        const int i = edge_at(t), i1 = (i + 1) % m;
        const double f = at[i + 1] > at[i] ? (t - at[i]) / (at[i + 1] - at[i]) : 0.0;
        const Vec3 shape_across = (1.0 - f) * across[i] + f * across[i1];
        const double shape_along = (1.0 - f) * along[i] + f * along[i1];
        const Vec3 radial = std::cos(2.0 * std::numbers::pi * t) * eu + std::sin(2.0 * std::numbers::pi * t) * ev;
        Vec3 point = c + (d + (1.0 - w) * shape_along) * n + (1.0 - w) * shape_across + w * circle * radial;
        const Vec3 wall = (1.0 - f) * direction[i] + f * direction[i1];
        if (options.mode == ExtensionMode::smooth && j < rings && wall.norm() > 0.0) {
          const Vec3 tangent = wall.normalized();
          const double rise = tangent.dot(n);
          if (rise > 0.2) point += phi * (tangent / rise - n);  // a wall nearly across n keeps the straight start
        }
        ring[k] = out.num_points();
        out.points.push_back(point);
      }
      band(previous, previous_at, ring, ring_at);
      previous = std::move(ring);
      previous_at = std::move(ring_at);
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
