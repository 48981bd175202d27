// Riemannian metrics for mesh adaptation: symmetric positive definite 3x3 tensors M such that
// an edge e has length sqrt(e^T M e) "in the metric"; a mesh adapted to M has edges of unit
// metric length. An isotropic size h is M = I / h^2. Operations after P. Frey, F. Alauzet,
// "Anisotropic mesh adaptation for CFD computations", CMAME 194, 2005, and F. Alauzet, "Size
// gradation control of anisotropic meshes", Finite Elem. Anal. Des. 46, 2010.
#pragma once

#include "mesh/sym3.h"
#include "mesh/trimesh.h"

namespace vesselmesh::sizing {

// M = I / h^2.
Sym3 isotropic_metric(double h);

// M = P diag(1/h1^2, 1/h2^2, 1/h3^2) P^T with P = [d1, d2, d3] orthonormal.
Sym3 metric_from_sizes(const Vec3& d1, double h1, const Vec3& d2, double h2, const Vec3& d3, double h3);

// Length of e in metric m.
double metric_length(const Sym3& m, const Vec3& e);

// Length of the edge a-b whose end metrics are ma and mb, the size varying geometrically along
// it: (la - lb) / ln(la / lb) for the lengths la, lb of the edge in each end's metric.
double edge_length(const Vec3& a, const Vec3& b, const Sym3& ma, const Sym3& mb);

// Quality of triangle (a, b, c) in the mean of its corners' metrics: 4 sqrt(3) area / sum of
// squared edge lengths, all measured in that metric; 1 for the metric's equilateral triangle.
double triangle_quality(const Vec3& a, const Vec3& b, const Vec3& c, const Sym3& ma, const Sym3& mb, const Sym3& mc);

// The sizes (1 / sqrt of the eigenvalues), ascending, and their directions (columns).
void metric_sizes(const Sym3& m, Vec3& sizes, Eigen::Matrix3d& directions);

// The largest metric that is at least as fine as both in every direction (simultaneous
// reduction): the intersection M1 cap M2.
Sym3 intersect(const Sym3& a, const Sym3& b);

// Every size of m clamped to [hmin, hmax], directions kept.
Sym3 clamp_sizes(const Sym3& m, double hmin, double hmax);

// Every size multiplied by s (the metric divided by s^2).
Sym3 scale_sizes(const Sym3& m, double s);

// Matrix logarithm and exponential of SPD / symmetric tensors (through the eigenvalues), for
// log-Euclidean interpolation (V. Arsigny et al., "Log-Euclidean metrics for fast and simple
// calculus on diffusion tensors", MRM 56, 2006): exp(sum w_i log M_i) stays SPD.
Sym3 metric_log(const Sym3& m);
Sym3 metric_exp(const Sym3& log_m);
// exp(sum w_i log_i) for weights summing to 1.
Sym3 interpolate_logs(const Sym3* logs, const double* weights, int count);

// The metric restricted to the plane with unit normal n: sqrt of the determinant of its 2x2
// form in an orthonormal frame of the plane, i.e. 1 / (h_a h_b) for the in-plane sizes.
double tangent_density(const Sym3& m, const Vec3& n);

}  // namespace vesselmesh::sizing
