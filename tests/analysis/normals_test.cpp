#include "analysis/normals.h"

#include "analytic_curvature.h"
#include "synth/shapes.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>

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
