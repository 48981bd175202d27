#include "synth/bifurcation.h"

#include "analysis/open_ends.h"
#include "mesh/clean.h"
#include "mesh/error.h"
#include "mesh/statistics.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace vesselmesh::synth
