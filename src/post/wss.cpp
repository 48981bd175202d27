#include "post/wss.h"

#include "mesh/error.h"

#include <fmt/format.h>

#include <Eigen/QR>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <map>

namespace vesselmesh::post {

const char* to_string(WssMethod method) { return method == WssMethod::quadratic ? "quadratic" : "face"; }

WssMethod parse_wss_method(const std::string& text) {
  if (text == "quadratic") return WssMethod::quadratic;
  if (text == "face") return WssMethod::face;
  throw InputError(fmt::format("unknown wall shear stress method '{}': give quadratic or face", text));
}

namespace {

// The least-squares quadratic's gradient weights at `origin`, from the offsets `d` (neighbour -
// origin), weighted by 1 / |d|^2; empty when the offsets do not fix a quadratic.
std::vector<Vec3> quadratic_gradient_weights(const std::vector<Vec3>& d) {
  constexpr int kTerms = 9;
  const int m = static_cast<int>(d.size());
  if (m < kTerms) return {};
  Eigen::MatrixXd a(m, kTerms);
  Eigen::VectorXd root_weight(m);
  for (int j = 0; j < m; ++j) {
    const Vec3& x = d[j];
    root_weight[j] = 1.0 / x.norm();
    a.row(j) << x.x(), x.y(), x.z(), 0.5 * x.x() * x.x(), 0.5 * x.y() * x.y(), 0.5 * x.z() * x.z(), x.x() * x.y(),
        x.x() * x.z(), x.y() * x.z();
    a.row(j) *= root_weight[j];
  }
  Eigen::VectorXd scale(kTerms);  // columns equilibrated: a layer's cells are far thinner than wide
  for (int k = 0; k < kTerms; ++k) {
    scale[k] = a.col(k).norm();
    if (!(scale[k] > 0.0)) return {};
    a.col(k) /= scale[k];
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  qr.setThreshold(1e-9);
  if (qr.rank() < kTerms) return {};
  const Eigen::MatrixXd pseudo_inverse = qr.solve(Eigen::MatrixXd(root_weight.asDiagonal()));  // 9 x m
  std::vector<Vec3> weights(m);
  for (int j = 0; j < m; ++j)
    weights[j] = Vec3(pseudo_inverse(0, j) / scale[0], pseudo_inverse(1, j) / scale[1], pseudo_inverse(2, j) / scale[2]);
  return weights;
}

Vec3 tangential_traction(const Eigen::Matrix3d& grad, const Vec3& n, double viscosity) {
  const Vec3 traction = viscosity * (grad + grad.transpose()) * n;
  return traction - traction.dot(n) * n;
}

}  // namespace

WallShearOperator::WallShearOperator(const WallSurface& wall, const std::vector<Tet>& tetrahedra,
                                     const std::vector<Vec3>& points, WssMethod method)
    : method_(method), volume_point_(wall.volume_point), triangles_(wall.mesh.triangles) {
  const size_t n_wall = wall.mesh.points.size();
  std::vector<Vec3> normal_sum(n_wall, Vec3::Zero());
  faces_.reserve(triangles_.size());
  for (size_t f = 0; f < triangles_.size(); ++f) {
    const Triangle& tri = triangles_[f];
    const Vec3& a = points[volume_point_[tri[0]]];
    const Vec3 area2 = (points[volume_point_[tri[1]]] - a).cross(points[volume_point_[tri[2]]] - a);
    Face face;
    face.tet = tetrahedra[wall.tet[f]];
    face.area = 0.5 * area2.norm();
    face.normal = face.area > 0.0 ? Vec3(-area2.normalized()) : Vec3::Zero();  // into the fluid
    double v6 = 0.0;
    face.gradient = mesh::barycentric_gradients(points[face.tet[0]], points[face.tet[1]], points[face.tet[2]],
                                                points[face.tet[3]], v6);
    faces_.push_back(face);
    for (int v : tri) normal_sum[v] -= area2;
  }
  offset_.assign(n_wall + 1, 0);
  if (method_ != WssMethod::quadratic) return;

  // The volume's point neighbours, for the points within one edge of the wall (whose neighbours
  // make the wall points' 2-rings).
  const int n_points = static_cast<int>(points.size());
  std::vector<char> on_wall(n_points, 0), near_wall(n_points, 0);
  for (int p : volume_point_) on_wall[p] = 1;
  for (const Tet& t : tetrahedra)
    if (on_wall[t[0]] || on_wall[t[1]] || on_wall[t[2]] || on_wall[t[3]])
      for (int p : t) near_wall[p] = 1;
  std::vector<std::pair<int, int>> pairs;
  for (const Tet& t : tetrahedra)
    for (int i = 0; i < 4; ++i)
      if (near_wall[t[i]])
        for (int j = 0; j < 4; ++j)
          if (i != j) pairs.emplace_back(t[i], t[j]);
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  std::vector<int> first(n_points + 1, 0);
  for (const auto& [p, q] : pairs) ++first[p + 1];
  for (int p = 0; p < n_points; ++p) first[p + 1] += first[p];

  std::vector<std::vector<int>> stencil_points(n_wall);
  std::vector<std::vector<Vec3>> stencil_weights(n_wall);
  normal_.resize(n_wall);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n_wall, 256), [&](const tbb::blocked_range<size_t>& range) {
    std::vector<int> ring;
    std::vector<Vec3> offsets;
    for (size_t v = range.begin(); v != range.end(); ++v) {
      normal_[v] = normal_sum[v].normalized();
      const int p = volume_point_[v];
      ring.clear();
      for (int k = first[p]; k < first[p + 1]; ++k) {
        const int q = pairs[k].second;
        ring.push_back(q);
        for (int l = first[q]; l < first[q + 1]; ++l) ring.push_back(pairs[l].second);
      }
      std::sort(ring.begin(), ring.end());
      ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
      ring.erase(std::remove(ring.begin(), ring.end(), p), ring.end());
      // A point on top of this one (a degenerate mesh) fixes nothing and would weigh infinitely.
      ring.erase(std::remove_if(ring.begin(), ring.end(), [&](int q) { return !((points[q] - points[p]).norm() > 0.0); }),
                 ring.end());
      offsets.clear();
      for (int q : ring) offsets.push_back(points[q] - points[p]);
      stencil_weights[v] = quadratic_gradient_weights(offsets);
      if (!stencil_weights[v].empty()) stencil_points[v] = ring;
    }
  });
  for (size_t v = 0; v < n_wall; ++v) {
    offset_[v + 1] = offset_[v] + static_cast<int>(stencil_points[v].size());
    if (stencil_points[v].empty()) ++fallbacks_;
    stencil_point_.insert(stencil_point_.end(), stencil_points[v].begin(), stencil_points[v].end());
    stencil_weight_.insert(stencil_weight_.end(), stencil_weights[v].begin(), stencil_weights[v].end());
  }
}

std::vector<Vec3> WallShearOperator::apply(const std::vector<Vec3>& velocity, double viscosity) const {
  const size_t n_wall = volume_point_.size();
  std::vector<Vec3> tau(n_wall, Vec3::Zero());
  std::vector<double> weight(n_wall, 0.0);
  const bool faces_needed = method_ == WssMethod::face || fallbacks_ > 0;
  for (size_t f = 0; faces_needed && f < faces_.size(); ++f) {
    const Face& face = faces_[f];
    if (!(face.area > 0.0)) continue;
    Eigen::Matrix3d grad = Eigen::Matrix3d::Zero();  // grad(i, j) = d u_i / d x_j
    for (int k = 0; k < 4; ++k) grad += velocity[face.tet[k]] * face.gradient[k].transpose();
    const Vec3 value = tangential_traction(grad, face.normal, viscosity);
    for (int v : triangles_[f]) {
      tau[v] += face.area * value;
      weight[v] += face.area;
    }
  }
  for (size_t v = 0; v < n_wall; ++v)
    if (weight[v] > 0.0) tau[v] /= weight[v];
  for (size_t v = 0; v < n_wall; ++v) {
    if (offset_[v] == offset_[v + 1]) continue;
    const Vec3& origin = velocity[volume_point_[v]];
    Eigen::Matrix3d grad = Eigen::Matrix3d::Zero();
    for (int k = offset_[v]; k < offset_[v + 1]; ++k)
      grad += (velocity[stencil_point_[k]] - origin) * stencil_weight_[k].transpose();
    tau[v] = tangential_traction(grad, normal_[v], viscosity);
  }
  return tau;
}

std::vector<Vec3> wall_shear_stress(const WallSurface& wall, const std::vector<Tet>& tetrahedra,
                                    const std::vector<Vec3>& points, const std::vector<Vec3>& velocity,
                                    double viscosity, WssMethod method) {
  return WallShearOperator(wall, tetrahedra, points, method).apply(velocity, viscosity);
}

}  // namespace vesselmesh::post
