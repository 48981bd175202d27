#include "analysis/normals.h"

#include "analytic_curvature.h"
#include "mesh/connectivity.h"
#include "synth/random.h"
#include "synth/shapes.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>

namespace vesselmesh::analysis {
namespace {

double median_error_deg(const TriMesh& m, const std::vector<Vec3>& normals) {
  std::vector<double> angle;
  for (int v = 0; v < m.num_points(); ++v) {
    const Vec3 exact = test::torus_curvature(m.points[v], 10).normal;
    angle.push_back(std::acos(std::min(1.0, normals[v].dot(exact))) * 180.0 / M_PI);
  }
  return test::quantile(angle, 0.5);
}

// The quadric-fit normal at v done plainly, as analysis/normals.h describes it: the 1-ring (the
// 2-ring under five points), the Max normal as the frame, a least-squares solve by QR. What
// vertex_normals must give whatever its shortcuts (closed fans, solves batched eight at a time,
// large fans on a general path).
Vec3 reference_fitted_normal(const TriMesh& m, const mesh::VertexTriangles& corners, int v) {
  std::set<int> ring;
  Vec3 max = Vec3::Zero();
  for (int corner : corners.of(v)) {
    const Triangle& f = m.triangles[corner / 3];
    for (int w : f)
      if (w != v) ring.insert(w);
    const Vec3 e1 = m.points[f[(corner % 3 + 1) % 3]] - m.points[v],
               e2 = m.points[f[(corner % 3 + 2) % 3]] - m.points[v];
    if (e1.cross(e2).squaredNorm() > 0.0)
      max += e1.cross(e2) / (e1.squaredNorm() * e2.squaredNorm());
  }
  if (ring.size() < 5) {
    const std::set<int> first = ring;
    for (int w : first)
      for (int corner : corners.of(w))
        for (int x : m.triangles[corner / 3])
          if (x != v) ring.insert(x);
  }
  if (max.squaredNorm() == 0.0) return max;
  max.normalize();
  if (ring.size() < 5) return max;
  const Vec3 t1 = max.unitOrthogonal(), t2 = max.cross(t1);
  Eigen::MatrixXd a(ring.size(), 5);
  Eigen::VectorXd z(ring.size());
  int row = 0;
  for (int w : ring) {
    const Vec3 q = m.points[w] - m.points[v];
    const double x = q.dot(t1), y = q.dot(t2);
    a.row(row) << x * x, x * y, y * y, x, y;
    z(row++) = q.dot(max);
  }
  const Eigen::VectorXd c = a.colPivHouseholderQr().solve(z);
  const Vec3 fitted = (max - c(3) * t1 - c(4) * t2).normalized();
  return fitted.dot(max) > std::cos(M_PI / 6) ? fitted : max;
}

// Points at the origin and on rings around it, lifted onto a noisy paraboloid; triangles fan
// around the origin over [first, last) of the `sides` sectors, and join the rings.
TriMesh umbrella(int sides, int first, int last, int rings, synth::Random& random) {
  TriMesh m;
  m.points.push_back(Vec3::Zero());
  for (int r = 1; r <= rings; ++r)
    for (int i = 0; i < sides; ++i) {
      const double angle = 2 * M_PI * (i + 0.3 * random.uniform()) / sides,
                   radius = 0.1 * r * (1 + 0.2 * random.uniform());
      const double x = radius * std::cos(angle), y = radius * std::sin(angle);
      m.points.push_back(
          Vec3(x, y, 0.8 * x * x + 0.3 * x * y + 0.2 * y * y + 1e-3 * (random.uniform() - 0.5)));
    }
  auto at = [&](int r, int i) { return r == 0 ? 0 : 1 + (r - 1) * sides + (i % sides); };
  for (int i = first; i < last; ++i) {
    m.triangles.push_back({at(0, 0), at(1, i), at(1, i + 1)});
    for (int r = 1; r < rings; ++r) {
      m.triangles.push_back({at(r, i), at(r + 1, i), at(r + 1, i + 1)});
      m.triangles.push_back({at(r, i), at(r + 1, i + 1), at(r, i + 1)});
    }
  }
  return m;
}

void expect_reference_normals(const TriMesh& m, const std::string& what) {
  const mesh::VertexTriangles corners = mesh::build_vertex_corners(m);
  const std::vector<Vec3> n = vertex_normals(m, NormalMethod::quadric_fit);
  for (int v = 0; v < m.num_points(); ++v) {
    const Vec3 expected = reference_fitted_normal(m, corners, v);
    EXPECT_LT((n[v] - expected).norm(), 1e-9)
        << what << ", point " << v << " of " << corners.of(v).size() << " triangles";
  }
}

TEST(Normals, MaxWeightsAreExactOnASphereWhateverTheTriangulation) {
  const TriMesh m = synth::sphere({.radius = 2, .resolution = 0.3, .jitter = 0.4});
  const std::vector<Vec3> n = vertex_normals(m, NormalMethod::max);
  for (int v = 0; v < m.num_points(); ++v) EXPECT_LT((n[v] - m.points[v] / 2.0).norm(), 1e-10);
}

TEST(Normals, FittedNormalsAreSecondOrderOnIrregularMeshes) {
  auto error = [](double h, NormalMethod method) {
    const TriMesh m = synth::torus({.major_radius = 10, .minor_radius = 3, .resolution = h, .jitter = 0.3});
    return median_error_deg(m, vertex_normals(m, method));
  };
  const double fit_coarse = error(0.4, NormalMethod::quadric_fit), fit_fine = error(0.2, NormalMethod::quadric_fit);
  const double max_coarse = error(0.4, NormalMethod::max), max_fine = error(0.2, NormalMethod::max);
  EXPECT_LT(fit_fine, 0.35 * fit_coarse);  // about 1/4 when h halves
  EXPECT_GT(max_fine, 0.4 * max_coarse);   // about 1/2: first order
  EXPECT_LT(fit_fine, 0.2 * max_fine);
  const TriMesh m = synth::torus({.major_radius = 10, .minor_radius = 3, .resolution = 0.2, .jitter = 0.3});
  EXPECT_LT(median_error_deg(m, vertex_normals(m, NormalMethod::angle)), 2 * error(0.2, NormalMethod::area));
}

TEST(Normals, FittedNormalsAreThePlainFitOnEveryKindOfPoint) {
  // Closed fans of 4 to 8 triangles (the jittered torus: valence 4 takes the 2-ring), open
  // fans (the pipe's ends), a fan of 40 triangles (the general path), and a point where two open
  // fans meet (a bow tie: neither fan's next corners are the whole ring).
  expect_reference_normals(
      synth::torus({.major_radius = 10, .minor_radius = 3, .resolution = 0.5, .jitter = 0.3}),
      "torus");
  expect_reference_normals(
      synth::cylinder({.radius = 3, .length = 6, .resolution = 0.5, .jitter = 0.3}), "open pipe");
  synth::Random random(7);
  expect_reference_normals(umbrella(40, 0, 40, 3, random), "40-triangle fan");
  expect_reference_normals(umbrella(30, 0, 30, 2, random), "30-triangle fan");
  TriMesh bow_tie = umbrella(12, 0, 4, 2, random);
  const TriMesh other = umbrella(12, 6, 10, 2, random);
  const int offset = bow_tie.num_points() - 1;  // the other's centre is point 0, shared
  for (int i = 1; i < other.num_points(); ++i) bow_tie.points.push_back(other.points[i]);
  for (Triangle f : other.triangles) {
    for (int& w : f) w = w == 0 ? 0 : w + offset;
    bow_tie.triangles.push_back(f);
  }
  // Number the fans' ends so that the two gaps have equal index sums (first corners 1 and 4,
  // last ones 2 and 3): only the sums of squares tell the fans apart from a closed one.
  auto swap_points = [&](int i, int j) {
    std::swap(bow_tie.points[i], bow_tie.points[j]);
    for (Triangle& f : bow_tie.triangles)
      for (int& w : f) w = w == i ? j : w == j ? i : w;
  };
  const int last_a = 5, first_b = offset + 7,
            last_b = offset + 11;  // ring points 4, 6, 10 (the first end, 0, is 1)
  swap_points(last_a, 2);
  swap_points(first_b, 4);
  swap_points(last_b, 3);
  const mesh::VertexTriangles corners = mesh::build_vertex_corners(bow_tie);
  std::vector<int> next, prev;
  for (int corner : corners.of(0)) {
    const Triangle& f = bow_tie.triangles[corner / 3];
    next.push_back(f[(corner % 3 + 1) % 3]), prev.push_back(f[(corner % 3 + 2) % 3]);
  }
  std::sort(next.begin(), next.end()), std::sort(prev.begin(), prev.end());
  ASSERT_NE(next, prev);
  ASSERT_EQ(std::accumulate(next.begin(), next.end(), 0),
            std::accumulate(prev.begin(), prev.end(), 0));
  expect_reference_normals(bow_tie, "bow tie");
}

TEST(Normals, OrientationFollowsTheTriangles) {
  TriMesh m = test::tetrahedron();
  for (NormalMethod method : {NormalMethod::quadric_fit, NormalMethod::max, NormalMethod::angle, NormalMethod::area}) {
    const std::vector<Vec3> n = vertex_normals(m, method);
    for (int v = 0; v < 4; ++v) EXPECT_GT(n[v].dot(m.points[v]), 0.9 * m.points[v].norm());
  }
  for (Triangle& f : m.triangles) std::swap(f[1], f[2]);
  const std::vector<Vec3> n = vertex_normals(m);
  for (int v = 0; v < 4; ++v) EXPECT_LT(n[v].dot(m.points[v]), 0.0);
}

TEST(Normals, PointsWithoutProperTrianglesGetZero) {
  TriMesh m;
  m.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(5, 5, 5)};
  m.triangles = {{0, 1, 2}};  // collinear
  for (NormalMethod method : {NormalMethod::quadric_fit, NormalMethod::max, NormalMethod::angle, NormalMethod::area})
    for (const Vec3& n : vertex_normals(m, method)) EXPECT_EQ(n, Vec3::Zero());
}

}  // namespace
}  // namespace vesselmesh::analysis
