#include "mesh/decimate.h"

#include "mesh/connectivity.h"
#include "synth/shapes.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace vesselmesh::mesh {
namespace {

// A sphere of radius 5 (about 20k triangles) made coarser for display: at most the asked count,
// not far under it, still closed, its volume within 1 % and every point within 2 % of the radius
// from the sphere.
TEST(Decimate, ASphereKeepsItsShapeUnderTheAskedCount) {
  const TriMesh sphere = synth::sphere({.radius = 5.0, .resolution = 0.18});
  ASSERT_GT(sphere.num_triangles(), 15000);
  const TriMesh coarse = decimated(sphere, 2000);
  EXPECT_LE(coarse.num_triangles(), 2000);
  EXPECT_GE(coarse.num_triangles(), 1700);
  EXPECT_TRUE(boundary_loops(coarse, build_edge_map(coarse)).empty());
  const double exact = 4.0 / 3.0 * std::numbers::pi * 125.0;
  EXPECT_NEAR(test::enclosed_volume(coarse.points, coarse.triangles), exact, 0.01 * exact);
  for (const Vec3& p : coarse.points) EXPECT_NEAR(p.norm(), 5.0, 0.1);
}

// An open pipe: its two rims stay (the boundary kept), and a surface under the count comes back as it was.
TEST(Decimate, AnOpenPipeKeepsItsRimsAndASmallSurfaceIsKept) {
  const TriMesh pipe = synth::cylinder({.radius = 3.0, .length = 30.0, .resolution = 0.2});
  const TriMesh coarse = decimated(pipe, pipe.num_triangles() / 8);
  EXPECT_LE(coarse.num_triangles(), pipe.num_triangles() / 8);
  double low = INFINITY, high = -INFINITY;
  for (const Vec3& p : coarse.points) {
    low = std::min(low, p.z());
    high = std::max(high, p.z());
    EXPECT_NEAR(std::hypot(p.x(), p.y()), 3.0, 0.06);
  }
  EXPECT_NEAR(low, 0.0, 1e-9);
  EXPECT_NEAR(high, 30.0, 1e-9);
  const TriMesh same = decimated(pipe, pipe.num_triangles());
  EXPECT_EQ(same.triangles, pipe.triangles);
  EXPECT_EQ(same.points, pipe.points);
}

}  // namespace
}  // namespace vesselmesh::mesh
