#include "mesh/geometry.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace vesselmesh::mesh {

std::array<double, 3> triangle_angles(const TriMesh& m, int t) {
  const Triangle& f = m.triangles[t];
  std::array<double, 3> angles{};
  for (int i = 0; i < 3; ++i) {
    const Vec3 u = m.points[f[(i + 1) % 3]] - m.points[f[i]];
    const Vec3 v = m.points[f[(i + 2) % 3]] - m.points[f[i]];
    const double nu = u.norm(), nv = v.norm();
    // atan2 of |u x v| and u.v is accurate for angles near 0 and pi, unlike acos.
    angles[i] = (nu == 0.0 || nv == 0.0) ? 0.0 : std::atan2(u.cross(v).norm(), u.dot(v));
  }
  return angles;
}

double surface_area(const TriMesh& m) {
  double area = 0.0;
  for (int t = 0; t < m.num_triangles(); ++t) area += triangle_area(m, t);
  return area;
}

std::array<Vec3, 2> bounding_box(const std::vector<Vec3>& points) {
  if (points.empty()) return {Vec3::Zero(), Vec3::Zero()};
  Vec3 lo = points.front(), hi = points.front();
  for (const Vec3& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return {lo, hi};
}


std::string format_point(const Vec3& p) {
  return fmt::format("({:.6g}, {:.6g}, {:.6g})", p.x(), p.y(), p.z());
}

}  // namespace vesselmesh::mesh
