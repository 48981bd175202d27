#include "synth/bifurcation.h"

#include "mesh/clean.h"
#include "mesh/connectivity.h"
#include "mesh/error.h"
#include "synth/implicit_surface.h"
#include "synth/plane_cut.h"
#include "synth/random.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace vesselmesh::synth {
namespace {

double distance_to_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

// Polynomial smooth minimum (Quilez): equals min(a, b) where |a - b| >= k.
double smooth_min(double a, double b, double k) {
  if (k <= 0.0) return std::min(a, b);
  const double h = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - h * h * k / 4.0;
}

Vec3 daughter_direction(const BifurcationOptions& o, int k) {
  const double a = o.angle_deg[k] * std::numbers::pi / 180.0 * (k == 0 ? 1.0 : -1.0);
  return Vec3(std::sin(a), 0.0, std::cos(a));
}

void validate(const BifurcationOptions& o) {
  for (double r : {o.radius, o.daughter_radius[0], o.daughter_radius[1], o.resolution})
    if (!(r > 0.0) || !std::isfinite(r)) throw OptionError("radii and resolution must be positive lengths");
  for (double a : o.angle_deg)
    if (!(a >= 5.0 && a <= 85.0)) throw OptionError(fmt::format("daughter angles must be in [5, 85] degrees, got {}", a));
  if (!(o.jitter >= 0.0 && o.jitter <= 0.45)) throw OptionError("jitter must be in [0, 0.45]");
  if (!(o.blend >= 0.0)) throw OptionError("the blend radius must not be negative");
  const double largest = std::max({o.radius, o.daughter_radius[0], o.daughter_radius[1]});
  if (o.resolution > 0.5 * std::min({o.radius, o.daughter_radius[0], o.daughter_radius[1]}))
    throw OptionError(fmt::format("resolution {} is too coarse for the smallest radius: use at most half of it",
                                  o.resolution));
  const double clear = 2.0 * largest + o.blend;
  if (o.parent_length < clear || o.daughter_length < clear)
    throw OptionError(fmt::format("parent and daughter lengths must be at least {:.3g} mm (twice the largest radius "
                                  "plus the blend) so that the ends are cut where the tubes are straight",
                                  clear));
  const Vec3 e1 = o.daughter_length * daughter_direction(o, 0), e2 = o.daughter_length * daughter_direction(o, 1);
  if ((e1 - e2).norm() < o.daughter_radius[0] + o.daughter_radius[1] + 2.0 * o.resolution)
    throw OptionError("the daughters overlap at their ends: widen the angles or lengthen them");
  const double triangles = 4.0 * std::numbers::pi * largest * (o.parent_length + 2 * o.daughter_length) /
                           (o.resolution * o.resolution);
  if (triangles > 5e7) throw OptionError("too many triangles: choose a coarser resolution");
}

}  // namespace

std::array<TubeEnd, 3> bifurcation_ends(const BifurcationOptions& o) {
  return {TubeEnd{Vec3(0.0, 0.0, -o.parent_length), Vec3(0.0, 0.0, -1.0), o.radius},
          TubeEnd{o.daughter_length * daughter_direction(o, 0), daughter_direction(o, 0), o.daughter_radius[0]},
          TubeEnd{o.daughter_length * daughter_direction(o, 1), daughter_direction(o, 1), o.daughter_radius[1]}};
}

TriMesh bifurcation(const BifurcationOptions& o) {
  validate(o);
  const double h = o.resolution;
  // Tubes run past their ends, so the cut meets them where they are straight.
  const std::array<Vec3, 3> tips = {Vec3(0.0, 0.0, -o.parent_length - 2.0 * o.radius),
                                    (o.daughter_length + 2.0 * o.daughter_radius[0]) * daughter_direction(o, 0),
                                    (o.daughter_length + 2.0 * o.daughter_radius[1]) * daughter_direction(o, 1)};
  const std::array<double, 3> radii = {o.radius, o.daughter_radius[0], o.daughter_radius[1]};
  const ImplicitFunction f = [&](const Vec3& p) {
    double d = distance_to_segment(p, tips[0], Vec3::Zero()) - radii[0];
    for (int k = 1; k < 3; ++k) d = smooth_min(d, distance_to_segment(p, Vec3::Zero(), tips[k]) - radii[k], o.blend);
    return d;
  };
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
  for (const Vec3& t : tips) lo = lo.cwiseMin(t), hi = hi.cwiseMax(t);
  const double margin = *std::max_element(radii.begin(), radii.end()) + o.blend + 2.0 * h;
  lo -= Vec3::Constant(margin);
  hi += Vec3::Constant(margin);

  const double dh = 1e-3 * h;  // finite-difference step of the gradient
  TriMesh mesh = polygonize(f, lo, hi, h);
  mesh::clean(mesh, {.merge_tolerance = 0.02, .find_self_intersections = false});
  for (int round = 0; round < 3; ++round) {  // marching cubes leaves slivers: smooth and flip
    relax_on_zero_set(mesh, f, dh, 5);
    flip_to_improve_angles(mesh);
  }
  relax_on_zero_set(mesh, f, dh, 5);
  for (const TubeEnd& end : bifurcation_ends(o)) {
    const CutPlane plane{.point = end.center, .normal = end.normal, .reach = 1.5 * end.radius};
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
    for (int e = 0; e < edges.num_edges(); ++e) {
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
