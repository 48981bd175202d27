#include "mesh/locator.h"

#include "synth/shapes.h"
#include "test_support.h"

#include <gtest/gtest.h>

namespace vesselmesh::mesh {
namespace {

TEST(Locator, ClosestPointOnASphere) {
  const TriMesh m = synth::sphere({.radius = 2.0, .resolution = 0.1});
  const SurfaceLocator locator(m);
  for (const Vec3& p : {Vec3(0, 0, 0.5), Vec3(3, 1, -1), Vec3(0.1, -1.5, 0.2)}) {
    const auto hit = locator.closest(p);
    EXPECT_NEAR(hit.distance, std::abs(p.norm() - 2.0), 2e-3);  // the polyhedron is within 1e-3 of the sphere
    EXPECT_NEAR(hit.point.norm(), 2.0, 2e-3);
    EXPECT_GE(hit.triangle, 0);
    EXPECT_LT(hit.triangle, m.num_triangles());
  }
}

TEST(Locator, InsideAClosedSurface) {
  const InsideTest inside(synth::sphere({.radius = 2.0, .resolution = 0.3}));
  EXPECT_TRUE(inside.inside(Vec3(0, 0, 0)));
  EXPECT_TRUE(inside.inside(Vec3(1.5, 0.5, 0.2)));
  EXPECT_FALSE(inside.inside(Vec3(2.5, 0, 0)));
  EXPECT_FALSE(inside.inside(Vec3(0, 0, -7)));
}

TEST(Locator, ClosestPointOnSegments) {
  const SegmentLocator locator({{Vec3(0, 0, 0), Vec3(10, 0, 0)}, {Vec3(10, 0, 0), Vec3(10, 10, 0)}});
  auto hit = locator.closest(Vec3(2.5, 1, 0));
  EXPECT_EQ(hit.segment, 0);
  EXPECT_NEAR(hit.t, 0.25, 1e-12);
  EXPECT_NEAR(hit.distance, 1.0, 1e-12);
  hit = locator.closest(Vec3(12, 7, 0));
  EXPECT_EQ(hit.segment, 1);
  EXPECT_NEAR(hit.t, 0.7, 1e-12);
  EXPECT_NEAR(hit.distance, 2.0, 1e-12);
}

}  // namespace
}  // namespace vesselmesh::mesh
