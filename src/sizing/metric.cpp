#include "sizing/metric.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace vesselmesh::sizing {

Sym3 isotropic_metric(double h) {
  const double l = 1.0 / (h * h);
  return {{l, 0.0, 0.0, l, 0.0, l}};
}

Sym3 metric_from_sizes(const Vec3& d1, double h1, const Vec3& d2, double h2, const Vec3& d3, double h3) {
  return Sym3::from_matrix(d1 * d1.transpose() / (h1 * h1) + d2 * d2.transpose() / (h2 * h2) +
                           d3 * d3.transpose() / (h3 * h3));
}

double metric_length(const Sym3& m, const Vec3& e) { return std::sqrt(std::max(0.0, m.form(e, e))); }

double edge_length(const Vec3& a, const Vec3& b, const Sym3& ma, const Sym3& mb) {
  const Vec3 e = b - a;
  const double la = metric_length(ma, e), lb = metric_length(mb, e);
  if (std::abs(la - lb) <= 1e-6 * std::max(la, lb)) return 0.5 * (la + lb);
  return (la - lb) / std::log(la / lb);
}

double triangle_quality(const Vec3& a, const Vec3& b, const Vec3& c, const Sym3& ma, const Sym3& mb, const Sym3& mc) {
  Sym3 m;
  for (int i = 0; i < 6; ++i) m.v[i] = (ma.v[i] + mb.v[i] + mc.v[i]) / 3.0;
  const Vec3 e1 = b - a, e2 = c - a, e3 = c - b;
  const double g11 = m.form(e1, e1), g12 = m.form(e1, e2), g22 = m.form(e2, e2), g33 = m.form(e3, e3);
  const double sum = g11 + g22 + g33;
  if (!(sum > 0.0)) return 0.0;
  return 2.0 * std::sqrt(3.0) * std::sqrt(std::max(0.0, g11 * g22 - g12 * g12)) / sum;
}

void metric_sizes(const Sym3& m, Vec3& sizes, Eigen::Matrix3d& directions) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(m.matrix());
  const Eigen::Vector3d l = eig.eigenvalues();  // ascending eigenvalues: descending sizes
  for (int i = 0; i < 3; ++i) sizes[i] = 1.0 / std::sqrt(std::max(l[2 - i], 1e-300));
  for (int i = 0; i < 3; ++i) directions.col(i) = eig.eigenvectors().col(2 - i);
}

Sym3 intersect(const Sym3& a, const Sym3& b) {
  // Simultaneous reduction: the eigenvectors P of A^-1 B make both diagonal; keep, along each,
  // the larger of the two quadratic forms.
  const Eigen::Matrix3d ma = a.matrix(), mb = b.matrix();
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix3d> eig(mb, ma);  // B v = l A v
  if (eig.info() != Eigen::Success) return a;
  const Eigen::Matrix3d p = eig.eigenvectors();
  Eigen::Vector3d l;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d v = p.col(i);
    l[i] = std::max(v.dot(ma * v), v.dot(mb * v));
  }
  const Eigen::Matrix3d p_inv = p.inverse();
  return Sym3::from_matrix(p_inv.transpose() * l.asDiagonal() * p_inv);
}

Sym3 clamp_sizes(const Sym3& m, double hmin, double hmax) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(m.matrix());
  Eigen::Vector3d l = eig.eigenvalues();
  const double lo = 1.0 / (hmax * hmax), hi = 1.0 / (hmin * hmin);
  for (int i = 0; i < 3; ++i) l[i] = std::clamp(l[i], lo, hi);
  return Sym3::from_matrix(eig.eigenvectors() * l.asDiagonal() * eig.eigenvectors().transpose());
}

Sym3 scale_sizes(const Sym3& m, double s) {
  Sym3 out = m;
  for (double& x : out.v) x /= s * s;
  return out;
}

namespace {

template <typename F>
Sym3 apply_to_eigenvalues(const Sym3& m, F f) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(m.matrix());
  Eigen::Vector3d l = eig.eigenvalues();
  for (int i = 0; i < 3; ++i) l[i] = f(l[i]);
  return Sym3::from_matrix(eig.eigenvectors() * l.asDiagonal() * eig.eigenvectors().transpose());
}

}  // namespace

Sym3 metric_log(const Sym3& m) {
  return apply_to_eigenvalues(m, [](double l) { return std::log(std::max(l, 1e-300)); });
}

Sym3 metric_exp(const Sym3& log_m) {
  return apply_to_eigenvalues(log_m, [](double l) { return std::exp(l); });
}

Sym3 interpolate_logs(const Sym3* logs, const double* weights, int count) {
  Sym3 sum;
  for (int k = 0; k < count; ++k)
    for (int i = 0; i < 6; ++i) sum.v[i] += weights[k] * logs[k].v[i];
  return metric_exp(sum);
}

double tangent_density(const Sym3& m, const Vec3& n) {
  const Vec3 t1 = n.unitOrthogonal(), t2 = n.cross(t1);
  const double a = m.form(t1, t1), b = m.form(t1, t2), c = m.form(t2, t2);
  return std::sqrt(std::max(0.0, a * c - b * b));
}

}  // namespace vesselmesh::sizing
