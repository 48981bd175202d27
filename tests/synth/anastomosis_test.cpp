#include "synth/anastomosis.h"

#include "analysis/open_ends.h"
#include "mesh/clean.h"
#include "mesh/error.h"
#include "mesh/locator.h"
#include "mesh/statistics.h"
#include "post/ring.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace vesselmesh::synth {
namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

// The axis of a straight stretch measured on the surface: the centroids of two plane cuts
// (a cylinder's cut is centred on its axis whatever the plane's tilt).
Vec3 measured_axis(const TriMesh& m, const Vec3& from, const Vec3& direction, double a, double b) {
  const std::vector<Vec3> values(m.points.size(), Vec3::Zero());
  const post::Ring p = post::cut_ring(m, values, {.name = "a", .point = from + a * direction, .normal = direction, .reference = {}});
  const post::Ring q = post::cut_ring(m, values, {.name = "b", .point = from + b * direction, .normal = direction, .reference = {}});
  EXPECT_TRUE(p.closed && q.closed);
  return (q.centroid - p.centroid).normalized();
}

double angle_deg(const Vec3& a, const Vec3& b) { return std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * kDeg; }

TEST(Anastomosis, PassesTheMeshDoctorWithNothingToRepair) {
  const AnastomosisOptions o{.resolution = 0.3};
  TriMesh m = anastomosis(o);
  const mesh::Statistics s = mesh::statistics(m);
  EXPECT_EQ(s.components, 1);
  EXPECT_EQ(s.boundary_loops, 3);
  EXPECT_EQ(s.genus, 0);
  EXPECT_GT(s.volume, 0.0);  // outward
  EXPECT_GT(s.min_angle.min, 5.0);
  EXPECT_GT(s.min_angle.median, 35.0);
  EXPECT_LT(s.edge_length.max, 2.0 * o.resolution);
  EXPECT_NEAR(s.edge_length.mean, o.resolution, 0.15 * o.resolution);
  const mesh::CleanReport report = mesh::clean(m);  // self-intersections included
  for (const auto& [kind, count] : report.defects) EXPECT_EQ(count, 0) << kind;
  EXPECT_EQ(report.total_repairs(), 0);
}

TEST(Anastomosis, EndsHaveTheRequestedRadiiAndRoles) {
  const AnastomosisOptions o{.host_radius = 2.0, .graft_radius = 2.8, .angle_deg = 45.0, .resolution = 0.3};
  const TriMesh m = anastomosis(o);
  const std::vector<analysis::OpenEnd> found = analysis::open_ends(m);
  ASSERT_EQ(found.size(), 3u);
  const AnastomosisLandmarks l = anastomosis_landmarks(o);
  ASSERT_EQ(l.ends.size(), 3u);
  EXPECT_EQ(l.ends[0].name, "inlet");
  EXPECT_EQ(l.ends[1].name, "outlet");
  EXPECT_EQ(l.ends[2].name, "stump");
  const double asked[3] = {o.graft_radius, o.host_radius, o.host_radius};
  for (int k = 0; k < 3; ++k) {
    const analysis::OpenEnd* nearest = nullptr;
    for (const auto& e : found)
      if (!nearest || (e.center - l.ends[k].end.center).norm() < (nearest->center - l.ends[k].end.center).norm())
        nearest = &e;
    EXPECT_LT((nearest->center - l.ends[k].end.center).norm(), 0.05) << l.ends[k].name;
    EXPECT_NEAR(nearest->radius, asked[k], 0.02 * asked[k]) << l.ends[k].name;
    EXPECT_LT(angle_deg(nearest->normal, l.ends[k].end.normal), 1.0) << l.ends[k].name;
  }
  // The flow runs from the graft to the distal host; the stump points the other way.
  EXPECT_GT(l.ends[1].end.center.x(), l.toe.x());
  EXPECT_LT(l.ends[2].end.center.x(), l.heel.x());
}

TEST(Anastomosis, GraftMeetsTheHostAtTheRequestedAngle) {
  for (double angle : {25.0, 45.0, 70.0}) {
    const AnastomosisOptions o{.angle_deg = angle, .graft_bend_deg = 0.0, .resolution = 0.3};
    const TriMesh m = anastomosis(o);
    const AnastomosisLandmarks l = anastomosis_landmarks(o);
    const TubeEnd& inlet = l.ends[0].end;
    const TubeEnd& outlet = l.ends[1].end;
    // Graft: two stations on its straight stretch from the inlet; host: two before the outlet.
    const Vec3 graft = measured_axis(m, inlet.center, -inlet.normal, 1.0 * o.graft_radius, 4.0 * o.graft_radius);
    const Vec3 host = measured_axis(m, outlet.center, -outlet.normal, 1.0 * o.host_radius, 6.0 * o.host_radius);
    EXPECT_NEAR(angle_deg(graft, -host), angle, 2.0) << "angle " << angle;
    EXPECT_NEAR(graft.y(), 0.0, 1e-3);
  }
}

TEST(Anastomosis, BentGraftArrivesFlatterAndTheLandmarksLieOnTheSurface) {
  const AnastomosisOptions o{.angle_deg = 40.0, .graft_bend_deg = 25.0, .resolution = 0.3};
  const TriMesh m = anastomosis(o);
  const AnastomosisLandmarks l = anastomosis_landmarks(o);
  const TubeEnd& inlet = l.ends[0].end;
  const Vec3 graft = measured_axis(m, inlet.center, -inlet.normal, 1.0 * o.graft_radius, 4.0 * o.graft_radius);
  EXPECT_NEAR(angle_deg(graft, Vec3::UnitX()), 15.0, 2.0);
  EXPECT_NEAR(angle_deg(l.graft_direction, Vec3::UnitX()), 40.0, 1e-9);
  // Heel (proximal) before toe (distal), both on the host's top; the floor on its far wall.
  EXPECT_LT(l.heel.x(), l.toe.x());
  EXPECT_GT(l.heel.z(), o.host_radius);
  EXPECT_GT(l.toe.z(), o.host_radius);
  EXPECT_NEAR(l.floor.z(), -o.host_radius, 1e-3);
  // On the exact surface, so off the triangulation by at most its facets' depth: l^2 / (2 rho) for
  // edges l = 0.3 mm over the heel's fillet (rho about a quarter of its 1 mm width) is 0.18 mm;
  // found 0.04 at most.
  const mesh::SurfaceLocator locator(m);
  for (const Vec3& p : {l.heel, l.toe, l.floor}) EXPECT_LT((locator.closest(p).point - p).norm(), 0.06);
  // Ring 1 runs round the mouth of the junction, through heel and toe.
  const std::vector<Vec3> values(m.points.size(), Vec3::Zero());
  const post::Ring ring1 = post::cut_ring(m, values, {.name = "1", .point = l.ring1_point, .normal = l.ring1_normal, .reference = {}});
  EXPECT_TRUE(ring1.closed);
  double to_heel = 1e9, to_toe = 1e9;
  for (const post::RingSample& s : ring1.samples)
    to_heel = std::min(to_heel, (s.point - l.heel).norm()), to_toe = std::min(to_toe, (s.point - l.toe).norm());
  EXPECT_LT(to_heel, 0.3);
  EXPECT_LT(to_toe, 0.3);
  const post::Ring ring2 = post::cut_ring(m, values, {.name = "2", .point = l.ring2_point, .normal = l.ring2_normal, .reference = {}});
  EXPECT_NEAR(ring2.length, 2.0 * std::numbers::pi * o.host_radius, 0.01 * 2.0 * std::numbers::pi * o.host_radius);
}

TEST(Anastomosis, TortuousHostStaysValid) {
  const AnastomosisOptions o{.outlet_length = 70.0, .tortuosity = 4.0, .resolution = 0.35};
  TriMesh m = anastomosis(o);
  const mesh::Statistics s = mesh::statistics(m);
  EXPECT_EQ(s.boundary_loops, 3);
  EXPECT_GT(s.box_max.y() - s.box_min.y(), 2.0 * o.graft_radius + 1.0);  // the S-bend leaves the plane
  EXPECT_EQ(mesh::clean(m).defects.at("self_intersections"), 0);
  // The outlet is straight again: cut normal to x at the requested radius.
  const std::vector<analysis::OpenEnd> ends = analysis::open_ends(m);
  ASSERT_EQ(ends.size(), 3u);
  for (const auto& e : ends) {
    if (e.center.x() > 20.0) {
      EXPECT_NEAR(e.radius, o.host_radius, 0.02 * o.host_radius);
    }
  }
}

TEST(Anastomosis, IsDeterministic) {
  const AnastomosisOptions o{.resolution = 0.4, .jitter = 0.2, .seed = 5};
  const TriMesh a = anastomosis(o), b = anastomosis(o);
  EXPECT_EQ(a.points, b.points);
  EXPECT_EQ(a.triangles, b.triangles);
}

TEST(Anastomosis, BadOptionsAreOptionErrors) {
  EXPECT_THROW(anastomosis({.angle_deg = 5.0}), OptionError);
  EXPECT_THROW(anastomosis({.angle_deg = 30.0, .graft_bend_deg = 40.0}), OptionError);
  EXPECT_THROW(anastomosis({.fillet = 5.0}), OptionError);
  EXPECT_THROW(anastomosis({.stump_length = 2.0}), OptionError);
  EXPECT_THROW(anastomosis({.outlet_length = 20.0, .tortuosity = 2.0}), OptionError);
  EXPECT_THROW(anastomosis({.tortuosity = 20.0}), OptionError);
  EXPECT_THROW(anastomosis({.host_radius = 1.0, .resolution = 0.8}), OptionError);
  EXPECT_THROW(anastomosis({.host_radius = -1.0}), OptionError);
}

}  // namespace
}  // namespace vesselmesh::synth
