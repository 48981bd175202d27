// The error of linear interpolation on a surface, as a metric (issue 52, the flow-adapted mesh).
//
// Hessian recovery: at each point, in the tangent frame of its normal, a least-squares fit of
// f = a + b x + c y + d x^2 + e x y + g y^2 to the field at the point and at its neighbours (the
// 2-ring; the 3-ring where that has fewer than 9 points, as at an open end); the Hessian is the
// fitted patch's, [[2d, e], [e, 2g]]. Exact for a quadratic in the tangent coordinates whatever
// the triangulation (tested on a plane and along a cylinder's axis); second derivatives of a
// smooth field otherwise converge as h on irregular meshes. Where the fit is ill-posed (fewer
// than 6 points, or all on a line) the Hessian is zero there.
//
// The metric (Loseille & Alauzet, "Continuous mesh framework, part II", SIAM J. Numer. Anal. 49,
// 2011; Frey & Alauzet, CMAME 194, 2005): the P1 interpolation error of f on a triangle is
// bounded by the edges' lengths in |H| (H's eigenvalues taken absolute), so a mesh of unit edges
// in c |H| spreads the error evenly. Several fields (a vector's components, several saved times)
// are bounded together by the intersection of their |H|. The L^p norm of the error over the
// surface (dimension 2) is least, for a given number of triangles, with the metric
// det(|H|)^(-1 / (2 p + 2)) |H|, up to the constant that sets the count (the size field's
// target-triangle scaling). Units: 1 / (the mesh's length unit)^2 times the field's unit; only
// the ratios matter once the count sets the scale.
#pragma once

#include "mesh/point_graph.h"
#include "mesh/reporter.h"
#include "mesh/sym3.h"
#include "mesh/trimesh.h"

#include <vector>

namespace vesselmesh::sizing {

// Per point the recovered tangent Hessian of `field` (one value per point), as a 3D tensor
// whose normal direction is zero: P [[2d, e], [e, 2g]] P^T for P = [u, v] the tangent frame of
// `normals` (unit, one per point; zero where undefined: Hessian zero there).
std::vector<Sym3> recover_hessians(const TriMesh& mesh, const std::vector<double>& field,
                                   const std::vector<Vec3>& normals);

struct ErrorMetricOptions {
  // The L^p norm of the interpolation error to make least (>= 1; infinity: no det factor).
  double p = 2.0;
  // Eigenvalues of the intersected |H| below this fraction of the largest anywhere are raised to
  // it (a field linear along a direction asks no size there; the clamps of the size field bound
  // it).
  double floor = 1e-6;
};

// The intersection over `fields` of |H| (each recovered as above), floored, normalized for the
// L^p norm, and made SPD in 3D with the normal direction as fine as the finer tangent one.
// InputError when every field is linear everywhere (nothing to adapt to).
std::vector<Sym3> error_metric(const TriMesh& mesh, const std::vector<std::vector<double>>& fields,
                               const std::vector<Vec3>& normals,
                               const ErrorMetricOptions& options = {},
                               const Reporter& reporter = silent_reporter());

// The volume's counterpart (the flow kind's interior, issue 52). Per point of a volume mesh the
// Hessian of each field recovered by a least-squares fit of a full quadratic in 3D (10
// coefficients) to the field at the point and at its 2-ring in `graph` (exact for a quadratic
// whatever the cells; zero where the fit is ill-posed: fewer than 10 points or a degenerate
// spread). Then the isotropic sizes that make the L^p norm of the fields' P1 interpolation error
// over the volume least for a given number of points: the error on a cell of size h goes as
// rho h^2, rho the largest |eigenvalue| of any field's Hessian there, and with the count as the
// integral of h^-3 the optimum is h = rho^(-p / (2 p + 3)) (p infinite: rho^(-1/2), the error
// spread evenly), up to the constant that sets the count. rho is floored at `floor` times the
// largest anywhere (a field linear somewhere asks no size there). Units: the mesh's length to the
// power 2p / (2p + 3) times the fields' unit; only the ratios matter once the count sets the
// scale. InputError when every field is linear everywhere, or a field's size is not the points'.
std::vector<double> volume_error_sizes(const std::vector<Vec3>& points, const mesh::PointGraph& graph,
                                       const std::vector<std::vector<double>>& fields,
                                       const ErrorMetricOptions& options = {},
                                       const Reporter& reporter = silent_reporter());

// The recovered Hessian of one field at every point (as volume_error_sizes fits it).
std::vector<Sym3> recover_volume_hessians(const std::vector<Vec3>& points, const mesh::PointGraph& graph,
                                          const std::vector<double>& field);

}  // namespace vesselmesh::sizing
