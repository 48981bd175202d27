#include "analysis/normals.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace vesselmesh::analysis {
namespace {

constexpr int kGrain = 2048;

// The weighted sum of the face normals around v (`corners` lists 3 t + c), not normalized.
Vec3 weighted_sum(const TriMesh& mesh, const mesh::VertexTriangles& corners, int v, NormalMethod weighting) {
  Vec3 sum = Vec3::Zero();
  for (int corner : corners.of(v)) {
    const Triangle& f = mesh.triangles[corner / 3];
    const int c = corner % 3;
    const Vec3 e1 = mesh.points[f[(c + 1) % 3]] - mesh.points[v];
    const Vec3 e2 = mesh.points[f[(c + 2) % 3]] - mesh.points[v];
    const Vec3 cross = e1.cross(e2);
    const double a2 = cross.squaredNorm();
    if (!(a2 > 0.0)) continue;  // degenerate triangle: no direction
    switch (weighting) {
      case NormalMethod::angle: {
        const double a = std::sqrt(a2);
        sum += (cross / a) * std::atan2(a, e1.dot(e2));
        break;
      }
      case NormalMethod::area: sum += cross; break;
      default: sum += cross / (e1.squaredNorm() * e2.squaredNorm()); break;
    }
  }
  return sum;
}

Vec3 unit_or_zero(const Vec3& v) {
  const double n = v.norm();
  return n > 0.0 ? Vec3(v / n) : Vec3::Zero();
}

// Neighbours of v: its 1-ring (each incident triangle's other two corners), grown to the
// 2-ring when smaller than min_ring. `stamp[w] == v + 1` marks w as taken for this v (the
// array belongs to one thread), so membership costs O(1) however large the ring.
void gather_ring(const TriMesh& mesh, const mesh::VertexTriangles& corners, int v, size_t min_ring,
                 std::vector<int>& stamp, std::vector<int>& ring) {
  const int mark = v + 1;
  auto add = [&](int w) {
    if (stamp[w] != mark) stamp[w] = mark, ring.push_back(w);
  };
  ring.clear();
  stamp[v] = mark;
  for (int corner : corners.of(v)) {
    const Triangle& f = mesh.triangles[corner / 3];
    add(f[(corner % 3 + 1) % 3]);
    add(f[(corner % 3 + 2) % 3]);
  }
  if (ring.size() >= min_ring) return;
  const size_t first = ring.size();
  for (size_t i = 0; i < first; ++i)
    for (int corner : corners.of(ring[i]))
      for (int w : mesh.triangles[corner / 3]) add(w);
}

// Solves the symmetric positive definite system a x = b (5x5, lower triangle of `a` used) by
// an LDL^T factorization in place (no square roots); false when a pivot is not clearly
// positive.
bool solve_spd5(double a[5][5], double b[5]) {
  double largest = 0.0;
  for (int i = 0; i < 5; ++i) largest = std::max(largest, a[i][i]);
  double inv_d[5];
  for (int j = 0; j < 5; ++j) {
    double d = a[j][j];
    for (int k = 0; k < j; ++k) d -= a[j][k] * a[j][k] * a[k][k];
    if (!(d > 1e-10 * largest)) return false;
    a[j][j] = d;
    inv_d[j] = 1.0 / d;
    for (int i = j + 1; i < 5; ++i) {
      double s = a[i][j];
      for (int k = 0; k < j; ++k) s -= a[i][k] * a[j][k] * a[k][k];
      a[i][j] = s * inv_d[j];
    }
  }
  for (int i = 0; i < 5; ++i)  // L y = b
    for (int k = 0; k < i; ++k) b[i] -= a[i][k] * b[k];
  for (int i = 4; i >= 0; --i) {  // D L^T x = y
    b[i] *= inv_d[i];
    for (int k = i + 1; k < 5; ++k) b[i] -= a[k][i] * b[k];
  }
  return true;
}

// The quadric-fit normal at v, or `start` (the Max normal) where the fit is ill-posed.
Vec3 fit_normal(const TriMesh& mesh, int v, const Vec3& start, const std::vector<int>& ring) {
  constexpr double kMinCos = 0.8660254037844386;  // 30 degrees
  if (ring.size() < 5 || start.squaredNorm() == 0.0) return start;
  const Vec3 t1 = start.unitOrthogonal(), t2 = start.cross(t1);
  const Vec3& o = mesh.points[v];
  double scale = 0.0;  // coordinates in units of the rms neighbour distance, for conditioning
  for (int w : ring) scale += (mesh.points[w] - o).squaredNorm();
  scale = std::sqrt(static_cast<double>(ring.size()) / scale);
  double a[5][5] = {}, b[5] = {};
  for (int w : ring) {
    const Vec3 q = scale * (mesh.points[w] - o);
    const double x = q.dot(t1), y = q.dot(t2), z = q.dot(start);
    const double r[5] = {x * x, x * y, y * y, x, y};
    for (int i = 0; i < 5; ++i) {
      for (int j = 0; j <= i; ++j) a[i][j] += r[i] * r[j];
      b[i] += z * r[i];
    }
  }
  if (!solve_spd5(a, b)) return start;
  const Vec3 fitted = (start - b[3] * t1 - b[4] * t2).normalized();
  return fitted.allFinite() && fitted.dot(start) > kMinCos ? fitted : start;
}

}  // namespace

std::vector<Vec3> vertex_normals(const TriMesh& mesh, const mesh::VertexTriangles& corners, NormalMethod method) {
  std::vector<Vec3> normals(mesh.points.size());
  if (method != NormalMethod::quadric_fit) {
    tbb::parallel_for(tbb::blocked_range<int>(0, mesh.num_points(), kGrain), [&](const tbb::blocked_range<int>& range) {
      for (int v = range.begin(); v < range.end(); ++v) normals[v] = unit_or_zero(weighted_sum(mesh, corners, v, method));
    });
    return normals;
  }
  tbb::enumerable_thread_specific<std::vector<int>> stamps(std::vector<int>(mesh.points.size(), 0));
  tbb::parallel_for(tbb::blocked_range<int>(0, mesh.num_points(), kGrain), [&](const tbb::blocked_range<int>& range) {
    std::vector<int>& stamp = stamps.local();
    std::vector<int> ring;
    for (int v = range.begin(); v < range.end(); ++v) {
      const Vec3 start = unit_or_zero(weighted_sum(mesh, corners, v, NormalMethod::max));
      gather_ring(mesh, corners, v, 5, stamp, ring);
      normals[v] = fit_normal(mesh, v, start, ring);
    }
  });
  return normals;
}

std::vector<Vec3> vertex_normals(const TriMesh& mesh, NormalMethod method) {
  return vertex_normals(mesh, mesh::build_vertex_corners(mesh), method);
}

}  // namespace vesselmesh::analysis
