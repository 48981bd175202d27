// Exact principal curvatures of the analytic test shapes, from their implicit equations
// F(x) = 0 (F < 0 inside): with n = grad F / |grad F| and P = I - n n^T, the shape operator is
// P Hess(F) P / |grad F| on the tangent plane; its eigenpairs are the principal curvatures
// (positive where convex, for outward normals) and directions.
#pragma once

#include "analysis/curvature.h"
#include "mesh/trimesh.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

namespace vesselmesh::test {

struct Principal {
  double k1 = 0.0, k2 = 0.0;  // k1 <= k2
  Vec3 d1, d2, normal;
};

inline Principal principal_from_implicit(const Vec3& grad, const Eigen::Matrix3d& hessian) {
  Principal p;
  const double g = grad.norm();
  p.normal = grad / g;
  const Vec3 t1 = p.normal.unitOrthogonal(), t2 = p.normal.cross(t1);
  const Eigen::Matrix3d w = hessian / g;
  Eigen::Matrix2d m;
  m << t1.dot(w * t1), t1.dot(w * t2), t2.dot(w * t1), t2.dot(w * t2);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(m);  // ascending
  p.k1 = eig.eigenvalues()(0);
  p.k2 = eig.eigenvalues()(1);
  p.d1 = (eig.eigenvectors()(0, 0) * t1 + eig.eigenvectors()(1, 0) * t2).normalized();
  p.d2 = (eig.eigenvectors()(0, 1) * t1 + eig.eigenvectors()(1, 1) * t2).normalized();
  return p;
}

inline Principal sphere_curvature(const Vec3& x) {
  return principal_from_implicit(2.0 * x, 2.0 * Eigen::Matrix3d::Identity());
}

// Cylinder about the z axis.
inline Principal cylinder_curvature(const Vec3& x) {
  return principal_from_implicit(Vec3(2 * x.x(), 2 * x.y(), 0.0), Eigen::Vector3d(2, 2, 0).asDiagonal());
}

inline Principal ellipsoid_curvature(const Vec3& x, const Vec3& axes) {
  const Vec3 a2 = axes.cwiseProduct(axes);
  return principal_from_implicit(2.0 * x.cwiseQuotient(a2), Eigen::Vector3d(2.0 * a2.cwiseInverse()).asDiagonal());
}

// Torus about the z axis: (sqrt(x^2 + y^2) - R)^2 + z^2 - r^2 = 0.
inline Principal torus_curvature(const Vec3& x, double major) {
  const double rho = std::hypot(x.x(), x.y()), q = rho - major;
  const Vec3 grad(2 * q * x.x() / rho, 2 * q * x.y() / rho, 2 * x.z());
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
  const double r3 = rho * rho * rho;
  h(0, 0) = 2 * (x.x() * x.x() / (rho * rho) + q * x.y() * x.y() / r3);
  h(1, 1) = 2 * (x.y() * x.y() / (rho * rho) + q * x.x() * x.x() / r3);
  h(0, 1) = h(1, 0) = 2 * (x.x() * x.y() / (rho * rho) - q * x.x() * x.y() / r3);
  h(2, 2) = 2;
  return principal_from_implicit(grad, h);
}

// Error figures of an estimate against the exact values, over the selected points.
struct CurvatureErrors {
  double h_median = 0.0;          // |H - H*| / |H*|
  double k1_median = 0.0, k2_median = 0.0;  // |k - k*| / max(|k1*|, |k2*|)
  double k1_p95 = 0.0, k2_p95 = 0.0;
  double direction_median_deg = 0.0;  // dir1 against d1*, where |k1* - k2*| > 10 % of |k2*|
  int direction_points = 0;
  bool finite = true;
};

inline double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const size_t i = std::min(v.size() - 1, static_cast<size_t>(q * static_cast<double>(v.size())));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(i), v.end());
  return v[i];
}

inline CurvatureErrors curvature_errors(const TriMesh& mesh, const analysis::CurvatureField& field,
                                        const std::function<Principal(const Vec3&)>& exact,
                                        const std::vector<char>& skip = {}) {
  CurvatureErrors e;
  std::vector<double> h, k1, k2, angle;
  for (int v = 0; v < mesh.num_points(); ++v) {
    e.finite = e.finite && std::isfinite(field.k1[v]) && std::isfinite(field.k2[v]) && field.dir1[v].allFinite();
    if (!skip.empty() && skip[v]) continue;
    const Principal p = exact(mesh.points[v]);
    const double scale = std::max(std::abs(p.k1), std::abs(p.k2));
    const double hx = 0.5 * (p.k1 + p.k2);
    h.push_back(std::abs(field.mean(v) - hx) / std::abs(hx));
    k1.push_back(std::abs(field.k1[v] - p.k1) / scale);
    k2.push_back(std::abs(field.k2[v] - p.k2) / scale);
    if (std::abs(p.k1 - p.k2) > 0.1 * std::abs(p.k2))
      angle.push_back(std::acos(std::min(1.0, std::abs(field.dir1[v].dot(p.d1)))) * 180.0 / M_PI);
  }
  e.h_median = quantile(h, 0.5);
  e.k1_median = quantile(k1, 0.5);
  e.k2_median = quantile(k2, 0.5);
  e.k1_p95 = quantile(k1, 0.95);
  e.k2_p95 = quantile(k2, 0.95);
  e.direction_median_deg = quantile(angle, 0.5);
  e.direction_points = static_cast<int>(angle.size());
  return e;
}

}  // namespace vesselmesh::test
