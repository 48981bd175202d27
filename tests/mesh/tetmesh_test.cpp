#include "mesh/tetmesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <random>

namespace vesselmesh::mesh {
namespace {

// A right prism over the triangle (0,0,0), (1,0,0), (0,1,0) facing -z (the wall side, outward),
// extruded to z = 1: TetMesh order, six times its volume is 3.
std::vector<Vec3> right_prism_points() {
  return {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}, {0, 1, 1}, {1, 0, 1}};
}

TEST(SplitPrism, EveryVertexNumberingGivesThreePositiveTetrahedraFillingThePrism) {
  // Every assignment of global numbers to the six corners.
  std::array<int, 6> ids = {0, 1, 2, 3, 4, 5};
  const std::vector<Vec3> reference = right_prism_points();
  int numberings = 0;
  do {
    TetMesh m;
    m.points.resize(6);
    for (int c = 0; c < 6; ++c) m.points[ids[c]] = reference[c];
    const Prism p = {ids[0], ids[1], ids[2], ids[3], ids[4], ids[5]};
    double total = 0.0;
    for (const Tet& t : split_prism(p)) {
      const double v = tet_volume6(m, t);
      EXPECT_GT(v, 0.0);
      total += v;
    }
    EXPECT_NEAR(total, 3.0, 1e-12);
    ++numberings;
  } while (std::next_permutation(ids.begin(), ids.end()));
  EXPECT_EQ(numberings, 720);
}

TEST(SplitPrism, NeighbouringPrismsCutTheirSharedSideAlike) {
  // Two prisms side by side over the square (0,0)-(1,1) cut along its diagonal, with shuffled
  // global numbers: the side they share must vanish from the boundary of their six tetrahedra.
  const std::vector<Vec3> corners = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  for (int seed = 0; seed < 50; ++seed) {
    std::array<int, 8> number;
    std::iota(number.begin(), number.end(), 0);
    std::mt19937 random(seed);
    std::shuffle(number.begin(), number.end(), random);
    TetMesh m;
    m.points.resize(8);
    for (int i = 0; i < 4; ++i) {
      m.points[number[i]] = corners[i];
      m.points[number[i + 4]] = corners[i] + Vec3(0, 0, 1);
    }
    // Bottom triangles facing -z: (0, 2, 1) and (0, 3, 2).
    const Prism a = {number[0], number[2], number[1], number[4], number[6], number[5]};
    const Prism b = {number[0], number[3], number[2], number[4], number[7], number[6]};
    std::vector<Tet> tets;
    for (const Prism& p : {a, b})
      for (const Tet& t : split_prism(p)) {
        EXPECT_GT(tet_volume6(m, t), 0.0);
        tets.push_back(t);
      }
    int nonmanifold = -1;
    // A cube-like box: two triangles on each of its 6 faces (the shared diagonal side gone).
    EXPECT_EQ(tet_boundary(tets, &nonmanifold).size(), 12u) << "seed " << seed;
    EXPECT_EQ(nonmanifold, 0);
  }
}

TEST(TetShape, RegularTetrahedron) {
  const Vec3 a(1, -1, -1), b(1, 1, 1), c(-1, 1, -1), d(-1, -1, 1);
  ASSERT_GT(tet_volume6(a, b, c, d), 0.0);
  for (double angle : dihedral_angles(a, b, c, d)) EXPECT_NEAR(angle, std::acos(1.0 / 3.0), 1e-12);
  EXPECT_NEAR(scaled_jacobian(a, b, c, d), 1.0, 1e-12);
  EXPECT_NEAR(scaled_jacobian(b, a, c, d), -1.0, 1e-12);
}

TEST(TetShape, CornerTetrahedronAnglesAndJacobian) {
  const Vec3 o(0, 0, 0), x(1, 0, 0), y(0, 1, 0), z(0, 0, 1);
  std::array<double, 6> angles = dihedral_angles(o, x, y, z);
  std::sort(angles.begin(), angles.end());
  // Three right angles at the edges through o, three of acos(1/sqrt(3)) at the far face.
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(angles[i], std::acos(1.0 / std::sqrt(3.0)), 1e-12);
  for (int i = 3; i < 6; ++i) EXPECT_NEAR(angles[i], std::numbers::pi / 2, 1e-12);
  // Largest corner product: at x (edges 1, sqrt 2, sqrt 2) = 2; 6V = 1.
  EXPECT_NEAR(scaled_jacobian(o, x, y, z), std::numbers::sqrt2 / 2.0, 1e-12);
}

TEST(TetShape, LeastDihedralAngleIsTheLeastOfTheSix) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coordinate(-1.0, 1.0);
  auto point = [&] { return Vec3(coordinate(random), coordinate(random), coordinate(random)); };
  for (int i = 0; i < 200; ++i) {
    const Vec3 a = point(), b = point(), c = point(), d = point();
    const std::array<double, 6> angles = dihedral_angles(a, b, c, d);
    const double least = *std::min_element(angles.begin(), angles.end());
    EXPECT_NEAR(least_dihedral_angle(a, b, c, d), least, 1e-12);
    EXPECT_NEAR(least_dihedral_angle(b, a, c, d), least, 1e-12);  // either orientation
  }
  EXPECT_NEAR(least_dihedral_angle({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}), std::acos(1.0 / std::sqrt(3.0)), 1e-12);
}

TEST(TetBoundary, OneTetrahedronHasFourOutwardFaces) {
  const std::vector<Tet> tets = {{0, 1, 2, 3}};
  const std::vector<Vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const auto faces = tet_boundary(tets);
  ASSERT_EQ(faces.size(), 4u);
  const Vec3 centre = (p[0] + p[1] + p[2] + p[3]) / 4.0;
  for (const Triangle& f : faces) {
    const Vec3 normal = (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]);
    EXPECT_GT(normal.dot(p[f[0]] - centre), 0.0);
  }
}

TEST(TetBoundary, CountsFacesSharedByThreeTetrahedra) {
  const std::vector<Tet> tets = {{0, 1, 2, 3}, {0, 2, 1, 4}, {0, 1, 2, 5}};
  int nonmanifold = 0;
  tet_boundary(tets, &nonmanifold);
  EXPECT_EQ(nonmanifold, 1);
}

}  // namespace
}  // namespace vesselmesh::mesh
