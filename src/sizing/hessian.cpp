#include "sizing/hessian.h"

#include "mesh/connectivity.h"
#include "mesh/error.h"
#include "mesh/geometry.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>

namespace vesselmesh::sizing {
namespace {

constexpr size_t kMinFitPoints = 9;  // neighbours: fewer in the 2-ring, the 3-ring is taken

// The frame of a point's tangent plane: u, v with (u, v, n) right-handed.
void tangent_frame(const Vec3& n, Vec3& u, Vec3& v) {
  u = n.unitOrthogonal();
  v = n.cross(u);
}

// What the least-squares fit at one point makes of the field's values: its Hessian's three
// entries (2d, e, 2g in the tangent frame) as weights on the values at `points` (the point first,
// then its neighbours). Empty where the fit is ill-posed (the Hessian is zero there). The fit's
// matrix depends on the geometry only, so it is factored once for all the fields.
struct Stencil {
  std::vector<int> points;
  Eigen::Matrix<double, 3, Eigen::Dynamic> weights;
};

Stencil fit_stencil(const TriMesh& mesh, const std::vector<int>& ring, int v, const Vec3& u,
                    const Vec3& w) {
  Stencil out;
  const int rows = static_cast<int>(ring.size()) + 1;
  if (rows < 6) return out;
  double scale2 = 0.0;
  for (int q : ring) scale2 += (mesh.points[q] - mesh.points[v]).squaredNorm();
  const double scale = std::sqrt(scale2 / ring.size());
  if (!(scale > 0.0)) return out;
  Eigen::MatrixXd a(rows, 6);
  out.points.reserve(rows);
  for (int i = 0; i < rows; ++i) {
    const int q = i == 0 ? v : ring[i - 1];
    out.points.push_back(q);
    const Vec3 d = (mesh.points[q] - mesh.points[v]) / scale;
    const double x = d.dot(u), y = d.dot(w);
    a.row(i) << 1.0, x, y, x * x, x * y, y * y;
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  if (qr.rank() < 6) return {};
  // The coefficients are pinv(a) b; the Hessian's entries rows 3-5 of it, scaled back.
  const Eigen::MatrixXd pinv = qr.solve(Eigen::MatrixXd::Identity(rows, rows));
  out.weights.resize(3, rows);
  out.weights.row(0) = 2.0 * pinv.row(3) / (scale * scale);
  out.weights.row(1) = pinv.row(4) / (scale * scale);
  out.weights.row(2) = 2.0 * pinv.row(5) / (scale * scale);
  return out;
}

// |H|: the eigenvalues made absolute, each raised to `floor` at least.
Eigen::Matrix2d absolute(const Eigen::Matrix2d& h, double floor) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(h);
  const Eigen::Vector2d l = eig.eigenvalues().cwiseAbs().cwiseMax(floor);
  return eig.eigenvectors() * l.asDiagonal() * eig.eigenvectors().transpose();
}

// The intersection of two SPD 2x2 forms (simultaneous reduction, as sizing::intersect in 3D).
Eigen::Matrix2d intersect2(const Eigen::Matrix2d& a, const Eigen::Matrix2d& b) {
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix2d> eig(b, a);
  if (eig.info() != Eigen::Success) return a;
  const Eigen::Matrix2d p = eig.eigenvectors();
  Eigen::Vector2d l;
  for (int i = 0; i < 2; ++i)
    l[i] = std::max(p.col(i).dot(a * p.col(i)), p.col(i).dot(b * p.col(i)));
  const Eigen::Matrix2d p_inv = p.inverse();
  return p_inv.transpose() * l.asDiagonal() * p_inv;
}

// Per point its fit's stencil, in the tangent frame of its normal (none where it has none).
std::vector<Stencil> stencils(const TriMesh& mesh, const std::vector<Vec3>& normals) {
  const int np = mesh.num_points();
  const mesh::VertexTriangles corners = mesh::build_vertex_corners(mesh);
  std::vector<Stencil> out(np);
  tbb::enumerable_thread_specific<std::vector<int>> stamps(
      [np] { return std::vector<int>(np, 0); });
  tbb::parallel_for(tbb::blocked_range<int>(0, np, 1024), [&](const tbb::blocked_range<int>& r) {
    std::vector<int>& stamp = stamps.local();
    std::vector<int> ring;
    for (int v = r.begin(); v < r.end(); ++v) {
      if (normals[v].squaredNorm() == 0.0) continue;
      mesh::gather_ring(mesh, corners, v, kMinFitPoints, stamp, ring, 3, 2);
      Vec3 u, w;
      tangent_frame(normals[v], u, w);
      out[v] = fit_stencil(mesh, ring, v, u, w);
    }
  });
  return out;
}

Eigen::Matrix2d apply(const Stencil& stencil, const std::vector<double>& field) {
  if (stencil.points.empty()) return Eigen::Matrix2d::Zero();
  Eigen::Vector3d h = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < stencil.points.size(); ++i)
    h += stencil.weights.col(i) * field[stencil.points[i]];
  Eigen::Matrix2d out;
  out << h[0], h[1], h[1], h[2];
  return out;
}

}  // namespace

std::vector<Sym3> recover_hessians(const TriMesh& mesh, const std::vector<double>& field,
                                   const std::vector<Vec3>& normals) {
  const std::vector<Stencil> fits = stencils(mesh, normals);
  std::vector<Sym3> out(fits.size());
  for (size_t v = 0; v < fits.size(); ++v) {
    if (normals[v].squaredNorm() == 0.0) continue;
    Vec3 u, w;
    tangent_frame(normals[v], u, w);
    Eigen::Matrix<double, 3, 2> p;
    p << u, w;
    out[v] = Sym3::from_matrix(p * apply(fits[v], field) * p.transpose());
  }
  return out;
}

std::vector<Sym3> error_metric(const TriMesh& mesh, const std::vector<std::vector<double>>& fields,
                               const std::vector<Vec3>& normals, const ErrorMetricOptions& options,
                               const Reporter& reporter) {
  if (!(options.p >= 1.0))
    throw OptionError(fmt::format("the error's norm p must be at least 1, not {}", options.p));
  if (!(options.floor > 0.0 && options.floor < 1.0))
    throw OptionError(fmt::format("the metric's floor must lie in (0, 1), not {}", options.floor));
  const int np = mesh.num_points();
  for (const std::vector<double>& f : fields)
    if (static_cast<int>(f.size()) != np)
      throw InputError(fmt::format("a field has {} values for {} points", f.size(), np));
  const std::vector<Stencil> fits = stencils(mesh, normals);
  const auto box = mesh::bounding_box(mesh.points);
  const double extent2 = (box[1] - box[0]).squaredNorm();
  const std::string task = "recovering the fields' Hessians";
  // The running intersection in each point's tangent frame, from the first field that is not
  // linear everywhere (`largest` > 0 from then on).
  std::vector<Eigen::Matrix2d> m(np, Eigen::Matrix2d::Zero());
  double largest = 0.0;
  for (size_t i = 0; i < fields.size(); ++i) {
    reporter.progress(task, static_cast<double>(i) / fields.size());
    std::vector<Eigen::Matrix2d> h(np);
    tbb::parallel_for(tbb::blocked_range<int>(0, np, 4096), [&](const tbb::blocked_range<int>& r) {
      for (int v = r.begin(); v < r.end(); ++v) h[v] = apply(fits[v], fields[i]);
    });
    double own = 0.0;
    for (const Eigen::Matrix2d& x : h) own = std::max(own, x.cwiseAbs().maxCoeff());
    // Linear to round-off (second derivatives that change the field by under 1e-9 of its range
    // across the mesh): nothing to bound.
    const auto [low, high] = std::minmax_element(fields[i].begin(), fields[i].end());
    if (!(own * extent2 > 1e-9 * (*high - *low))) continue;
    const bool first = !(largest > 0.0);
    largest = std::max(largest, own);
    tbb::parallel_for(tbb::blocked_range<int>(0, np, 4096), [&](const tbb::blocked_range<int>& r) {
      for (int v = r.begin(); v < r.end(); ++v) {
        const Eigen::Matrix2d a = absolute(h[v], options.floor * own);
        m[v] = first ? a : intersect2(m[v], a);
      }
    });
  }
  reporter.progress(task, 1.0);
  if (!(largest > 0.0))
    throw InputError(
        "the fields are linear everywhere (their recovered second derivatives are zero): there is "
        "nothing to adapt to");
  const double floor = options.floor * largest;
  const double exponent = std::isfinite(options.p) ? -1.0 / (2.0 * options.p + 2.0) : 0.0;
  std::vector<Sym3> out(np);
  for (int v = 0; v < np; ++v) {
    const Vec3 n = normals[v].squaredNorm() > 0.0 ? Vec3(normals[v]) : Vec3::UnitZ();
    Vec3 u, w;
    tangent_frame(n, u, w);
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(absolute(m[v], floor));
    Eigen::Vector2d l = eig.eigenvalues();
    l *= std::pow(l[0] * l[1], exponent);
    Eigen::Matrix<double, 3, 2> p;
    p << u, w;
    const Eigen::Matrix<double, 3, 2> d = p * eig.eigenvectors();
    out[v] =
        Sym3::from_matrix(d * l.asDiagonal() * d.transpose() + l.maxCoeff() * n * n.transpose());
  }
  return out;
}

}  // namespace vesselmesh::sizing
