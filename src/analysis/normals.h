// Per-vertex unit normals of a triangle surface.
//
// `quadric_fit` (default): in the frame of the Max normal below, a least-squares fit of the
// height z = a x^2 + b xy + c y^2 + d x + e y through the point to its neighbours (the 1-ring,
// or the 2-ring where the 1-ring has fewer than five points); the normal is the fitted patch's
// at the point. Exact for any quadratic patch whatever the triangulation, so its error falls
// as h^2 on irregular meshes, where every weighted average of face normals stays first order
// (measured on a jittered torus: 0.064 deg median error with Max weights at h = r/17, halving
// only with h; curvature from them does not converge). Falls back to the Max normal where the
// fit is ill-posed or would turn the normal by more than 30 degrees.
// `max`: N. Max, "Weights for computing vertex normals from facet normals", J. Graphics Tools
// 4(2), 1999: each face adds (e1 x e2) / (|e1|^2 |e2|^2), e1, e2 its edges from the point;
// exact on a sphere for any triangulation. This is what Rusinkiewicz's paper uses.
// `angle`: unit face normals times the face's angle at the point (Thuermer & Wuethrich 1998).
// `area`: face area vectors.
// Orientation follows the triangles (outward for a cleaned lumen). A point without a
// non-degenerate triangle gets the zero vector. Threaded (TBB), deterministic: each point
// sums its faces in index order.
#pragma once

#include "mesh/connectivity.h"
#include "mesh/trimesh.h"

#include <vector>

namespace vesselmesh::analysis {

enum class NormalMethod { quadric_fit, max, angle, area };

std::vector<Vec3> vertex_normals(const TriMesh& mesh, NormalMethod method = NormalMethod::quadric_fit);
// The same with the vertex-corner incidence (mesh::build_vertex_corners) already built.
std::vector<Vec3> vertex_normals(const TriMesh& mesh, const mesh::VertexTriangles& corners, NormalMethod method);

}  // namespace vesselmesh::analysis
