#include "analysis/curvature.h"

#include "analysis/mixed_areas.h"
#include "mesh/connectivity.h"
#include "mesh/error.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace vesselmesh::analysis {
namespace {

constexpr int kGrain = 4096;
constexpr double kLeastFitShape = 4e-4;  // see face_record

// What the vertex pass needs of a triangle, kept small (float) so the pass streams little
// memory: its fitted tensor II = (e f; f g) in its frame (tu, n x tu), its unit normal n and
// first axis tu, and the mixed Voronoi areas of its corners (Meyer et al. 2002). Zero for a
// degenerate triangle.
struct FaceRecord {
  float efg[3];
  float n[3];
  float tu[3];
  float area[3];
};

// II fitted to the change of the vertex normals along the triangle's edges: in the frame
// (tu, tv) of its plane, e u + f v = du and f u + g v = dv for each edge (u, v) with normal
// change (du, dv). Least squares through the normal equations
// [[su, suv, 0], [suv, su + sv, suv], [0, suv, sv]] (e f g)^T = r, solved by Cramer's rule
// (determinant (su + sv)(su sv - suv^2)).
FaceRecord face_record(const TriMesh& mesh, const std::vector<Vec3>& normals, int t) {
  FaceRecord out{};
  const Triangle& f = mesh.triangles[t];
  const Vec3 edge[3] = {mesh.points[f[2]] - mesh.points[f[1]], mesh.points[f[0]] - mesh.points[f[2]],
                        mesh.points[f[1]] - mesh.points[f[0]]};
  const Vec3 n = edge[0].cross(edge[1]);
  const double l2[3] = {edge[0].squaredNorm(), edge[1].squaredNorm(), edge[2].squaredNorm()};
  const double ln = n.norm();
  if (!(l2[0] > 0.0) || !(ln > 0.0)) return out;
  const Vec3 nu = n * (1.0 / ln), tu = edge[0] * (1.0 / std::sqrt(l2[0])), tv = nu.cross(tu);
  double su = 0.0, sv = 0.0, suv = 0.0, r0 = 0.0, r1 = 0.0, r2 = 0.0;
  for (int j = 0; j < 3; ++j) {
    const double u = edge[j].dot(tu), v = edge[j].dot(tv);
    const Vec3 dn = normals[f[(j + 2) % 3]] - normals[f[(j + 1) % 3]];  // along edge j
    const double du = dn.dot(tu), dv = dn.dot(tv);
    su += u * u, sv += v * v, suv += u * v;
    r0 += du * u, r1 += du * v + dv * u, r2 += dv * v;
  }
  const double trace = su + sv, minor = su * sv - suv * suv, det = trace * minor;
  // A needle or a flat triangle (smallest angle under about 2 degrees: minor / trace^2 is 0.25 for
  // an equilateral triangle, 4e-4 at 2 degrees) measures the normals' change across itself over
  // a distance near zero: its fit is noise (a plane cut's needles at an open end gave |k| = 2600
  // on a pipe of radius 2, and the curvature size field its smallest size there). Left out.
  if (!(det > 1e-12 * trace * trace * trace) || !(minor > kLeastFitShape * trace * trace)) return out;
  const double inv_det = 1.0 / det;
  const double e = ((trace * sv - suv * suv) * r0 - suv * sv * r1 + suv * suv * r2) * inv_det;
  const double g = (suv * suv * r0 - suv * su * r1 + (trace * su - suv * suv) * r2) * inv_det;
  const double fm = (r1 - suv * (e + g)) * minor * inv_det;  // (...) / trace
  if (!std::isfinite(e) || !std::isfinite(g) || !std::isfinite(fm)) return out;
  out.efg[0] = static_cast<float>(e), out.efg[1] = static_cast<float>(fm), out.efg[2] = static_cast<float>(g);
  for (int i = 0; i < 3; ++i) out.n[i] = static_cast<float>(nu[i]), out.tu[i] = static_cast<float>(tu[i]);
  const std::array<double, 3> corner = triangle_corner_areas(l2, 0.5 * ln);
  for (int i = 0; i < 3; ++i) out.area[i] = static_cast<float>(corner[i]);
  return out;
}

// The 2x2 tensor (e f; f g) in a vertex's tangent frame (u, v).
struct Tensor2 {
  double e = 0.0, f = 0.0, g = 0.0;
};

// A tensor (e f; f g) given in the frame (tu, m x tu) of a plane with unit normal m, read in
// the frame (u, v) of the tangent plane with unit normal n. As in Rusinkiewicz's paper the
// frames are brought into one plane by the smallest rotation between the normals, here turning
// tu from m to n: for x orthogonal to m that rotation is R x = x - (x.n) / (1 + c) (m + n), c = m.n
// (the axis m x n is kept, the plane of m and n turned by the angle between them). Both frames are
// then orthonormal in that plane, so they differ by a plane rotation Q = (cs -sn; sn cs) and the
// tensor becomes Q II Q^T.
inline Tensor2 project(const float efg[3], const Vec3& m, const Vec3& tu, const Vec3& n,
                       const Vec3& u, const Vec3& v) {
  const double c = m.dot(n);
  const Vec3 r = c > -1.0 + 1e-12 ? Vec3(tu - (tu.dot(n) / (1.0 + c)) * (m + n))
                                  : Vec3(-tu);  // opposite normals: a half turn
  const double cs = r.dot(u), sn = r.dot(v);
  const double e = efg[0], f = efg[1], g = efg[2];
  const double cc = cs * cs, ss = sn * sn, cn = cs * sn;
  return {cc * e - 2.0 * cn * f + ss * g, cn * (e - g) + (cc - ss) * f, ss * e + 2.0 * cn * f + cc * g};
}

// An orthonormal tangent frame at a vertex with unit normal n, from a fixed axis so that it
// does not depend on the mesh's ordering.
void tangent_frame(const Vec3& n, Vec3& u, Vec3& v) {
  u = n.unitOrthogonal();
  v = n.cross(u);
}

// The frame (u, v, n) a point's tensor is written in: its normal, or +z where it has none (then
// false: its tensor is zero and its directions arbitrary).
bool point_frame(const Vec3& normal, Vec3& n, Vec3& u, Vec3& v) {
  const bool has_normal = normal.squaredNorm() > 0.0;
  n = has_normal ? normal : Vec3::UnitZ();
  tangent_frame(n, u, v);
  return has_normal;
}

// Principal curvatures and directions of (e f; f g) in frame (u, v): the larger eigenvalue's
// eigenvector is (f, k2 - e) or (k2 - g, f), whichever is longer (both are when f != 0).
void diagonalize(const Tensor2& t, const Vec3& n, const Vec3& u, const Vec3& v, double& k1, double& k2, Vec3& d1,
                 Vec3& d2) {
  const double mid = 0.5 * (t.e + t.g);
  const double half = 0.5 * (t.e - t.g);
  const double radius = std::sqrt(half * half + t.f * t.f);
  k1 = mid - radius;
  k2 = mid + radius;
  double x = t.f, y = k2 - t.e;
  if (std::abs(k2 - t.g) + std::abs(t.f) > std::abs(x) + std::abs(y)) x = k2 - t.g, y = t.f;
  const double length = std::sqrt(x * x + y * y);
  if (!(length > 0.0)) x = 1.0, y = 0.0;  // umbilic: any direction
  else x /= length, y /= length;
  d2 = x * u + y * v;
  d1 = d2.cross(n);  // (d1, d2, n) right-handed
}

// Averages each vertex's tensor with its neighbours', weighted by point area, every tensor
// turned into the vertex's tangent plane first.
void smooth(const TriMesh& mesh, const mesh::VertexTriangles& corners, const std::vector<double>& area,
            const std::vector<Vec3>& normals, std::vector<Tensor2>& tensors) {
  const std::vector<Tensor2> before = tensors;
  tbb::parallel_for(tbb::blocked_range<int>(0, mesh.num_points(), kGrain), [&](const tbb::blocked_range<int>& range) {
    std::vector<int> ring;
    for (int p = range.begin(); p < range.end(); ++p) {
      if (normals[p].squaredNorm() == 0.0) continue;
      ring.assign(1, p);
      for (int corner : corners.of(p))
        for (int w : mesh.triangles[corner / 3]) ring.push_back(w);
      std::sort(ring.begin(), ring.end());
      ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
      Vec3 u, v;
      tangent_frame(normals[p], u, v);
      Tensor2 sum;
      double weight = 0.0;
      for (int w : ring) {
        if (normals[w].squaredNorm() == 0.0 || !(area[w] > 0.0)) continue;
        Vec3 uw, vw;
        tangent_frame(normals[w], uw, vw);
        const float efg[3] = {float(before[w].e), float(before[w].f), float(before[w].g)};
        const Tensor2 t = project(efg, normals[w], uw, normals[p], u, v);
        sum.e += area[w] * t.e, sum.f += area[w] * t.f, sum.g += area[w] * t.g;
        weight += area[w];
      }
      tensors[p] = weight > 0.0 ? Tensor2{sum.e / weight, sum.f / weight, sum.g / weight} : before[p];
    }
  });
}

// The tensor at p in its frame (u, v): its triangles' tensors turned into the frame and averaged
// with their corner areas as weights, summed in p's corner order (the same sums for any thread
// count). Zero with zero area where p has no proper triangle.
Tensor2 vertex_tensor(const mesh::VertexTriangles& corners, const std::vector<FaceRecord>& faces,
                      int p, const Vec3& n, const Vec3& u, const Vec3& v, double& area) {
  Tensor2 sum;
  area = 0.0;
  for (int corner : corners.of(p)) {
    const FaceRecord& face = faces[corner / 3];
    const double w = face.area[corner % 3];
    if (!(w > 0.0)) continue;
    const Tensor2 s = project(face.efg, Vec3(face.n[0], face.n[1], face.n[2]),
                              Vec3(face.tu[0], face.tu[1], face.tu[2]), n, u, v);
    sum.e += w * s.e, sum.f += w * s.f, sum.g += w * s.g;
    area += w;
  }
  if (!(area > 0.0)) return {};
  const double inv = 1.0 / area;
  return {sum.e * inv, sum.f * inv, sum.g * inv};
}

CurvatureField curvature_with(const TriMesh& mesh, const mesh::VertexTriangles& corners, std::vector<Vec3> normals,
                              const CurvatureOptions& options, const Reporter& reporter) {
  if (options.smoothing_passes < 0)
    throw OptionError(fmt::format("smoothing passes must not be negative, got {}", options.smoothing_passes));
  VM_CHECK(normals.size() == mesh.points.size(), "one normal per point");
  const int np = mesh.num_points();
  const std::string task = "computing curvature";
  reporter.progress(task, 0.3);

  CurvatureField field;
  field.k1.resize(np);
  field.k2.resize(np);
  field.dir1.resize(np);
  field.dir2.resize(np);
  std::vector<FaceRecord> faces(mesh.triangles.size());
  tbb::parallel_for(tbb::blocked_range<int>(0, mesh.num_triangles(), kGrain),
                    [&](const tbb::blocked_range<int>& range) {
                      for (int t = range.begin(); t < range.end(); ++t)
                        faces[t] = face_record(mesh, normals, t);
                    });
  const bool smoothing = options.smoothing_passes > 0;
  std::vector<Tensor2> tensors(smoothing ? np : 0);
  std::vector<double> area(smoothing ? np : 0);
  // Without smoothing each point's tensor is diagonalized as soon as it is made.
  tbb::parallel_for(tbb::blocked_range<int>(0, np, kGrain), [&](const tbb::blocked_range<int>& range) {
    for (int p = range.begin(); p < range.end(); ++p) {
      Vec3 n, u, v;
      const bool has_normal = point_frame(normals[p], n, u, v);
      double weight = 0.0;
      const Tensor2 t = has_normal ? vertex_tensor(corners, faces, p, n, u, v, weight) : Tensor2{};
      if (smoothing)
        tensors[p] = t, area[p] = weight;
      else
        diagonalize(t, n, u, v, field.k1[p], field.k2[p], field.dir1[p], field.dir2[p]);
    }
  });
  reporter.progress(task, 0.6);
  if (smoothing) {
    for (int pass = 0; pass < options.smoothing_passes; ++pass)
      smooth(mesh, corners, area, normals, tensors);
    tbb::parallel_for(
        tbb::blocked_range<int>(0, np, kGrain), [&](const tbb::blocked_range<int>& range) {
          for (int p = range.begin(); p < range.end(); ++p) {
            Vec3 n, u, v;
            point_frame(normals[p], n, u, v);
            diagonalize(tensors[p], n, u, v, field.k1[p], field.k2[p], field.dir1[p],
                        field.dir2[p]);
          }
        });
  }
  field.normal = std::move(normals);
  reporter.progress(task, 1.0);
  return field;
}

}  // namespace

Sym3 CurvatureField::tensor(int v) const {
  return Sym3::from_matrix(k1[v] * dir1[v] * dir1[v].transpose() + k2[v] * dir2[v] * dir2[v].transpose());
}

CurvatureField curvature(const TriMesh& mesh, const CurvatureOptions& options, const Reporter& reporter) {
  reporter.progress("computing curvature", 0.0);
  const mesh::VertexTriangles corners = mesh::build_vertex_corners(mesh);
  return curvature_with(mesh, corners, vertex_normals(mesh, corners, options.normals), options, reporter);
}

CurvatureField curvature_from_normals(const TriMesh& mesh, std::vector<Vec3> normals, const CurvatureOptions& options,
                                     const Reporter& reporter) {
  return curvature_with(mesh, mesh::build_vertex_corners(mesh), std::move(normals), options, reporter);
}

}  // namespace vesselmesh::analysis
