// A Y-shaped bifurcation: a parent pipe splitting into two daughters, smoothly blended at
// the junction, with three open ends cut normal to the vessels. Built as the zero set of a
// smooth union of tubes (distance to each axis segment minus its radius), polygonized,
// relaxed on the exact zero set and cut open. Lengths in mm.
//
// Geometry: the parent runs along +z from (0, 0, -parent_length) to the origin, where the
// daughters start, in the xz plane at +angle_1 (towards +x) and -angle_2 from +z.
// Labels: none. Ends: parent inlet, daughter 1, daughter 2 (bifurcation_ends()). Optionally an
// aneurysm at the apex.
#pragma once

#include "mesh/trimesh.h"
#include "synth/tubes.h"

#include <array>
#include <cstdint>

namespace vesselmesh::synth {

struct BifurcationOptions {
  double radius = 3.0;                              // parent
  std::array<double, 2> daughter_radius = {2.4, 2.4};  // Murray: 3 / 2^(1/3) = 2.38
  std::array<double, 2> angle_deg = {35.0, 35.0};
  double parent_length = 20.0;
  double daughter_length = 20.0;
  double blend = 1.5;  // smooth-union radius at the junction
  // A saccular aneurysm at the apex (a bifurcation aneurysm, where the parent's jet hits): a
  // sphere of this radius on the daughters' bisector, its centre 0.7 radii beyond the apex (the
  // point where the daughters' walls part), blended in as the tubes are. 0: none.
  double aneurysm_radius = 0.0;
  double resolution = 0.5;
  double jitter = 0.0;
  uint64_t seed = 1;
};

TriMesh bifurcation(const BifurcationOptions& options);
// The aneurysm's centre (with aneurysm_radius > 0).
Vec3 aneurysm_center(const BifurcationOptions& options);
std::array<TubeEnd, 3> bifurcation_ends(const BifurcationOptions& options);

}  // namespace vesselmesh::synth
