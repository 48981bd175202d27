#include "volume/sliver.h"

#include "synth/shapes.h"
#include "test_support.h"
#include "volume/fill.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace vesselmesh::volume {
namespace {

double volume_of(const std::vector<Vec3>& p, const std::vector<Tet>& tets) {
  double v = 0.0;
  for (const Tet& t : tets) v += mesh::tet_volume6(p[t[0]], p[t[1]], p[t[2]], p[t[3]]) / 6.0;
  return v;
}

double least_of(const std::vector<Vec3>& p, const std::vector<Tet>& tets) {
  double least = 1e300;
  for (const Tet& t : tets) least = std::min(least, least_dihedral_deg(p[t[0]], p[t[1]], p[t[2]], p[t[3]]));
  return least;
}

// What every clean-up must keep: the boundary faces, the fixed points, the volume, no
// inverted tetrahedron, a least angle no lower than before.
void expect_kept(const std::vector<Vec3>& points_before, const std::vector<Tet>& tets_before,
                 const std::vector<Vec3>& points, const std::vector<Tet>& tets, int first_free) {
  EXPECT_EQ(mesh::tet_boundary(tets), mesh::tet_boundary(tets_before));
  for (int i = 0; i < first_free; ++i) ASSERT_EQ(points[i], points_before[i]) << "fixed point " << i << " moved";
  const double volume = volume_of(points_before, tets_before);
  EXPECT_NEAR(volume_of(points, tets), volume, 1e-12 * std::abs(volume));
  for (const Tet& t : tets) EXPECT_GT(mesh::tet_volume6(points[t[0]], points[t[1]], points[t[2]], points[t[3]]), 0.0);
  int nonmanifold = 0;
  mesh::tet_boundary(tets, &nonmanifold);
  EXPECT_EQ(nonmanifold, 0);
  EXPECT_GE(least_of(points, tets), least_of(points_before, tets_before));
  // No point is left out (a solver's matrix would get an empty row).
  std::vector<char> used(points.size(), 0);
  for (const Tet& t : tets)
    for (int v : t) used[v] = 1;
  EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0);
}

TEST(LeastDihedral, RegularCornerAndFlat) {
  const double s = 1.0 / std::sqrt(2.0);
  // Regular tetrahedron: acos(1/3) = 70.5288 degrees everywhere.
  EXPECT_NEAR(least_dihedral_deg({-1, 0, -s}, {1, 0, -s}, {0, 1, s}, {0, -1, s}), 70.528779, 1e-5);
  // The corner of a cube: 90 degrees at the three axes, acos(1/sqrt(3)) = 54.7356 at the others.
  EXPECT_NEAR(least_dihedral_deg({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}), 54.735610, 1e-5);
  // Inverted and flat: negative.
  EXPECT_LT(least_dihedral_deg({0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}), 0.0);
  EXPECT_LT(least_dihedral_deg({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}), 0.0);
}

// Two flat tetrahedra on either side of a large triangle: the 2-3 flip makes three around the
// short edge joining their tips.
TEST(Slivers, TwoThreeFlip) {
  const double h = 0.03;
  std::vector<Vec3> points = {{0, 0, 0}, {1, 0, 0}, {0.5, 0.8660254, 0}, {0.5, 0.2886751, h}, {0.5, 0.2886751, -h}};
  std::vector<Tet> tets = {{0, 1, 2, 3}, {0, 2, 1, 4}};
  const auto points_before = points;
  const auto tets_before = tets;
  ASSERT_LT(least_of(points, tets), 10.0);
  const SliverReport r = remove_slivers(points, tets, 5);
  EXPECT_EQ(r.below_before, 2);
  EXPECT_EQ(r.flips, 1);
  EXPECT_EQ(r.insertions, 0);
  EXPECT_EQ(tets.size(), 3u);
  expect_kept(points_before, tets_before, points, tets, 5);
  // Each new one spans the short edge (3, 4) against an edge of the triangle: 2 atan(h / inradius).
  EXPECT_NEAR(r.least_after, 2.0 * std::atan(h / 0.2886751) * 180.0 / std::numbers::pi, 1e-3);
  EXPECT_EQ(r.below_after, 0);
}

// A sliver lying on two nearly coplanar boundary triangles, under a tent: all its corners are
// on the boundary, so only a flip can remove it: the edge across it (3 tetrahedra) goes.
TEST(Slivers, BoundarySliverUnderATentIsFlippedAway) {
  std::vector<Vec3> points = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0.05}, {0, 1, 0.05}, {0, 0, 1}};
  // The sliver (a, b, c, d) and the two tetrahedra joining its upper faces to the tip e.
  std::vector<Tet> tets = {{0, 1, 3, 2}, {0, 2, 3, 4}, {1, 3, 2, 4}};
  for (Tet& t : tets)
    if (mesh::tet_volume6(points[t[0]], points[t[1]], points[t[2]], points[t[3]]) < 0) std::swap(t[0], t[1]);
  const auto points_before = points;
  const auto tets_before = tets;
  const SliverReport r = remove_slivers(points, tets, 5);
  EXPECT_LT(r.least_before, 10.0);
  EXPECT_EQ(r.flips, 1);
  EXPECT_EQ(tets.size(), 2u);  // (a, b, e, c) and (a, b, e, d)
  expect_kept(points_before, tets_before, points, tets, 5);
  EXPECT_EQ(r.below_after, 0);
  EXPECT_GT(r.least_after, 20.0);
}

// A good fill of a ball, spoiled: inside points pushed almost onto a face of their ball makes
// slivers, which the clean-up must remove with the surface kept.
TEST(Slivers, AnInsidePointNoPlaceSuitsIsCollapsed) {
  // A flat tetrahedron (base of side 1, apex 0.08 above its centre: least angle
  // atan(0.08 / 0.2887) = 15.5 degrees) split in four at a free point p. Wherever p goes, one of
  // the four is under 10 degrees (the one on the base needs p 0.051 up, where the three against
  // the apex's faces flatten); no flip applies (every edge of p has three tetrahedra whose ring
  // is the far face). The cure is to remove p: one tetrahedron again, p dropped.
  const double s3 = std::sqrt(3.0);
  std::vector<Vec3> points = {{0, 0, 0}, {1, 0, 0}, {0.5, s3 / 2, 0}, {0.5, s3 / 6, 0.08}, {0.5, s3 / 6, 0.04}};
  const Tet whole = {0, 1, 2, 3};
  ASSERT_GT(mesh::tet_volume6(points[0], points[1], points[2], points[3]), 0.0);
  std::vector<Tet> tets;
  for (int c = 0; c < 4; ++c) {
    Tet t = whole;
    t[c] = 4;
    tets.push_back(t);
  }
  const auto points_before = points;
  const auto tets_before = tets;
  const SliverReport r = remove_slivers(points, tets, 4);
  EXPECT_GT(r.below_before, 0);
  EXPECT_EQ(r.collapses, 1);
  ASSERT_EQ(points.size(), 4u);
  ASSERT_EQ(tets.size(), 1u);
  expect_kept(points_before, tets_before, points, tets, 4);
  EXPECT_NEAR(r.least_after, std::atan(0.08 / (s3 / 6)) * 180.0 / std::numbers::pi, 1e-6);
  EXPECT_EQ(r.below_after, 0);
}

TEST(Slivers, SpoiledFillIsRepaired) {
  const TriMesh sphere = synth::sphere({.radius = 2.0, .resolution = 0.4, .jitter = 0.2});
  FillResult fill = fill_tetrahedra(sphere.points, sphere.triangles, FillAlgorithm::tetgen);
  const int first_free = static_cast<int>(sphere.points.size());
  ASSERT_GT(static_cast<int>(fill.points.size()), first_free + 20);
  // Every 7th inside point moved 92 % of the way to the centroid of the face across it in its
  // first tetrahedron (a flat, valid tetrahedron), where no other tetrahedron turns over.
  int spoiled = 0;
  for (int v = first_free; v < static_cast<int>(fill.points.size()); v += 7) {
    for (const Tet& t : fill.tets) {
      const auto at = std::find(t.begin(), t.end(), v);
      if (at == t.end()) continue;
      Vec3 face = Vec3::Zero();
      for (int w : t)
        if (w != v) face += fill.points[w] / 3.0;
      const Vec3 old = fill.points[v];
      fill.points[v] = old + 0.92 * (face - old);
      bool valid = true;
      for (const Tet& u : fill.tets)
        valid = valid && mesh::tet_volume6(fill.points[u[0]], fill.points[u[1]], fill.points[u[2]], fill.points[u[3]]) > 0;
      if (valid) ++spoiled;
      else fill.points[v] = old;
      break;
    }
  }
  ASSERT_GT(spoiled, 3);
  const auto points_before = fill.points;
  const auto tets_before = fill.tets;
  const SliverReport r = remove_slivers(fill.points, fill.tets, first_free);
  std::printf("spoiled %d points: %d tetrahedra under 10 deg (least %.2f) -> %d (least %.2f); %d flips, %d moves, %d "
              "insertions\n",
              spoiled, r.below_before, r.least_before, r.below_after, r.least_after, r.flips, r.moves, r.insertions);
  EXPECT_GE(r.below_before, spoiled);
  EXPECT_LT(r.least_before, 5.0);
  expect_kept(points_before, tets_before, fill.points, fill.tets, first_free);
  EXPECT_EQ(r.below_after, 0);
  EXPECT_GE(r.least_after, 10.0);
  EXPECT_NEAR(least_of(fill.points, fill.tets), r.least_after, 1e-9);
  // The same input gives the same mesh.
  std::vector<Vec3> points_again = points_before;
  std::vector<Tet> tets_again = tets_before;
  remove_slivers(points_again, tets_again, first_free);
  EXPECT_EQ(points_again, fill.points);
  EXPECT_EQ(tets_again, fill.tets);
}

}  // namespace
}  // namespace vesselmesh::volume
