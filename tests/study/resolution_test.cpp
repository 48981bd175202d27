#include "study/resolution.h"

#include "mesh/tetmesh.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

namespace vesselmesh::study {
namespace {

// A box of n x n x m cubes of side a, each cut into the six tetrahedra of its main diagonal (Kuhn's
// subdivision); its bottom face (z = 0) the wall, the rest of its boundary an end. Every figure is
// known by hand: the wall's right isosceles triangles of legs a have a least altitude a / sqrt 2, so
// a size of 2 / sqrt 3 x a / sqrt 2; the first cells stand a high over the wall; every tetrahedron
// has three edges of a, two of a sqrt 2 and one of a sqrt 3.
struct Box {
  TetMesh volume;
  TriMesh wall;
};

Box kuhn_box(int n, int m, double a) {
  Box box;
  box.volume = test::kuhn_box({n, n, m}, Vec3(n, n, m) * a);
  // The boundary: faces used by one tetrahedron.
  std::map<std::array<int, 3>, std::pair<int, Triangle>> faces;
  for (const Tet& t : box.volume.tets)
    for (int f = 0; f < 4; ++f) {
      Triangle tri = {t[(f + 1) % 4], t[(f + 2) % 4], t[(f + 3) % 4]};
      std::array<int, 3> key = tri;
      std::sort(key.begin(), key.end());
      auto& entry = faces[key];
      ++entry.first;
      entry.second = tri;
    }
  box.volume.tag_names = {{1, "wall"}, {2, "inlet"}};
  box.wall.points = box.volume.points;
  for (const auto& [key, entry] : faces) {
    if (entry.first != 1) continue;
    const bool bottom = box.volume.points[key[0]].z() == 0 && box.volume.points[key[1]].z() == 0 &&
                        box.volume.points[key[2]].z() == 0;
    box.volume.boundary.push_back(entry.second);
    box.volume.boundary_tags.push_back(bottom ? 1 : 2);
    if (bottom) box.wall.triangles.push_back(entry.second);
  }
  return box;
}

TEST(Resolution, MeasuresAHandBuiltBoxAsByHand) {
  const double a = 0.25;
  const Box box = kuhn_box(16, 8, a);  // 4 x 4 wide, 2 high
  ASSERT_EQ(box.wall.triangles.size(), 2u * 16 * 16);
  // Two positions on the wall, inward +z, radius 2: the surface reach 0.4, the interior sampled 1
  // above the wall within 0.5.
  Place place{"point P", {Vec3(2.0, 2.0, 0.0), Vec3(1.1, 2.9, 0.0)}, {Vec3::UnitZ(), Vec3::UnitZ()}, {2.0, 2.0}};
  const std::vector<PlaceResolution> r = measure_resolution(box.wall, box.volume, {place});
  ASSERT_EQ(r.size(), 1u);
  ASSERT_EQ(r[0].surface.size(), 2u);
  const double surface = 2.0 / std::sqrt(3.0) * a / std::sqrt(2.0);
  const double interior = (3.0 + 2.0 * std::sqrt(2.0) + std::sqrt(3.0)) / 6.0 * a;
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(r[0].surface[i], surface, 1e-12) << i;
    EXPECT_NEAR(r[0].first_height[i], a, 1e-12) << i;
    EXPECT_NEAR(r[0].interior[i], interior, 1e-12) << i;
  }
  EXPECT_NEAR(mean_of(r[0].surface), surface, 1e-12);

  // Twice as fine everywhere: twice as fine by each measure.
  const Box fine = kuhn_box(32, 16, a / 2);
  const std::vector<PlaceResolution> f = measure_resolution(fine.wall, fine.volume, {place});
  EXPECT_NEAR(least_ratio(r[0].surface, f[0].surface), 2.0, 1e-9);
  EXPECT_NEAR(least_ratio(r[0].first_height, f[0].first_height), 2.0, 1e-9);
  EXPECT_NEAR(least_ratio(r[0].interior, f[0].interior), 2.0, 1e-9);
}

// The first height at a wall point is its column's (the edge nearest the normal), not a neighbour's
// edge that runs nearly along the wall (as where a layer's wall curves): 0.05, not 0.002.
TEST(Resolution, TheFirstHeightIsTheColumnsNotANeighboursAlongTheWall) {
  TetMesh m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.1, 0.1, 0.05}, {1.5, 0.2, 0.002}};
  m.tets = {{0, 1, 2, 3}, {0, 1, 3, 4}};
  m.boundary = {{0, 2, 1}};
  m.boundary_tags = {1};
  m.tag_names = {{1, "wall"}};
  const std::vector<double> h = first_heights(m);
  ASSERT_EQ(h.size(), 5u);
  EXPECT_NEAR(h[0], 0.05, 1e-12);
  EXPECT_NEAR(h[1], 0.05, 1e-12);  // (-0.9, 0.1, 0.05): nearer the normal than (0.5, 0.2, 0.002)
  EXPECT_TRUE(std::isnan(h[3]));   // off the wall
}

TEST(Resolution, MeansAndRatiosLeaveOutWhatIsNotMeasured) {
  EXPECT_DOUBLE_EQ(mean_of({1.0, NAN, 3.0}), 2.0);
  EXPECT_TRUE(std::isnan(mean_of({NAN})));
  EXPECT_DOUBLE_EQ(least_ratio({2.0, 3.0, NAN}, {1.0, 2.0, 1.0}), 1.5);
  EXPECT_TRUE(std::isnan(least_ratio({NAN}, {1.0})));
}

}  // namespace
}  // namespace vesselmesh::study
