// Analytic test shapes whose geometry is known exactly: every point lies on the analytic
// surface (also after jitter), triangles face outward. Lengths in mm.
//
// `resolution` is the target edge length; `jitter` moves every point along the surface by a
// random fraction (up to `jitter`) of its local grid step, seeded by `seed`, to make the
// triangulation irregular. These are the fixtures of the curvature, centerline and flow tests.
#pragma once

#include "mesh/trimesh.h"

#include <cstdint>
#include <utility>

namespace vesselmesh::synth {

// Geodesic sphere: an icosahedron's faces subdivided and projected onto the sphere.
struct SphereOptions {
  double radius = 5.0;
  Vec3 center = Vec3::Zero();
  double resolution = 0.5;
  double jitter = 0.0;
  uint64_t seed = 1;
};
TriMesh sphere(const SphereOptions& options);

// Ellipsoid x²/a² + y²/b² + z²/c² = 1: a geodesic sphere scaled along the axes.
struct EllipsoidOptions {
  Vec3 semi_axes = Vec3(6.0, 4.0, 3.0);
  double resolution = 0.4;
  double jitter = 0.0;
  uint64_t seed = 1;
};
TriMesh ellipsoid(const EllipsoidOptions& options);

// Straight pipe along +z from z = 0 to z = length, open ends unless `capped` (flat caps
// triangulated in rings, no fans). Labels when capped: 1 wall, 2 cap at z = 0, 3 cap at z = length.
struct CylinderOptions {
  double radius = 3.0;
  double length = 30.0;
  double resolution = 0.5;
  bool capped = false;
  bool random_diagonals = true;
  double jitter = 0.0;
  uint64_t seed = 1;
};
TriMesh cylinder(const CylinderOptions& options);

// Torus about the z axis: ((R + r cos v) cos u, (R + r cos v) sin u, r sin v).
struct TorusOptions {
  double major_radius = 10.0;
  double minor_radius = 3.0;
  double resolution = 0.5;
  bool random_diagonals = true;
  double jitter = 0.0;
  uint64_t seed = 1;
};
TriMesh torus(const TorusOptions& options);

// Bent pipe in the xy plane: a straight inlet along +y ending at the origin, an arc of radius
// `bend_radius` about (bend_radius, 0, 0) turning toward +x by `angle_deg`, a straight
// outlet. Open ends. Its centerline is bend_centerline().
struct BendOptions {
  double radius = 3.0;
  double bend_radius = 15.0;
  double angle_deg = 90.0;
  double inlet_length = 10.0;
  double outlet_length = 10.0;
  double resolution = 0.5;
  bool random_diagonals = true;
  double jitter = 0.0;
  uint64_t seed = 1;
};
TriMesh bend(const BendOptions& options);

// The bend's centerline at arc length s in [0, inlet + bend_radius * angle + outlet]:
// position and unit tangent.
struct CenterlinePoint {
  Vec3 position;
  Vec3 tangent;
};
CenterlinePoint bend_centerline(const BendOptions& options, double s);
double bend_length(const BendOptions& options);

// The FDA benchmark nozzle (Hariharan et al. 2011, J Biomech Eng 133:041002), a surface of
// revolution about the z axis with the data's coordinates: in the sudden-expansion orientation
// the flow (+z) runs through the inlet pipe, a cone of `cone_half_angle_deg` narrowing from
// `radius` to `throat_radius`, the throat (z from -throat_length to 0), an abrupt step back to
// `radius` at z = 0 and the outlet pipe. The conical-diffuser orientation is its mirror image
// (z -> -z): the step at z = 0 leads into the throat, the cone widens after it. Open ends at
// the lowest z (the inlet) and the highest; sharp creases at the throat's ends are kept exact
// (a ring of points on each). Every point lies on the profile, whatever the jitter (none:
// rings are regular and staggered; jitter is refused).
enum class NozzleOrientation { sudden_expansion, conical_diffuser };
struct NozzleOptions {
  double radius = 6.0;
  double throat_radius = 2.0;
  double throat_length = 40.0;
  double cone_half_angle_deg = 10.0;
  double inlet_length = 40.0;   // straight pipe before the first change of radius
  double outlet_length = 120.0;  // straight pipe after the last
  NozzleOrientation orientation = NozzleOrientation::sudden_expansion;
  double resolution = 0.5;
  double jitter = 0.0;
  uint64_t seed = 1;
};
TriMesh nozzle(const NozzleOptions& options);

// The nozzle's wall radius at axial position z (where the step is, z = 0, the larger one), and
// the axial extent [z_inlet, z_outlet] of the surface.
double nozzle_radius(const NozzleOptions& options, double z);
std::pair<double, double> nozzle_extent(const NozzleOptions& options);

}  // namespace vesselmesh::synth
