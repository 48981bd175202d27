#include "remesh/extend.h"

#include "analysis/open_ends.h"
#include "io/surface.h"
#include "io/units.h"
#include "mesh/clean.h"
#include "mesh/connectivity.h"
#include "mesh/error.h"
#include "mesh/self_intersections.h"
#include "synth/shapes.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace vesselmesh::remesh {
namespace {

double degrees(double radians) { return radians * 180.0 / std::numbers::pi; }

// The largest angle between the normals of a wall triangle on an extended end's loop and the
// tube triangle across that loop edge (0: no crease).
double largest_crease(const TriMesh& extended, int old_triangles, const std::vector<int>& loop) {
  const mesh::EdgeMap edges = mesh::build_edge_map(extended);
  const auto normal = [&](int t) {
    const Triangle& f = extended.triangles[t];
    return Vec3((extended.points[f[1]] - extended.points[f[0]]).cross(extended.points[f[2]] - extended.points[f[0]]))
        .normalized();
  };
  double worst = 0.0;
  for (int e = 0; e < edges.num_edges(); ++e) {
    const auto [a, b] = edges.edges[e];
    if (std::find(loop.begin(), loop.end(), a) == loop.end() || std::find(loop.begin(), loop.end(), b) == loop.end())
      continue;
    const auto around = edges.triangles_of(e);
    if (around.size() != 2) continue;
    const int wall = std::min(around[0], around[1]), tube = std::max(around[0], around[1]);
    if (wall >= old_triangles || tube < old_triangles) continue;
    worst = std::max(worst, degrees(std::acos(std::clamp(normal(wall).dot(normal(tube)), -1.0, 1.0))));
  }
  return worst;
}

// The checks every extension must pass: the input kept as it was (its points and triangles
// first), the mesh doctor with nothing to mend and no self-intersection, as many ends as before,
// each extended end moved by length x its radius along its normal (2 %) with its radius (1 %).
void expect_extended(const TriMesh& input, const std::vector<analysis::OpenEnd>& ends, const ExtensionResult& r,
                     double length) {
  const TriMesh& out = r.mesh;
  ASSERT_GE(out.num_points(), input.num_points());
  for (int k = 0; k < input.num_points(); ++k) ASSERT_EQ(out.points[k], input.points[k]);
  for (int t = 0; t < input.num_triangles(); ++t) ASSERT_EQ(out.triangles[t], input.triangles[t]);
  TriMesh doctored = out;
  const mesh::CleanReport report = mesh::clean(doctored);
  EXPECT_EQ(report.total_repairs(), 0);
  EXPECT_TRUE(mesh::self_intersecting_pairs(out).empty());
  const std::vector<analysis::OpenEnd> now = analysis::open_ends(out);
  ASSERT_EQ(now.size(), ends.size());
  for (const ExtendedEnd& x : r.extended) {
    const analysis::OpenEnd& before = ends[x.end];
    const auto moved = std::min_element(now.begin(), now.end(), [&](const auto& a, const auto& b) {
      return (a.center - x.center).norm() < (b.center - x.center).norm();
    });
    SCOPED_TRACE(::testing::Message() << "end " << x.end);
    EXPECT_NEAR((moved->center - before.center).norm(), length * before.radius, 0.02 * length * before.radius);
    EXPECT_NEAR((moved->center - before.center).normalized().dot(before.normal), 1.0, 1e-3);
    EXPECT_NEAR(moved->radius, before.radius, 0.01 * before.radius);
    EXPECT_NEAR(moved->normal.dot(before.normal), 1.0, 1e-6);  // cut normal to the axis
    EXPECT_NEAR(x.length, length * before.radius, 1e-9 * x.length);
  }
}

TEST(Extend, APipesEndsMoveByTheirLengthInRadii) {
  const TriMesh pipe = synth::cylinder({.radius = 2.0, .length = 10.0, .resolution = 0.4});
  const auto ends = analysis::open_ends(pipe);
  ASSERT_EQ(ends.size(), 2u);
  const ExtensionResult r = extend_ends(pipe, ends, {.length = 5.0});
  ASSERT_EQ(r.extended.size(), 2u);
  expect_extended(pipe, ends, r, 5.0);
  // The tube's rings about the wall's triangle height apart: its edges within the wall's range.
  const mesh::EdgeMap edges = mesh::build_edge_map(r.mesh);
  double shortest = 1e300, longest = 0.0;
  for (const auto& [a, b] : edges.edges) {
    if (a < pipe.num_points() && b < pipe.num_points()) continue;
    const double l = (r.mesh.points[a] - r.mesh.points[b]).norm();
    shortest = std::min(shortest, l);
    longest = std::max(longest, l);
  }
  EXPECT_GT(shortest, 0.5 * 0.4);
  EXPECT_LT(longest, 2.0 * 0.4);
  // One end only, by index, and a shorter tube.
  const ExtensionResult one = extend_ends(pipe, ends, {.length = 2.0, .ends = {1}});
  ASSERT_EQ(one.extended.size(), 1u);
  EXPECT_EQ(one.extended[0].end, 1);
  expect_extended(pipe, ends, one, 2.0);
}

// A flaring end (a cone whose radius grows 20 % a radius along it): in smooth mode the tube leaves
// the wall in its own direction (no crease at the loop); straight, it turns there by the cone's
// angle (measured: 1.8-1.9 and 11.2-11.3 degrees at the two ends, the cone 11.3). Labels follow the wall.
TEST(Extend, SmoothModeLeavesNoCrease) {
  TriMesh cone = synth::cylinder({.radius = 2.0, .length = 10.0, .resolution = 0.4});
  for (Vec3& p : cone.points) {
    const double grow = 1.0 + 0.2 * p.z() / 2.0;
    p.x() *= grow;
    p.y() *= grow;
  }
  cone.labels.assign(cone.triangles.size(), 7);
  const auto ends = analysis::open_ends(cone);
  const ExtensionResult smooth = extend_ends(cone, ends, {.length = 4.0, .mode = ExtensionMode::smooth});
  const ExtensionResult straight = extend_ends(cone, ends, {.length = 4.0, .mode = ExtensionMode::straight});
  expect_extended(cone, ends, smooth, 4.0);
  expect_extended(cone, ends, straight, 4.0);
  const double cone_angle = degrees(std::atan(0.2));  // 11.3 degrees
  for (const analysis::OpenEnd& end : ends) {
    const double s = largest_crease(smooth.mesh, cone.num_triangles(), end.loop);
    const double t = largest_crease(straight.mesh, cone.num_triangles(), end.loop);
    EXPECT_LT(s, 0.35 * cone_angle) << "smooth";
    EXPECT_GT(t, 0.6 * cone_angle) << "straight";
  }
  ASSERT_EQ(smooth.mesh.labels.size(), smooth.mesh.triangles.size());
  EXPECT_TRUE(std::all_of(smooth.mesh.labels.begin(), smooth.mesh.labels.end(), [](int l) { return l == 7; }));
}

TEST(Extend, RefusesCappedEndsAndNonPositiveLengths) {
  const TriMesh pipe = synth::cylinder({.radius = 2.0, .length = 10.0, .resolution = 0.4});
  auto ends = analysis::open_ends(pipe);
  const auto message = [&](const ExtensionOptions& o) {
    try {
      extend_ends(pipe, ends, o);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message({.length = 0.0}).find("positive length"), std::string::npos);
  EXPECT_NE(message({.length = 5.0, .ends = {2}}).find("the surface has 2 ends"), std::string::npos);
  ends[0].capped = true;
  EXPECT_NE(message({.length = 5.0, .ends = {0}}).find("is capped"), std::string::npos);
  EXPECT_EQ(message({.length = 5.0}), "");  // every open end: the capped one left out
  EXPECT_EQ(parse_extension_mode("straight"), ExtensionMode::straight);
  EXPECT_THROW(parse_extension_mode("curved"), InputError);
}

// Every open end of the shared vessels (inward-oriented files, three units): the doctor finds
// nothing to mend, the ends move by five radii and keep their radii.
struct Vessel {
  const char* name;
  const char* file;
  const char* units;
};
class ExtendVessel : public ::testing::TestWithParam<Vessel> {};

TEST_P(ExtendVessel, EveryEndExtended) {
  VESSELMESH_REQUIRE_SHARED(path, std::string("vessels/") + GetParam().file);
  io::SurfaceFile file = io::read_surface(path, {.units = io::parse_unit(GetParam().units)});
  mesh::clean(file.mesh, {.find_self_intersections = false});
  const auto ends = analysis::open_ends(file.mesh);
  const ExtensionResult r = extend_ends(file.mesh, ends, {.length = 5.0});
  EXPECT_EQ(r.extended.size(), ends.size());
  expect_extended(file.mesh, ends, r, 5.0);
}

INSTANTIATE_TEST_SUITE_P(Shared, ExtendVessel,
                         ::testing::Values(Vessel{"aorta", "vmtk_aorta_iliac_bifurcation_open_mm.stl", "mm"},
                                           Vessel{"arch", "gmsh_aortic_arch_open_cm.stl", "cm"},
                                           Vessel{"carotid", "gmsh_carotid_bifurcation_open_m.stl", "m"}),
                         [](const auto& param_info) { return std::string(param_info.param.name); });

}  // namespace
}  // namespace vesselmesh::remesh
