#include "synth/bifurcation.h"

#include "analysis/open_ends.h"
#include "mesh/clean.h"
#include "mesh/error.h"
#include "mesh/statistics.h"

#include <gtest/gtest.h>

#include <cmath>

namespace vesselmesh::synth {
namespace {

TEST(Bifurcation, PassesTheMeshDoctorWithNothingToRepair) {
  TriMesh m = bifurcation({.resolution = 0.5});
  const mesh::Statistics s = mesh::statistics(m);
  EXPECT_EQ(s.components, 1);
  EXPECT_EQ(s.boundary_loops, 3);
  EXPECT_EQ(s.genus, 0);
  EXPECT_GT(s.volume, 0.0);
  EXPECT_GT(s.min_angle.min, 5.0);
  EXPECT_GT(s.min_angle.median, 35.0);
  EXPECT_LT(s.edge_length.max, 2.0 * 0.5);
  const mesh::CleanReport report = mesh::clean(m);
  for (const auto& [kind, count] : report.defects) EXPECT_EQ(count, 0) << kind;
  EXPECT_EQ(report.total_repairs(), 0);
}

TEST(Bifurcation, IsDeterministicAndJitterKeepsItValid) {
  const TriMesh a = bifurcation({.resolution = 0.6, .jitter = 0.3, .seed = 3});
  const TriMesh b = bifurcation({.resolution = 0.6, .jitter = 0.3, .seed = 3});
  EXPECT_EQ(a.points, b.points);
  EXPECT_EQ(a.triangles, b.triangles);
  TriMesh c = a;
  EXPECT_EQ(mesh::clean(c).defects.at("self_intersections"), 0);
  EXPECT_EQ(analysis::open_ends(a).size(), 3u);
}

TEST(Bifurcation, BadOptionsAreOptionErrors) {
  EXPECT_THROW(bifurcation({.angle_deg = {2.0, 35.0}}), OptionError);
  EXPECT_THROW(bifurcation({.daughter_length = 3.0}), OptionError);
  EXPECT_THROW(bifurcation({.radius = 1.0, .resolution = 0.8}), OptionError);
  EXPECT_THROW(bifurcation({.angle_deg = {5.0, 5.0}, .daughter_length = 10.0}), OptionError);
}

// A bifurcation aneurysm: the dome on the daughters' bisector, its far side a radius beyond the
// centre (the smooth union only adds near the neck), the vessel otherwise as without it (the
// same ends); a sound surface; a dome that reaches the ends or is too small for the resolution is
// refused.
TEST(Bifurcation, AnAneurysmSitsAtTheApex) {
  const BifurcationOptions plain{.radius = 1.5, .daughter_radius = {1.1, 1.0}, .angle_deg = {55.0, 55.0},
                                 .parent_length = 12.0, .daughter_length = 12.0, .blend = 0.8, .resolution = 0.25};
  BifurcationOptions with = plain;
  with.aneurysm_radius = 2.5;
  TriMesh dome = bifurcation(with);
  const TriMesh without = bifurcation(plain);
  const Vec3 centre = aneurysm_center(with);
  EXPECT_NEAR(centre.x(), 0.0, 1e-12);  // symmetric angles: the bisector is +z
  EXPECT_NEAR(centre.z(), 1.1 / std::sin(55.0 * M_PI / 180.0) + 0.7 * 2.5, 1e-12);
  double far = 0.0;  // the highest point on the axis (the daughters rise higher aside)
  for (const Vec3& p : dome.points)
    if (std::hypot(p.x(), p.y()) < 0.3) far = std::max(far, p.z());
  EXPECT_NEAR(far, centre.z() + 2.5, 0.02);
  const mesh::Statistics s = mesh::statistics(dome), s0 = mesh::statistics(without);
  EXPECT_EQ(s.boundary_loops, 3);
  EXPECT_EQ(s.genus, 0);
  EXPECT_GT(s.volume, s0.volume + 0.5 * 4.0 / 3.0 * M_PI * std::pow(2.5, 3));  // most of the sphere added
  const auto ends = analysis::open_ends(dome), ends0 = analysis::open_ends(without);
  ASSERT_EQ(ends.size(), 3u);
  for (size_t e = 0; e < 3; ++e) EXPECT_LT((ends[e].center - ends0[e].center).norm(), 0.01);
  const mesh::CleanReport report = mesh::clean(dome);
  EXPECT_EQ(report.defects.at("self_intersections"), 0);
  with.aneurysm_radius = 9.0;
  EXPECT_THROW(bifurcation(with), OptionError);
  with.aneurysm_radius = 0.4;  // under twice the resolution
  EXPECT_THROW(bifurcation(with), OptionError);
  with.aneurysm_radius = -1.0;
  EXPECT_THROW(bifurcation(with), OptionError);
}

}  // namespace
}  // namespace vesselmesh::synth
