// A symmetric 3x3 tensor stored as its six distinct entries (xx, xy, xz, yy, yz, zz), the
// order of the `metric` arrays in VTP outputs. Used for curvature tensors and metrics.
#pragma once

#include "mesh/trimesh.h"

#include <array>

namespace vesselmesh {

struct Sym3 {
  std::array<double, 6> v{};  // xx, xy, xz, yy, yz, zz

  static Sym3 from_matrix(const Eigen::Matrix3d& m) {
    return {{m(0, 0), 0.5 * (m(0, 1) + m(1, 0)), 0.5 * (m(0, 2) + m(2, 0)), m(1, 1), 0.5 * (m(1, 2) + m(2, 1)), m(2, 2)}};
  }
  Eigen::Matrix3d matrix() const {
    Eigen::Matrix3d m;
    m << v[0], v[1], v[2], v[1], v[3], v[4], v[2], v[4], v[5];
    return m;
  }
  // x^T S y
  double form(const Vec3& x, const Vec3& y) const {
    return v[0] * x.x() * y.x() + v[1] * (x.x() * y.y() + x.y() * y.x()) + v[2] * (x.x() * y.z() + x.z() * y.x()) +
           v[3] * x.y() * y.y() + v[4] * (x.y() * y.z() + x.z() * y.y()) + v[5] * x.z() * y.z();
  }
};

}  // namespace vesselmesh
