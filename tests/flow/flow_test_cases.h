// The flow tests' shared cases: a straight pipe, a 180-degree bend and the FDA nozzle's sudden
// expansion as volume meshes, and a pipe-tagged case.
#pragma once

#include "flow/case.h"
#include "mesh/tetmesh.h"
#include "synth/shapes.h"

#include <string>

namespace vesselmesh::flow {

// A straight pipe along +z (mm) with a 4-layer boundary layer (or none), tagged wall / inlet
// (z = 0) / outlet_1, meshed the way `vesselmesh volume` does.
TetMesh pipe_volume(double radius, double length, double resolution, bool layer = true);

// A 180-degree bend (radius R mm, bend radius 6 mm, 8 mm straight before and after, 0.6 mm
// triangles) with two layers, its inlet the first end: the steady tests' convective case.
TetMesh bend_volume(double R);

// The FDA nozzle's sudden expansion (synth::nozzle: throat radius 2 mm, outlet 6 mm) with two
// layers, tagged as pipe_volume's.
TetMesh nozzle_volume(const synth::NozzleOptions& o);

// A pipe case: `time` is the [time] table's body, `inflow` the inlet's profile and flow keys.
FlowCase pipe_case(const std::string& time, const std::string& inflow, const std::string& path);

}  // namespace vesselmesh::flow
