// Per-vertex curvature tensor, principal curvatures and directions of a triangle surface.
//
// Method: S. Rusinkiewicz, "Estimating curvatures and their derivatives on triangle meshes",
// 3DPVT 2004. Per triangle, the second fundamental form II (a symmetric 2x2 tensor in the
// triangle's plane) is fitted in the least-squares sense to the change of the vertex normals
// along its three edges: II e = dn for each edge e. Each triangle's tensor is turned into
// every corner's tangent plane (by the smallest rotation taking the triangle's normal to the
// vertex normal) and averaged with mixed Voronoi corner areas as weights (Meyer et al. 2002).
// The average is diagonalized per vertex. The fit differences vertex normals, so their accuracy
// is the method's: the default normals are second order (a local quadric fit, see
// analysis/normals.h), which makes the estimate converge on irregular meshes; the paper's Max
// weights (`normals = NormalMethod::max`) do not (jittered torus, 50k points: median error of
// H 1.4 % with Max normals, 0.17 % with fitted ones, 0.14 % with exact ones).
//
// Sign convention: with the surface oriented outward, curvature is positive where the surface
// bends away from its normal (convex). On an outward pipe of radius R: k2 = +1/R around it,
// k1 = 0 along it, H = 1/(2R); on a sphere k1 = k2 = +1/R. An inward surface flips the signs.
// Units: 1 / (the mesh's length unit). k1 <= k2 always; (dir1, dir2, normal) is a
// right-handed orthonormal frame.
//
// Open ends: boundary points use the triangles they have. Needles and flat triangles (smallest
// angle under about 2 degrees, as a plane cut leaves at an open end) are left out of the average:
// their fit is noise. Points without another triangle get zero curvature, and points without a
// non-degenerate triangle a zero normal and arbitrary directions too (never NaN).
// Linear time; threaded with TBB; the result does not depend on the thread count.
#pragma once

#include "analysis/normals.h"
#include "mesh/reporter.h"
#include "mesh/sym3.h"
#include "mesh/trimesh.h"

#include <vector>

namespace vesselmesh::analysis {

struct CurvatureOptions {
  NormalMethod normals = NormalMethod::quadric_fit;
  // Passes of area-weighted averaging of each vertex's tensor with its neighbours' (tensors
  // turned into the vertex's tangent plane first). 0: none, as in the paper.
  int smoothing_passes = 0;
};

struct CurvatureField {
  std::vector<double> k1, k2;  // k1 <= k2
  std::vector<Vec3> dir1, dir2, normal;

  int size() const { return static_cast<int>(k1.size()); }
  double mean(int v) const { return 0.5 * (k1[v] + k2[v]); }
  double gauss(int v) const { return k1[v] * k2[v]; }
  // T = P diag(k1, k2, 0) P^T with P = [dir1, dir2, normal]: what the anisotropic metric uses.
  Sym3 tensor(int v) const;
};

CurvatureField curvature(const TriMesh& mesh, const CurvatureOptions& options = {},
                         const Reporter& reporter = silent_reporter());

// The same with vertex normals given (unit, one per point; zero where undefined; `normals` in
// the options is not used), e.g. exact ones in tests or those of a smooth reconstruction.
CurvatureField curvature_from_normals(const TriMesh& mesh, std::vector<Vec3> normals,
                                     const CurvatureOptions& options = {},
                                     const Reporter& reporter = silent_reporter());

}  // namespace vesselmesh::analysis
