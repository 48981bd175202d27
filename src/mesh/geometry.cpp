#include "mesh/geometry.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace vesselmesh::mesh {

Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + (d1 / (d1 - d3)) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denominator = va + vb + vc;
  if (!(denominator > 0.0)) return (a + b + c) / 3.0;  // degenerate
  const double v = vb / denominator, w = vc / denominator;
  return a + v * ab + w * ac;
}

std::array<double, 3> barycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const double area = n.squaredNorm();
  if (!(area > 0.0)) return {1.0 / 3, 1.0 / 3, 1.0 / 3};
  std::array<double, 3> l = {(c - b).cross(p - b).dot(n) / area, (a - c).cross(p - c).dot(n) / area, 0.0};
  l[0] = std::clamp(l[0], 0.0, 1.0);
  l[1] = std::clamp(l[1], 0.0, 1.0 - l[0]);
  l[2] = 1.0 - l[0] - l[1];
  return l;
}

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
