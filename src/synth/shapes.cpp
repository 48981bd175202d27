#include "synth/shapes.h"

#include "mesh/clean.h"
#include "mesh/error.h"
#include "mesh/merge_points.h"
#include "synth/parametric.h"
#include "synth/random.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace vesselmesh::synth {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kMaxTriangles = 5e7;

void require_positive(double value, const char* name) {
  if (!(value > 0.0) || !std::isfinite(value))
    throw OptionError(fmt::format("{} must be a positive length, got {}", name, value));
}

void require_jitter(double jitter) {
  if (!(jitter >= 0.0 && jitter <= 0.45))
    throw OptionError(fmt::format("jitter must be in [0, 0.45] (a fraction of the edge length), got {}", jitter));
}

void require_count(double triangles) {
  if (triangles > kMaxTriangles)
    throw OptionError(fmt::format("about {:.3g} triangles: choose a coarser resolution (at most {:.0g})",
                                  triangles, kMaxTriangles));
}

int cells(double length, double resolution, int minimum) {
  return std::max(minimum, static_cast<int>(std::ceil(length / resolution - 1e-9)));
}

// Construction orientation is checked, not assumed: a tube or closed shape faces outward.
void face_outward(TriMesh& mesh) {
  if (mesh::signed_volume(mesh) < 0.0)
    for (Triangle& f : mesh.triangles) std::swap(f[1], f[2]);
}

// Unit geodesic sphere of frequency n, with jitter along the sphere.
TriMesh unit_geodesic_sphere(int n, double jitter, uint64_t seed) {
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  const std::vector<Vec3> ico = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                                 {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  const int faces[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                            {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                            {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                            {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  TriMesh mesh;
  for (const auto& face : faces) {
    const Vec3 a = ico[face[0]].normalized(), b = ico[face[1]].normalized(), c = ico[face[2]].normalized();
    const int base = mesh.num_points();
    auto id = [&](int i, int j) { return base + j * (n + 1) - j * (j - 1) / 2 + i; };  // i + j <= n
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i + j <= n; ++i)
        mesh.points.push_back((a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n)).normalized());
    for (int j = 0; j < n; ++j)
      for (int i = 0; i + j < n; ++i) {
        mesh.triangles.push_back({id(i, j), id(i + 1, j), id(i, j + 1)});
        if (i + j + 1 < n) mesh.triangles.push_back({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      }
  }
  // Points on the icosahedron's edges were made once per face: merge them.
  const std::vector<double> tolerance(mesh.points.size(), 1e-9);
  mesh::remap_triangles(mesh.triangles, mesh::merge_close_points(mesh.points, tolerance));
  face_outward(mesh);
  if (jitter > 0.0) {
    const double step = 1.1 / n;  // geodesic edge length on the unit sphere, about
    Random random(seed);
    for (Vec3& p : mesh.points) {
      const Vec3 t1 = p.unitOrthogonal(), t2 = p.cross(t1);
      const double angle = random.uniform(0.0, 2.0 * kPi), amount = jitter * step * random.uniform();
      p = (p + amount * (std::cos(angle) * t1 + std::sin(angle) * t2)).normalized();
    }
  }
  return mesh;
}

int sphere_frequency(double radius, double resolution) {
  require_positive(radius, "radius");
  require_positive(resolution, "resolution");
  const int n = cells(1.0515 * radius, resolution, 1);
  require_count(20.0 * n * n);
  return n;
}

// Triangles between two concentric rings of point indices, sorted by angle (zipper).
void zip_rings(TriMesh& mesh, const std::vector<int>& inner, const std::vector<double>& inner_angle,
               const std::vector<int>& outer, const std::vector<double>& outer_angle) {
  const size_t na = inner.size(), nb = outer.size();
  auto angle_a = [&](size_t i) { return inner_angle[i % na] + (i >= na ? 2 * kPi : 0.0); };
  auto angle_b = [&](size_t j) { return outer_angle[j % nb] + (j >= nb ? 2 * kPi : 0.0); };
  for (size_t i = 0, j = 0; i < na || j < nb;) {
    const bool advance_outer = i == na || (j < nb && angle_b(j + 1) < angle_a(i + 1));
    if (advance_outer) {
      mesh.triangles.push_back({inner[i % na], outer[j % nb], outer[(j + 1) % nb]});
      ++j;
    } else {
      mesh.triangles.push_back({inner[i % na], outer[j % nb], inner[(i + 1) % na]});
      ++i;
    }
  }
}

// A flat disk cap at height z closing the ring `rim` (angles 2*pi*i/n), in rings of points.
void add_cap(TriMesh& mesh, const std::vector<int>& rim, double radius, double z, double resolution,
             int label, double outward_z) {
  const size_t first_triangle = mesh.triangles.size();
  const int rings = cells(radius, resolution, 1);
  std::vector<int> outer = rim;
  std::vector<double> outer_angle(rim.size());
  for (size_t i = 0; i < rim.size(); ++i) outer_angle[i] = 2 * kPi * i / rim.size();
  for (int k = rings - 1; k >= 1; --k) {
    const double r = radius * k / rings;
    const int n = std::max(6, static_cast<int>(std::lround(rim.size() * double(k) / rings)));
    const double offset = (k % 2) * kPi / n;  // stagger neighbouring rings
    std::vector<int> ring(n);
    std::vector<double> angle(n);
    for (int i = 0; i < n; ++i) {
      angle[i] = offset + 2 * kPi * i / n;
      ring[i] = mesh.num_points();
      mesh.points.emplace_back(r * std::cos(angle[i]), r * std::sin(angle[i]), z);
    }
    zip_rings(mesh, ring, angle, outer, outer_angle);
    outer = std::move(ring);
    outer_angle = std::move(angle);
  }
  const int centre = mesh.num_points();
  mesh.points.emplace_back(0.0, 0.0, z);
  for (size_t i = 0; i < outer.size(); ++i)
    mesh.triangles.push_back({centre, outer[i], outer[(i + 1) % outer.size()]});
  for (size_t t = first_triangle; t < mesh.triangles.size(); ++t) {
    Triangle& f = mesh.triangles[t];
    const double nz = (mesh.points[f[1]] - mesh.points[f[0]]).cross(mesh.points[f[2]] - mesh.points[f[0]]).z();
    if (nz * outward_z < 0.0) std::swap(f[1], f[2]);
  }
  mesh.labels.resize(mesh.triangles.size(), label);
}

}  // namespace

TriMesh sphere(const SphereOptions& o) {
  require_jitter(o.jitter);
  TriMesh mesh = unit_geodesic_sphere(sphere_frequency(o.radius, o.resolution), o.jitter, o.seed);
  for (Vec3& p : mesh.points) p = o.center + o.radius * p;
  return mesh;
}

TriMesh ellipsoid(const EllipsoidOptions& o) {
  require_jitter(o.jitter);
  for (int i = 0; i < 3; ++i) require_positive(o.semi_axes[i], "semi-axis");
  const double largest = o.semi_axes.maxCoeff();
  TriMesh mesh = unit_geodesic_sphere(sphere_frequency(largest, o.resolution), o.jitter, o.seed);
  for (Vec3& p : mesh.points) p = p.cwiseProduct(o.semi_axes);
  return mesh;
}

TriMesh cylinder(const CylinderOptions& o) {
  require_positive(o.radius, "radius");
  require_positive(o.length, "length");
  require_positive(o.resolution, "resolution");
  require_jitter(o.jitter);
  const int around = cells(2 * kPi * o.radius, o.resolution, 8);
  const int along = cells(o.length, o.resolution * std::sqrt(3.0) / 2.0, 1);
  require_count(2.0 * around * along);
  ParametricGrid grid{.position = [&](double t, double z) { return Vec3(o.radius * std::cos(t), o.radius * std::sin(t), z); },
                      .u0 = 0.0, .u1 = 2 * kPi, .v0 = 0.0, .v1 = o.length,
                      .nu = around, .nv = along, .periodic_u = true, .periodic_v = false};
  TriMesh mesh = mesh_parametric(grid, {.random_diagonals = o.random_diagonals, .jitter = o.jitter, .seed = o.seed});
  if (!o.capped) return mesh;
  mesh.labels.assign(mesh.triangles.size(), 1);
  std::vector<int> bottom(around), top(around);
  for (int i = 0; i < around; ++i) bottom[i] = i, top[i] = along * around + i;
  // The rims must sit exactly at their angles for the ring caps: undo jitter along the rim.
  for (int i = 0; i < around; ++i) {
    const double t = 2 * kPi * i / around;
    mesh.points[bottom[i]] = Vec3(o.radius * std::cos(t), o.radius * std::sin(t), 0.0);
    mesh.points[top[i]] = Vec3(o.radius * std::cos(t), o.radius * std::sin(t), o.length);
  }
  add_cap(mesh, bottom, o.radius, 0.0, o.resolution, 2, -1.0);
  add_cap(mesh, top, o.radius, o.length, o.resolution, 3, +1.0);
  return mesh;
}

TriMesh torus(const TorusOptions& o) {
  require_positive(o.major_radius, "major radius");
  require_positive(o.minor_radius, "minor radius");
  require_positive(o.resolution, "resolution");
  require_jitter(o.jitter);
  if (o.minor_radius >= o.major_radius)
    throw OptionError(fmt::format("the minor radius ({}) must be smaller than the major radius ({}): the "
                                  "torus would intersect itself",
                                  o.minor_radius, o.major_radius));
  const int around_axis = cells(2 * kPi * (o.major_radius + o.minor_radius), o.resolution, 8);
  const int around_tube = cells(2 * kPi * o.minor_radius, o.resolution, 8);
  require_count(2.0 * around_axis * around_tube);
  const double R = o.major_radius, r = o.minor_radius;
  ParametricGrid grid{.position = [&](double u, double v) {
                        return Vec3((R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v));
                      },
                      .u0 = 0.0, .u1 = 2 * kPi, .v0 = 0.0, .v1 = 2 * kPi,
                      .nu = around_axis, .nv = around_tube, .periodic_u = true, .periodic_v = true};
  return mesh_parametric(grid, {.random_diagonals = o.random_diagonals, .jitter = o.jitter, .seed = o.seed});
}

double bend_length(const BendOptions& o) {
  return o.inlet_length + o.bend_radius * o.angle_deg * kPi / 180.0 + o.outlet_length;
}

CenterlinePoint bend_centerline(const BendOptions& o, double s) {
  const double arc = o.bend_radius * o.angle_deg * kPi / 180.0;
  const double phi_end = o.angle_deg * kPi / 180.0;
  if (s <= o.inlet_length) return {Vec3(0.0, s - o.inlet_length, 0.0), Vec3(0.0, 1.0, 0.0)};
  if (s <= o.inlet_length + arc) {
    const double phi = (s - o.inlet_length) / o.bend_radius;
    return {Vec3(o.bend_radius * (1.0 - std::cos(phi)), o.bend_radius * std::sin(phi), 0.0),
            Vec3(std::sin(phi), std::cos(phi), 0.0)};
  }
  const Vec3 end(o.bend_radius * (1.0 - std::cos(phi_end)), o.bend_radius * std::sin(phi_end), 0.0);
  const Vec3 tangent(std::sin(phi_end), std::cos(phi_end), 0.0);
  return {end + (s - o.inlet_length - arc) * tangent, tangent};
}

TriMesh bend(const BendOptions& o) {
  require_positive(o.radius, "radius");
  require_positive(o.resolution, "resolution");
  require_jitter(o.jitter);
  if (!(o.bend_radius > o.radius))
    throw OptionError(fmt::format("the bend radius ({}) must be larger than the pipe radius ({})", o.bend_radius, o.radius));
  if (!(o.angle_deg > 0.0 && o.angle_deg <= 180.0))
    throw OptionError(fmt::format("the bend angle must be in (0, 180] degrees, got {}", o.angle_deg));
  if (!(o.inlet_length >= 0.0 && o.outlet_length >= 0.0))
    throw OptionError("inlet and outlet lengths must not be negative");
  const double length = bend_length(o);
  const int around = cells(2 * kPi * o.radius, o.resolution, 8);
  // Steps along the axis sized for the outer side of the bend, where the wall is longest.
  const int along = cells(length * (1.0 + o.radius / o.bend_radius), o.resolution * std::sqrt(3.0) / 2.0, 2);
  require_count(2.0 * around * along);
  const Vec3 binormal(0.0, 0.0, 1.0);
  ParametricGrid grid{.position = [&](double t, double s) {
                        const CenterlinePoint c = bend_centerline(o, s);
                        const Vec3 normal = c.tangent.cross(binormal);
                        return Vec3(c.position + o.radius * (std::cos(t) * normal + std::sin(t) * binormal));
                      },
                      .u0 = 0.0, .u1 = 2 * kPi, .v0 = 0.0, .v1 = length,
                      .nu = around, .nv = along, .periodic_u = true, .periodic_v = false};
  TriMesh mesh = mesh_parametric(grid, {.random_diagonals = o.random_diagonals, .jitter = o.jitter, .seed = o.seed});
  face_outward(mesh);
  return mesh;
}

namespace {

// The nozzle's profile in the sudden-expansion orientation, (z, r) from the inlet to the outlet,
// with `before` and `after` the straight pipes' lengths; zero-length pieces left out.
std::vector<std::pair<double, double>> sudden_expansion_profile(const NozzleOptions& o, double before, double after) {
  const double cone = (o.radius - o.throat_radius) / std::tan(o.cone_half_angle_deg * kPi / 180.0);
  const std::pair<double, double> corners[] = {{-(o.throat_length + cone + before), o.radius},
                                               {-(o.throat_length + cone), o.radius},
                                               {-o.throat_length, o.throat_radius},
                                               {0.0, o.throat_radius},
                                               {0.0, o.radius},
                                               {after, o.radius}};
  std::vector<std::pair<double, double>> profile;
  for (const auto& corner : corners)
    if (profile.empty() || corner != profile.back()) profile.push_back(corner);
  return profile;
}

// The profile of the nozzle as built, (z, r) in order of the inlet to the outlet.
std::vector<std::pair<double, double>> nozzle_profile(const NozzleOptions& o) {
  require_positive(o.radius, "radius");
  require_positive(o.throat_radius, "throat radius");
  require_positive(o.throat_length, "throat length");
  if (!(o.throat_radius < o.radius))
    throw OptionError(fmt::format("the throat radius ({}) must be smaller than the pipe radius ({})", o.throat_radius,
                                  o.radius));
  if (!(o.cone_half_angle_deg > 0.0 && o.cone_half_angle_deg < 90.0))
    throw OptionError(fmt::format("the cone's half angle must be in (0, 90) degrees, got {}", o.cone_half_angle_deg));
  if (!(o.inlet_length >= 0.0 && o.outlet_length >= 0.0))
    throw OptionError("inlet and outlet lengths must not be negative");
  if (o.orientation == NozzleOrientation::sudden_expansion)
    return sudden_expansion_profile(o, o.inlet_length, o.outlet_length);
  // The conical diffuser is the mirror image: its inlet pipe is the sudden expansion's outlet.
  std::vector<std::pair<double, double>> profile = sudden_expansion_profile(o, o.outlet_length, o.inlet_length);
  std::reverse(profile.begin(), profile.end());
  for (auto& [z, r] : profile) z = -z;
  return profile;
}

}  // namespace

std::pair<double, double> nozzle_extent(const NozzleOptions& o) {
  const auto profile = nozzle_profile(o);
  return {profile.front().first, profile.back().first};
}

double nozzle_radius(const NozzleOptions& o, double z) {
  const auto profile = nozzle_profile(o);
  double radius = 0.0;  // the largest of the pieces that hold z: the step's plane gives the pipe's
  for (size_t i = 0; i + 1 < profile.size(); ++i) {
    const auto [z0, r0] = profile[i];
    const auto [z1, r1] = profile[i + 1];
    if (z < z0 || z > z1) continue;
    radius = std::max(radius, z1 > z0 ? r0 + (r1 - r0) * (z - z0) / (z1 - z0) : std::max(r0, r1));
  }
  return radius;
}

TriMesh nozzle(const NozzleOptions& o) {
  require_positive(o.resolution, "resolution");
  if (o.jitter != 0.0)
    throw OptionError("the nozzle takes no jitter: its rings stay on the profile's creases (remesh it instead)");
  const auto profile = nozzle_profile(o);
  // Samples along the profile, a ring of points at each: the corners are samples.
  std::vector<std::pair<double, double>> samples = {profile.front()};
  double triangles = 0.0;
  for (size_t i = 0; i + 1 < profile.size(); ++i) {
    const auto [z0, r0] = profile[i];
    const auto [z1, r1] = profile[i + 1];
    const int steps = cells(std::hypot(z1 - z0, r1 - r0), o.resolution * std::sqrt(3.0) / 2.0, 1);
    for (int k = 1; k <= steps; ++k) {
      const double t = double(k) / steps;
      samples.emplace_back(z0 + t * (z1 - z0), r0 + t * (r1 - r0));
      triangles += 4.0 * kPi * std::max(r0, r1) / o.resolution;
    }
  }
  require_count(triangles);
  TriMesh mesh;
  std::vector<int> previous, ring;
  std::vector<double> previous_angle, angle;
  for (size_t k = 0; k < samples.size(); ++k) {
    const auto [z, r] = samples[k];
    const int n = cells(2 * kPi * r, o.resolution, 8);
    const double offset = (k % 2) * kPi / n;  // stagger neighbouring rings
    ring.resize(n);
    angle.resize(n);
    for (int i = 0; i < n; ++i) {
      angle[i] = offset + 2 * kPi * i / n;
      ring[i] = mesh.num_points();
      mesh.points.emplace_back(r * std::cos(angle[i]), r * std::sin(angle[i]), z);
    }
    if (k > 0) zip_rings(mesh, previous, previous_angle, ring, angle);
    std::swap(previous, ring);
    std::swap(previous_angle, angle);
  }
  // The zipper's triangles share one orientation: outward if they face away from the axis (the
  // step's plane, facing along it, has no say).
  double away = 0.0;
  for (const Triangle& f : mesh.triangles) {
    const Vec3 a = mesh.points[f[0]], b = mesh.points[f[1]], c = mesh.points[f[2]];
    const Vec3 centre = (a + b + c) / 3.0;
    away += (b - a).cross(c - a).dot(Vec3(centre.x(), centre.y(), 0.0));
  }
  if (away < 0.0)
    for (Triangle& t : mesh.triangles) std::swap(t[1], t[2]);
  return mesh;
}

}  // namespace vesselmesh::synth
