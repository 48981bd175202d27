#include "sizing/hessian.h"

#include "mesh/error.h"
#include "mesh/point_graph.h"
#include "synth/shapes.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

namespace vesselmesh::sizing {
namespace {

// The unit square of n x n cells with its inner points moved at random by up to 0.4 of a cell
// in the plane: an irregular triangulation of z = 0.
TriMesh irregular_square(int n = 20) {
  TriMesh mesh = test::unit_square(n);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> move(-0.4 / n, 0.4 / n);
  for (Vec3& p : mesh.points)
    if (p.x() > 1e-9 && p.x() < 1.0 - 1e-9 && p.y() > 1e-9 && p.y() < 1.0 - 1e-9)
      p += Vec3(move(random), move(random), 0);
  return mesh;
}

std::vector<double> sample(const TriMesh& mesh, double (*f)(const Vec3&)) {
  std::vector<double> out;
  for (const Vec3& p : mesh.points) out.push_back(f(p));
  return out;
}

TEST(Hessian, ExactForAQuadraticOnAnIrregularPlaneEvenAtItsBorder) {
  const TriMesh mesh = irregular_square();
  const std::vector<Vec3> normals(mesh.points.size(), Vec3::UnitZ());
  const std::vector<Sym3> h = recover_hessians(
      mesh,
      sample(mesh,
             [](const Vec3& p) {
               return 3 * p.x() * p.x() + 2 * p.x() * p.y() - p.y() * p.y() + p.x() + 5;
             }),
      normals);
  for (const Sym3& s : h) {  // [[6, 2], [2, -2]] in x, y; nothing along the normal
    EXPECT_NEAR(s.v[0], 6.0, 1e-7);
    EXPECT_NEAR(s.v[1], 2.0, 1e-7);
    EXPECT_NEAR(s.v[3], -2.0, 1e-7);
    EXPECT_NEAR(s.v[2], 0.0, 1e-9);
    EXPECT_NEAR(s.v[4], 0.0, 1e-9);
    EXPECT_NEAR(s.v[5], 0.0, 1e-9);
  }
}

TEST(Hessian, AlongACylindersAxisAndConvergingForASmoothField) {
  // z^2 on a jittered pipe (radius 3): 2 along the axis, 0 round it, at every point.
  const TriMesh pipe =
      synth::cylinder({.radius = 3.0, .length = 10.0, .resolution = 0.4, .jitter = 0.3});
  std::vector<Vec3> radial;
  for (const Vec3& p : pipe.points) radial.push_back(Vec3(p.x(), p.y(), 0).normalized());
  const std::vector<Sym3> h =
      recover_hessians(pipe, sample(pipe, [](const Vec3& p) { return p.z() * p.z(); }), radial);
  for (size_t v = 0; v < h.size(); ++v) {
    const Vec3 round = Vec3::UnitZ().cross(radial[v]);
    EXPECT_NEAR(h[v].form(Vec3::UnitZ(), Vec3::UnitZ()), 2.0, 1e-7);
    EXPECT_NEAR(h[v].form(round, round), 0.0, 1e-7);
  }
  // sin(4 x) on the irregular plane: -16 sin(4 x), the RMS error falling as h inside (0.53, 0.28,
  // 0.14 at 20, 40, 80 cells) and near the border (within 0.15: the fit is one-sided there; 1.5,
  // 0.58, 0.23).
  const auto errors = [](int cells) {
    const TriMesh plane = irregular_square(cells);
    const std::vector<Sym3> s =
        recover_hessians(plane, sample(plane, [](const Vec3& p) { return std::sin(4 * p.x()); }),
                         std::vector<Vec3>(plane.points.size(), Vec3::UnitZ()));
    double sum[2] = {0.0, 0.0};
    int count[2] = {0, 0};
    for (size_t v = 0; v < s.size(); ++v) {
      const Vec3& p = plane.points[v];
      const double e = s[v].v[0] + 16 * std::sin(4 * p.x());
      const int in = std::min({p.x(), p.y(), 1 - p.x(), 1 - p.y()}) > 0.15 ? 0 : 1;
      sum[in] += e * e;
      ++count[in];
    }
    return std::pair{std::sqrt(sum[0] / count[0]), std::sqrt(sum[1] / count[1])};
  };
  const auto [inside20, border20] = errors(20);
  const auto [inside40, border40] = errors(40);
  EXPECT_LT(inside20, 0.05 * 16);
  EXPECT_LT(inside40, 0.6 * inside20);
  EXPECT_LT(border40, 0.6 * border20);
  EXPECT_GT(inside40, 0.0);
}

TEST(Hessian, ErrorMetricIntersectsTheFieldsAndNormalizesForTheLpNorm) {
  const TriMesh mesh = irregular_square();
  const std::vector<Vec3> normals(mesh.points.size(), Vec3::UnitZ());
  const std::vector<std::vector<double>> fields = {
      sample(mesh, [](const Vec3& p) { return p.x() * p.x(); }),
      sample(mesh, [](const Vec3& p) { return 4 * p.y() * p.y() + p.x(); })};
  // |H| = diag(2, 0) and diag(0, 8): their intersection diag(2, 8), det 16.
  const double factor = std::pow(16.0, -1.0 / 6.0);  // p = 2: det^(-1 / (2 p + 2))
  const std::vector<Sym3> m = error_metric(mesh, fields, normals, {.p = 2.0});
  const std::vector<Sym3> m_inf = error_metric(mesh, fields, normals, {.p = INFINITY});
  for (size_t v = 0; v < m.size(); ++v) {
    EXPECT_NEAR(m[v].v[0], 2.0 * factor, 1e-6);
    EXPECT_NEAR(m[v].v[3], 8.0 * factor, 1e-6);
    EXPECT_NEAR(m[v].v[1], 0.0, 1e-6);
    EXPECT_NEAR(m[v].v[5], 8.0 * factor,
                1e-6);  // the normal as fine as the finer tangent direction
    EXPECT_NEAR(m_inf[v].v[0], 2.0, 1e-6);
    EXPECT_NEAR(m_inf[v].v[3], 8.0, 1e-6);
  }
  // One field alone: the direction it is linear along gets the floor, not zero.
  const std::vector<Sym3> one =
      error_metric(mesh, {fields[0]}, normals, {.p = INFINITY, .floor = 1e-3});
  EXPECT_NEAR(one[0].v[3], 2e-3, 1e-9);
}

TEST(Hessian, ErrorMetricRefusesLinearFieldsAndBadOptions) {
  const TriMesh mesh = irregular_square();
  const std::vector<Vec3> normals(mesh.points.size(), Vec3::UnitZ());
  const std::vector<double> linear = sample(mesh, [](const Vec3& p) { return 2 * p.x() - p.y(); });
  EXPECT_THROW(error_metric(mesh, {linear}, normals), InputError);
  EXPECT_THROW(error_metric(mesh, {linear}, normals, {.p = 0.5}), OptionError);
  EXPECT_THROW(error_metric(mesh, {linear}, normals, {.floor = 0.0}), OptionError);
  EXPECT_THROW(error_metric(mesh, {{1.0, 2.0}}, normals), InputError);
}

// A box of Kuhn tetrahedra (6 x 5 x 4 cells of 0.2 by default), its inner points moved at random by
// up to 0.3 of a cell: an irregular volume mesh and its point graph.
struct IrregularBox {
  TetMesh mesh;
  mesh::PointGraph graph;
  explicit IrregularBox(const std::array<int, 3>& cells = {6, 5, 4}, double cell = 0.2)
      : mesh(test::kuhn_box(cells, cell * Vec3(cells[0], cells[1], cells[2]))) {
    std::mt19937 random(11);
    std::uniform_real_distribution<double> move(-0.3 * cell, 0.3 * cell);
    for (Vec3& p : mesh.points) {
      bool inner = true;
      for (int k = 0; k < 3; ++k) inner = inner && p[k] > 1e-9 && p[k] < cell * cells[k] - 1e-9;
      if (inner) p += Vec3(move(random), move(random), move(random));
    }
    graph = mesh::point_graph(mesh.num_points(), mesh.tets);
  }
  std::vector<double> sample(double (*f)(const Vec3&)) const {
    std::vector<double> out;
    for (const Vec3& p : mesh.points) out.push_back(f(p));
    return out;
  }
};

// The volume's fit (issue 52's flow interior) recovers a quadratic's Hessian to round-off at every
// point, the box's faces and corners included.
TEST(Hessian, VolumeFitExactForAQuadraticEvenAtTheBoxsCorners) {
  const IrregularBox box;
  const std::vector<double> f = box.sample([](const Vec3& p) {
    return 1.0 + 2 * p.x() - p.y() + 3 * p.x() * p.x() - 2 * p.x() * p.y() + 0.5 * p.z() * p.z() + p.y() * p.z();
  });
  Eigen::Matrix3d expected;
  expected << 6, -2, 0, -2, 0, 1, 0, 1, 1;
  const std::vector<Sym3> h = recover_volume_hessians(box.mesh.points, box.graph, f);
  ASSERT_EQ(h.size(), box.mesh.points.size());
  for (size_t v = 0; v < h.size(); ++v) EXPECT_LT((h[v].matrix() - expected).cwiseAbs().maxCoeff(), 1e-8) << v;
}

// The sizes go as the largest |eigenvalue| to the power -p / (2 p + 3): for f = exp(2 x), whose
// Hessian is 4 exp(2 x) e_x e_x, sizes from x = 0.4 to 0.8 (inside a box of cells of 0.1, 1.2 long)
// fall by exp(0.8 p / (2 p + 3)) (the fit's error of a smooth field's second derivative within 2 %);
// the finest of two fields bounds them; linear fields and bad options are refused.
TEST(Hessian, VolumeErrorSizesFollowTheLpExponentAndBoundSeveralFields) {
  const IrregularBox box({12, 6, 6}, 0.1);
  const std::vector<double> f = box.sample([](const Vec3& p) { return std::exp(2.0 * p.x()); });
  const auto size_at = [&](const std::vector<double>& sizes, double x) {  // mean over the inner points at x
    double sum = 0.0;
    int count = 0;
    for (size_t v = 0; v < sizes.size(); ++v) {
      const Vec3& p = box.mesh.points[v];
      if (std::abs(p.x() - x) < 0.04 && p.y() > 0.15 && p.y() < 0.45 && p.z() > 0.15 && p.z() < 0.45)
        sum += sizes[v], ++count;
    }
    return sum / count;
  };
  for (double p : {1.0, 2.0, double(INFINITY)}) {
    const std::vector<double> h = volume_error_sizes(box.mesh.points, box.graph, {f}, {.p = p});
    const double expected = std::exp(0.8 * (std::isfinite(p) ? p / (2 * p + 3) : 0.5));
    EXPECT_NEAR(size_at(h, 0.4) / size_at(h, 0.8), expected, 0.02 * expected) << p;
  }
  // A second field of Hessian 200 e_z e_z everywhere is the finer below x = ln(50) / 2 = 1.96: all of the box.
  const std::vector<double> g = box.sample([](const Vec3& p) { return 100.0 * p.z() * p.z(); });
  const std::vector<double> both = volume_error_sizes(box.mesh.points, box.graph, {f, g}, {.p = INFINITY});
  for (double x : {0.2, 0.6, 1.0}) EXPECT_NEAR(size_at(both, x), std::pow(200.0, -0.5), 1e-6) << x;
  const std::vector<double> linear = box.sample([](const Vec3& p) { return 2 * p.x() - p.z(); });
  EXPECT_THROW(volume_error_sizes(box.mesh.points, box.graph, {linear}), InputError);
  EXPECT_THROW(volume_error_sizes(box.mesh.points, box.graph, {f}, {.p = 0.5}), OptionError);
  EXPECT_THROW(volume_error_sizes(box.mesh.points, box.graph, {f}, {.floor = 0.0}), OptionError);
  EXPECT_THROW(volume_error_sizes(box.mesh.points, box.graph, {{1.0, 2.0}}), InputError);
}

}  // namespace
}  // namespace vesselmesh::sizing
