// Triangulated parametric surfaces: a regular (u, v) grid mapped through x(u, v), each grid
// cell split along one of its diagonals, optionally jittered along the surface.
#pragma once

#include "mesh/trimesh.h"

#include <cstdint>
#include <functional>

namespace vesselmesh::synth {

struct ParametricGrid {
  std::function<Vec3(double u, double v)> position;
  double u0 = 0.0, u1 = 1.0, v0 = 0.0, v1 = 1.0;
  int nu = 1, nv = 1;  // cells along u and v
  bool periodic_u = false, periodic_v = false;
};

struct GridOptions {
  bool random_diagonals = true;  // else alternating diagonals
  // Each point moves by up to `jitter` of its grid step, in a random direction of the (u, v)
  // plane; points on an open edge of the grid move along that edge only. Stays on the surface.
  double jitter = 0.0;
  uint64_t seed = 1;
};

// Triangles follow the right-hand rule about du x dv.
TriMesh mesh_parametric(const ParametricGrid& grid, const GridOptions& options);

}  // namespace vesselmesh::synth
