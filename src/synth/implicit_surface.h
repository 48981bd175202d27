// Surfaces given as the zero set of a function f (negative inside): polygonized on a grid by
// VTK's flying edges, then moved exactly onto f = 0 and relaxed along it for shape.
#pragma once

#include "mesh/trimesh.h"

#include <functional>
#include <span>

namespace vesselmesh::synth {

using ImplicitFunction = std::function<double(const Vec3&)>;

// Zero set of f sampled on a grid of `spacing` over the box [lo, hi] (f must be positive on
// the box's faces). Triangles face towards increasing f (outward for f < 0 inside). Points
// of the grid's triangulation are projected onto f = 0.
TriMesh polygonize(const ImplicitFunction& f, const Vec3& lo, const Vec3& hi, double spacing);

// Gradient of f by central differences of step h.
Vec3 gradient(const ImplicitFunction& f, const Vec3& p, double h);

// Newton steps along the gradient (central differences of step h) onto f = 0.
Vec3 project_to_zero_set(const ImplicitFunction& f, Vec3 p, double h);

// Tangential smoothing kept on f = 0: each free point moves halfway to its neighbours' mean
// within its tangent plane, then back onto the surface. `fixed` (may be empty) pins points.
void relax_on_zero_set(TriMesh& mesh, const ImplicitFunction& f, double h, int iterations,
                       std::span<const char> fixed = {});

// Flips edges where that raises the smaller angle of the two triangles, as long as the surface
// barely bends there (normals within `max_bend_deg`). Boundary edges stay. Returns the flips.
int flip_to_improve_angles(TriMesh& mesh, double max_bend_deg = 20.0);

}  // namespace vesselmesh::synth
