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

namespace {

constexpr int kVolumeCoefficients = 10;  // a full quadratic in 3D

// Point v's 2-ring in `graph` (v left out), in the order found; `stamp` is all -1 on entry and on exit.
void volume_ring(const mesh::PointGraph& graph, int v, std::vector<int>& stamp, std::vector<int>& ring) {
  ring.clear();
  stamp[v] = v;
  for (int k = graph.start[v]; k < graph.start[v + 1]; ++k) {
    const int q = graph.next[k];
    if (stamp[q] != v) stamp[q] = v, ring.push_back(q);
  }
  const size_t first = ring.size();
  for (size_t i = 0; i < first; ++i)
    for (int k = graph.start[ring[i]]; k < graph.start[ring[i] + 1]; ++k) {
      const int q = graph.next[k];
      if (stamp[q] != v) stamp[q] = v, ring.push_back(q);
    }
  for (int q : ring) stamp[q] = -1;
  stamp[v] = -1;
}

// The Hessians at point v of every field (columns of `values`: the fields at the point, then at its
// ring), from the least-squares quadratic; false where the fit is ill-posed.
bool fit_volume(const std::vector<Vec3>& points, int v, const std::vector<int>& ring,
                const Eigen::MatrixXd& values, std::vector<Eigen::Matrix3d>& out) {
  const int rows = static_cast<int>(ring.size()) + 1;
  if (rows < kVolumeCoefficients) return false;
  double scale2 = 0.0;
  for (int q : ring) scale2 += (points[q] - points[v]).squaredNorm();
  const double scale = std::sqrt(scale2 / ring.size());
  if (!(scale > 0.0)) return false;
  Eigen::MatrixXd a(rows, kVolumeCoefficients);
  for (int i = 0; i < rows; ++i) {
    const Vec3 d = (points[i == 0 ? v : ring[i - 1]] - points[v]) / scale;
    a.row(i) << 1.0, d.x(), d.y(), d.z(), d.x() * d.x(), d.y() * d.y(), d.z() * d.z(), d.x() * d.y(),
        d.x() * d.z(), d.y() * d.z();
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  if (qr.rank() < kVolumeCoefficients) return false;
  const Eigen::MatrixXd c = qr.solve(values) / (scale * scale);
  out.resize(values.cols());
  for (Eigen::Index f = 0; f < values.cols(); ++f) {
    const auto k = c.col(f);
    out[f] << 2.0 * k[4], k[7], k[8], k[7], 2.0 * k[5], k[9], k[8], k[9], 2.0 * k[6];
  }
  return true;
}

// Per point, `use(v, hessians)` with every field's Hessian there (not called where the fit is
// ill-posed); on threads, each point once.
template <typename Use>
void for_volume_hessians(const std::vector<Vec3>& points, const mesh::PointGraph& graph,
                         const std::vector<const std::vector<double>*>& fields, Use use) {
  const int np = static_cast<int>(points.size());
  VM_CHECK(static_cast<int>(graph.start.size()) == np + 1, "recovering Hessians: one graph row per point");
  tbb::enumerable_thread_specific<std::vector<int>> stamps([np] { return std::vector<int>(np, -1); });
  tbb::parallel_for(tbb::blocked_range<int>(0, np, 256), [&](const tbb::blocked_range<int>& r) {
    std::vector<int>& stamp = stamps.local();
    std::vector<int> ring;
    std::vector<Eigen::Matrix3d> h;
    Eigen::MatrixXd values;
    for (int v = r.begin(); v < r.end(); ++v) {
      volume_ring(graph, v, stamp, ring);
      values.resize(static_cast<Eigen::Index>(ring.size()) + 1, static_cast<Eigen::Index>(fields.size()));
      for (size_t f = 0; f < fields.size(); ++f) {
        values(0, f) = (*fields[f])[v];
        for (size_t i = 0; i < ring.size(); ++i) values(i + 1, f) = (*fields[f])[ring[i]];
      }
      if (fit_volume(points, v, ring, values, h)) use(v, h);
    }
  });
}

}  // namespace

std::vector<Sym3> recover_volume_hessians(const std::vector<Vec3>& points, const mesh::PointGraph& graph,
                                          const std::vector<double>& field) {
  VM_CHECK(field.size() == points.size(), "recover_volume_hessians: one value per point");
  std::vector<Sym3> out(points.size());
  for_volume_hessians(points, graph, {&field},
                      [&](int v, const std::vector<Eigen::Matrix3d>& h) { out[v] = Sym3::from_matrix(h[0]); });
  return out;
}

std::vector<double> volume_error_sizes(const std::vector<Vec3>& points, const mesh::PointGraph& graph,
                                       const std::vector<std::vector<double>>& fields,
                                       const ErrorMetricOptions& options, const Reporter& reporter) {
  if (!(options.p >= 1.0))
    throw OptionError(fmt::format("the error's norm p must be at least 1, not {}", options.p));
  if (!(options.floor > 0.0 && options.floor < 1.0))
    throw OptionError(fmt::format("the metric's floor must lie in (0, 1), not {}", options.floor));
  const int np = static_cast<int>(points.size());
  const auto box = mesh::bounding_box(points);
  const double extent2 = (box[1] - box[0]).squaredNorm();
  // The fields that are linear to round-off (second derivatives that change the field by under 1e-9
  // of its range across the mesh) are told apart after the fit, by each field's largest |H|.
  std::vector<const std::vector<double>*> used;
  for (const std::vector<double>& f : fields) {
    if (static_cast<int>(f.size()) != np)
      throw InputError(fmt::format("a field has {} values for {} points", f.size(), np));
    used.push_back(&f);
  }
  reporter.progress("recovering the fields' Hessians in the volume", 0.0);
  std::vector<std::vector<double>> rho(fields.size(), std::vector<double>(np, 0.0));
  for_volume_hessians(points, graph, used, [&](int v, const std::vector<Eigen::Matrix3d>& h) {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    for (size_t f = 0; f < h.size(); ++f) {
      eig.computeDirect(h[f], Eigen::EigenvaluesOnly);
      rho[f][v] = eig.eigenvalues().cwiseAbs().maxCoeff();
    }
  });
  reporter.progress("recovering the fields' Hessians in the volume", 1.0);
  std::vector<double> largest_rho(np, 0.0);
  double largest = 0.0;
  for (size_t f = 0; f < fields.size(); ++f) {
    const double own = *std::max_element(rho[f].begin(), rho[f].end());
    const auto [low, high] = std::minmax_element(fields[f].begin(), fields[f].end());
    // (against the values' size too: a constant field's fit leaves round-off)
    if (!(own * extent2 > 1e-9 * std::max({*high - *low, std::abs(*low), std::abs(*high)}))) continue;
    largest = std::max(largest, own);
    for (int v = 0; v < np; ++v) largest_rho[v] = std::max(largest_rho[v], rho[f][v]);
  }
  if (!(largest > 0.0))
    throw InputError(
        "the fields are linear everywhere in the volume (their recovered second derivatives are zero): there is "
        "nothing to adapt to");
  const double exponent = std::isfinite(options.p) ? -options.p / (2.0 * options.p + 3.0) : -0.5;
  std::vector<double> out(np);
  for (int v = 0; v < np; ++v) out[v] = std::pow(std::max(largest_rho[v], options.floor * largest), exponent);
  return out;
}

}  // namespace vesselmesh::sizing
