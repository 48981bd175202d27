#include "synth/tubes.h"

#include "mesh/clean.h"
#include "mesh/connectivity.h"
#include "synth/plane_cut.h"
#include "synth/random.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace vesselmesh::synth {

double distance_to_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

double distance_to_arc(const Vec3& p, const Vec3& center, const Vec3& u, const Vec3& v, double radius,
                       double sweep) {
  const Vec3 d = p - center;
  const double x = d.dot(u), y = d.dot(v);
  const Vec3 start = center + radius * u;
  const Vec3 end = center + radius * (std::cos(sweep) * u + std::sin(sweep) * v);
  double best = std::min((p - start).norm(), (p - end).norm());
  if (x != 0.0 || y != 0.0) {
    double angle = std::atan2(y, x);
    if (angle < 0.0) angle += 2.0 * std::numbers::pi;
    if (angle <= sweep) {
      const Vec3 q = center + radius * (std::cos(angle) * u + std::sin(angle) * v);
      best = std::min(best, (p - q).norm());
    }
  }
  return best;
}

double smooth_min(double a, double b, double k) {
  if (k <= 0.0) return std::min(a, b);
  const double h = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - h * h * k / 4.0;
}

TriMesh open_tube_surface(const ImplicitFunction& f, const Vec3& lo, const Vec3& hi, std::span<const TubeEnd> ends,
                          const TubeSurfaceOptions& o) {
  const double h = o.resolution;
  const double dh = 1e-3 * h;  // finite-difference step of the gradient
  TriMesh mesh = polygonize(f, lo, hi, h);
  mesh::clean(mesh, {.merge_tolerance = 0.02, .find_self_intersections = false});
  for (int round = 0; round < 3; ++round) {  // marching cubes leaves slivers: smooth and flip
    relax_on_zero_set(mesh, f, dh, 5);
    flip_to_improve_angles(mesh);
  }
  relax_on_zero_set(mesh, f, dh, 5);
  for (const TubeEnd& end : ends) {
    const CutPlane plane{.point = end.center, .normal = end.normal, .reach = o.reach * end.radius};
    auto onto_plane = [&](const Vec3& p) {
      return project_to_zero_set(f, p - (p - end.center).dot(end.normal) * end.normal, dh);
    };
    mesh = cut_by_plane(mesh, plane, 0.35 * h, onto_plane);
  }
  // Relax again around the cuts, the new boundary kept in its planes.
  const mesh::EdgeMap edges = mesh::build_edge_map(mesh);
  std::vector<char> fixed(mesh.points.size(), 0);
  for (int e = 0; e < edges.num_edges(); ++e)
    if (edges.is_boundary(e)) fixed[edges.edges[e][0]] = fixed[edges.edges[e][1]] = 1;
  flip_to_improve_angles(mesh);
  relax_on_zero_set(mesh, f, dh, 3, fixed);
  if (o.jitter > 0.0) {
    Random random(o.seed);
    std::vector<double> shortest(mesh.points.size(), std::numeric_limits<double>::infinity());
    for (int e = 0; e < edges.num_edges(); ++e) {  // the edges before the last flips
      const auto [a, b] = edges.edges[e];
      const double l = (mesh.points[a] - mesh.points[b]).norm();
      shortest[a] = std::min(shortest[a], l), shortest[b] = std::min(shortest[b], l);
    }
    std::vector<Vec3> moved = mesh.points;
    for (int v = 0; v < mesh.num_points(); ++v) {
      const double angle = random.uniform(0.0, 2.0 * std::numbers::pi), amount = o.jitter * random.uniform();
      if (fixed[v]) continue;
      const Vec3 n = gradient(f, mesh.points[v], dh).normalized();
      const Vec3 t1 = n.unitOrthogonal(), t2 = n.cross(t1);
      moved[v] = project_to_zero_set(
          f, mesh.points[v] + amount * shortest[v] * (std::cos(angle) * t1 + std::sin(angle) * t2), dh);
    }
    mesh.points = std::move(moved);
  }
  mesh::clean(mesh, {.find_self_intersections = false});
  return mesh;
}

}  // namespace vesselmesh::synth
