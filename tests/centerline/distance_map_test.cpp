#include "centerline/distance_map.h"

#include "analysis/analytic_curvature.h"
#include "io/surface.h"
#include "mesh/error.h"
#include "mesh/clean.h"
#include "synth/bifurcation.h"
#include "synth/shapes.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>

namespace vesselmesh::centerline {
namespace {

TEST(DistanceMap, PipeWallIsOneRadiusAway) {
  const double R = 3.0;
  const TriMesh m = synth::cylinder({.radius = R, .length = 20, .resolution = 0.3, .jitter = 0.3});
  const DistanceMap map = distance_map(m, extract(m));
  ASSERT_EQ(map.distance.size(), m.points.size());
  for (size_t v = 0; v < m.points.size(); ++v) {
    EXPECT_NEAR(map.distance[v], R, 0.01 * R) << v;
    EXPECT_NEAR(map.radius[v], R, 0.015 * R) << v;
  }
}

TEST(DistanceMap, DaughtersAreSmallerThanTheParent) {
  const synth::BifurcationOptions o{.radius = 3.0, .daughter_radius = {1.8, 2.4}, .resolution = 0.4};
  const TriMesh m = synth::bifurcation(o);
  const DistanceMap map = distance_map(m, extract(m));
  for (size_t v = 0; v < m.points.size(); ++v) {
    const Vec3& p = m.points[v];
    if (p.z() < -8.0) {  // parent
      EXPECT_NEAR(map.distance[v], 3.0, 0.05) << v;
    } else if (p.z() > 12.0 && p.x() > 0.0) {  // daughter 1
      EXPECT_NEAR(map.distance[v], 1.8, 0.05) << v;
    } else if (p.z() > 12.0 && p.x() < 0.0) {  // daughter 2
      EXPECT_NEAR(map.radius[v], 2.4, 0.08) << v;
    }
  }
}

TEST(DistanceMap, RealVesselDistancesMatchTheRadius) {
  VESSELMESH_REQUIRE_SHARED(path, "vessels/vmtk_aorta_iliac_bifurcation_open_mm.stl");
  io::SurfaceFile file = io::read_surface(path);
  mesh::clean(file.mesh);
  const DistanceMap map = distance_map(file.mesh, extract(file.mesh));
  std::vector<double> ratio;
  for (size_t v = 0; v < map.distance.size(); ++v) {
    ASSERT_TRUE(std::isfinite(map.distance[v]) && map.radius[v] > 0.0);
    ratio.push_back(map.distance[v] / map.radius[v]);
  }
  std::nth_element(ratio.begin(), ratio.begin() + static_cast<std::ptrdiff_t>(ratio.size() / 2), ratio.end());
  EXPECT_NEAR(ratio[ratio.size() / 2], 1.0, 0.1);  // the wall is about one radius from the centerline
}

// Inner poles: on a closed torus (no ends, so no centerlines) the radius is the tube's, r; the
// big circle R is the ball of no point.
TEST(PoleRadius, ClosedTorusGivesTheTubeRadius) {
  const double r = 3.0;
  const TriMesh m = synth::torus({.major_radius = 10, .minor_radius = r, .resolution = 0.3, .jitter = 0.3});
  EXPECT_THROW(extract(m), InputError);
  const std::vector<double> radius = pole_radius(m);
  ASSERT_EQ(radius.size(), m.points.size());
  EXPECT_NEAR(test::quantile(radius, 0.5), r, 0.03 * r);
  EXPECT_GT(test::quantile(radius, 0.01), 0.9 * r);
  EXPECT_LT(test::quantile(radius, 0.99), 1.1 * r);
}

TEST(PoleRadius, OpenPipeAndBifurcationAgreeWithTheDistanceMap) {
  const TriMesh pipe = synth::cylinder({.radius = 3.0, .length = 20, .resolution = 0.3, .jitter = 0.3});
  const std::vector<double> radius = pole_radius(pipe);
  for (size_t v = 0; v < pipe.points.size(); ++v) {
    if (std::abs(pipe.points[v].z() - 10.0) < 6.0) {
      EXPECT_NEAR(radius[v], 3.0, 0.1 * 3.0) << v;
    }
  }
  const TriMesh y = synth::bifurcation({.radius = 3.0, .daughter_radius = {1.8, 2.4}, .resolution = 0.4});
  const std::vector<double> poles = pole_radius(y);
  const DistanceMap map = distance_map(y, extract(y));
  std::vector<double> ratio;
  for (size_t v = 0; v < poles.size(); ++v) ratio.push_back(poles[v] / map.radius[v]);
  EXPECT_NEAR(test::quantile(ratio, 0.5), 1.0, 0.05);
  EXPECT_GT(test::quantile(ratio, 0.05), 0.8);
  EXPECT_LT(test::quantile(ratio, 0.95), 1.25);
}

TEST(PoleRadius, RealVesselAgreesWithTheDistanceMap) {
  VESSELMESH_REQUIRE_SHARED(path, "vessels/vmtk_aorta_iliac_bifurcation_open_mm.stl");
  io::SurfaceFile file = io::read_surface(path);
  mesh::clean(file.mesh);
  const std::vector<double> poles = pole_radius(file.mesh);
  const DistanceMap map = distance_map(file.mesh, extract(file.mesh));
  std::vector<double> ratio;
  for (size_t v = 0; v < poles.size(); ++v) ratio.push_back(poles[v] / map.radius[v]);
  EXPECT_NEAR(test::quantile(ratio, 0.5), 1.0, 0.1);
  EXPECT_GT(test::quantile(ratio, 0.05), 0.75);
}

}  // namespace
}  // namespace vesselmesh::centerline
