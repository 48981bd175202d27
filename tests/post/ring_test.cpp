#include "post/ring.h"

#include "mesh/error.h"
#include "synth/shapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace vesselmesh::post {
namespace {

constexpr double kPi = std::numbers::pi;

// On a pipe of radius 2 along z: tau = (1 + 0.5 cos theta) e_z + 0.2 e_theta, so its magnitude is
// least (0.5 ... ) at theta = 180 degrees.
struct Pipe {
  TriMesh wall;
  std::vector<Vec3> tau;
};

Vec3 field(const Vec3& p) {
  const double theta = std::atan2(p.y(), p.x());
  const Vec3 e_theta(-std::sin(theta), std::cos(theta), 0.0);
  return (1.0 + 0.5 * std::cos(theta)) * Vec3::UnitZ() + 0.2 * e_theta;
}

RingSpec plane(const std::string& name, const Vec3& point, const Vec3& normal,
               std::optional<Vec3> reference = std::nullopt) {
  RingSpec spec;
  spec.name = name;
  spec.point = point;
  spec.normal = normal;
  spec.reference = reference;
  return spec;
}

Pipe pipe(double shift_x = 0.0) {
  Pipe p;
  p.wall = synth::cylinder({.radius = 2.0, .length = 10.0, .resolution = 0.1, .jitter = 0.2});
  for (Vec3& x : p.wall.points) x.x() += shift_x;
  for (const Vec3& x : p.wall.points) p.tau.push_back(field(x - Vec3(shift_x, 0, 0)));
  return p;
}

TEST(Ring, CutsAPipeIntoItsCircleWithTheFieldAlongIt) {
  const Pipe p = pipe();
  const Ring ring = cut_ring(p.wall, p.tau, plane("mid", Vec3(0.1, -0.2, 5.03), Vec3(0, 0, 2)));
  EXPECT_TRUE(ring.closed);
  EXPECT_EQ(ring.other_loops, 0);
  EXPECT_NEAR(ring.length, 2 * kPi * 2.0, 2e-3 * 2 * kPi * 2.0);  // the inscribed polygon, 0.1 edges
  EXPECT_NEAR(ring.centroid.norm(), 5.03, 1e-2);
  ASSERT_GT(ring.samples.size(), 100u);
  // Starts at angle 0 on +x (the axis least aligned with z), ends there again, counter-clockwise.
  EXPECT_NEAR((ring.samples.front().point - ring.centroid).y(), 0.0, 1e-9);
  EXPECT_GT(ring.samples.front().point.x(), 1.9);
  EXPECT_EQ(ring.samples.front().angle, 0.0);
  EXPECT_EQ(ring.samples.back().angle, 360.0);
  EXPECT_NEAR(ring.samples.back().arc_length, ring.length, 1e-12);
  EXPECT_GT(ring.samples[5].point.y(), 0.0);
  double worst = 0.0;
  for (const RingSample& s : ring.samples) {
    EXPECT_NEAR(s.point.z(), 5.03, 1e-12);
    const Vec3 expected = field(s.point);
    worst = std::max(worst, (s.value - expected).norm());
    EXPECT_NEAR(s.axial, expected.z(), 0.02);
    EXPECT_NEAR(s.circumferential, 0.2, 0.02);
    EXPECT_NEAR(s.magnitude, s.value.norm(), 1e-12);
    const double theta = std::atan2(s.point.y(), s.point.x()) * 180 / kPi;
    EXPECT_NEAR(std::remainder(s.angle - theta, 360.0), 0.0, 1.0) << s.angle;
  }
  EXPECT_LT(worst, 0.02);  // linear interpolation of a smooth field on 0.1 edges
  const RingSample& least = ring.samples[ring.minimum];
  EXPECT_NEAR(least.angle, 180.0, 5.0);
  EXPECT_NEAR(least.magnitude, std::hypot(0.5, 0.2), 2e-3);
}

// Rings of two meshes compared point by point: the magnitude at even angles follows the field's,
// |tau| = sqrt((1 + 0.5 cos theta)^2 + 0.04), on a coarse and a fine pipe alike; an open ring by
// the fraction of its length.
TEST(Ring, ResampledAtEvenAnglesAlikeOnTwoMeshes) {
  const Pipe fine = pipe();
  Pipe coarse;
  coarse.wall = synth::cylinder({.radius = 2.0, .length = 10.0, .resolution = 0.3, .jitter = 0.2});
  for (const Vec3& x : coarse.wall.points) coarse.tau.push_back(field(x));
  const RingSpec spec = plane("mid", Vec3(0, 0, 5.03), Vec3(0, 0, 1));
  const std::vector<double> a = resampled_magnitude(cut_ring(fine.wall, fine.tau, spec), 72);
  const std::vector<double> b = resampled_magnitude(cut_ring(coarse.wall, coarse.tau, spec), 72);
  ASSERT_EQ(a.size(), 72u);
  ASSERT_EQ(b.size(), 72u);
  for (int k = 0; k < 72; ++k) {
    const double theta = 2 * kPi * k / 72, exact = std::hypot(1.0 + 0.5 * std::cos(theta), 0.2);
    EXPECT_NEAR(a[k], exact, 0.02) << k;
    EXPECT_NEAR(b[k], exact, 0.06) << k;
  }
  Ring open = cut_ring(fine.wall, fine.tau, spec);
  open.closed = false;
  const std::vector<double> by_length = resampled_magnitude(open, 4);
  EXPECT_NEAR(by_length[0], open.samples.front().magnitude, 1e-12);
  EXPECT_NEAR(by_length[2], std::hypot(0.5, 0.2), 0.02);  // half way round: theta = 180 degrees
}

TEST(Ring, ReversedNormalTurnsTheOtherWay) {
  const Pipe p = pipe();
  const Ring ring = cut_ring(p.wall, p.tau, plane("r", Vec3(0, 0, 4), Vec3(0, 0, -1)));
  // Counter-clockwise about -z is clockwise about z: just after the start, y < 0.
  EXPECT_LT(ring.samples[5].point.y(), 0.0);
  EXPECT_NEAR(ring.samples[ring.minimum].angle, 180.0, 5.0);
  EXPECT_NEAR(ring.samples[5].axial, -ring.samples[5].value.z(), 1e-12);
  // A reference direction moves the start.
  const Ring turned = cut_ring(p.wall, p.tau, plane("t", Vec3(0, 0, 4), Vec3(0, 0, 1), Vec3(0, 1, 0)));
  EXPECT_NEAR((turned.samples.front().point - turned.centroid).x(), 0.0, 1e-9);
  EXPECT_GT(turned.samples.front().point.y(), 1.9);
}

TEST(Ring, TakesTheLoopNearestThePointAndCountsTheOthers) {
  Pipe a = pipe(), b = pipe(10.0);
  const int offset = static_cast<int>(a.wall.points.size());
  a.wall.points.insert(a.wall.points.end(), b.wall.points.begin(), b.wall.points.end());
  a.tau.insert(a.tau.end(), b.tau.begin(), b.tau.end());
  for (Triangle t : b.wall.triangles) {
    for (int& v : t) v += offset;
    a.wall.triangles.push_back(t);
  }
  const Ring ring = cut_ring(a.wall, a.tau, plane("far", Vec3(9.5, 0, 5), Vec3(0, 0, 1)));
  EXPECT_EQ(ring.other_loops, 1);
  EXPECT_NEAR(ring.centroid.x(), 10.0, 1e-2);
}

TEST(Ring, ATiltedPlaneGivesAnEllipse) {
  const Pipe p = pipe();
  const double tilt = 30.0 * kPi / 180.0;
  const Ring ring = cut_ring(p.wall, p.tau, plane("e", Vec3(0, 0, 5), Vec3(std::sin(tilt), 0, std::cos(tilt))));
  // Semi-axes 2 and 2 / cos(30): Ramanujan's perimeter.
  const double a = 2.0 / std::cos(tilt), b = 2.0;
  const double h = std::pow((a - b) / (a + b), 2);
  const double perimeter = kPi * (a + b) * (1 + 3 * h / (10 + std::sqrt(4 - 3 * h)));
  EXPECT_NEAR(ring.length, perimeter, 3e-3 * perimeter);
}

TEST(Ring, OpenWhereThePlaneRunsOutOfTheWallAndRefusesAMiss) {
  const Pipe p = pipe();
  // A plane along the axis cuts the open pipe into two lines running end to end.
  const Ring line = cut_ring(p.wall, p.tau, plane("side", Vec3(1.9, 0, 5), Vec3(1, 0, 0)));
  EXPECT_FALSE(line.closed);
  EXPECT_NEAR(line.length, 10.0, 0.1);
  try {
    cut_ring(p.wall, p.tau, plane("miss", Vec3(0, 0, 20), Vec3(0, 0, 1)));
    FAIL() << "a plane beyond the pipe";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("ring miss"), std::string::npos) << e.what();
  }
  EXPECT_THROW(cut_ring(p.wall, std::vector<Vec3>(3), plane("n", Vec3(0, 0, 5), Vec3(0, 0, 1))), InputError);
}

TEST(Ring, PlacedNormalToACenterline) {
  centerline::Centerlines c;
  centerline::Branch b;
  for (int k = 0; k <= 20; ++k) {
    const double s = 0.5 * k;  // a quarter circle of radius 20 in the xz plane
    b.points.emplace_back(20.0 - 20.0 * std::cos(s / 20.0), 0.0, 20.0 * std::sin(s / 20.0));
  }
  c.branches.push_back(b);
  const Vec3 near = b.points[10] + Vec3(0.3, 1.0, 0.0);
  const RingSpec spec = centerline_ring(c, "c", near);
  EXPECT_EQ(spec.name, "c");
  EXPECT_LT((spec.point - b.points[10]).norm(), 0.35);
  const Vec3 tangent = Vec3(std::sin(5.0 / 20.0), 0, std::cos(5.0 / 20.0));
  EXPECT_GT(spec.normal.dot(tangent), std::cos(2.0 * kPi / 180.0));
  EXPECT_THROW(centerline_ring(centerline::Centerlines{}, "none", near), InputError);
}

TEST(PointProbe, InterpolatesAtTheNearestWallLocation) {
  Pipe p = pipe();
  for (size_t i = 0; i < p.tau.size(); ++i) p.tau[i] = Vec3(p.wall.points[i].z(), 2.0, 0.0);  // linear in z
  const std::vector<PointProbe> probes = probe_points(p.wall, p.tau, {{"A", Vec3(3.0, 0.0, 4.321)}, {"B", Vec3(0, 0.5, 7)}});
  ASSERT_EQ(probes.size(), 2u);
  EXPECT_EQ(probes[0].name, "A");
  EXPECT_NEAR(probes[0].point.z(), 4.321, 1e-2);
  EXPECT_NEAR(probes[0].distance, 1.0, 0.01);
  EXPECT_NEAR(probes[0].value.x(), probes[0].point.z(), 1e-9);  // exact for a linear field
  EXPECT_NEAR(probes[0].value.y(), 2.0, 1e-12);
  EXPECT_NEAR(probes[1].point.y(), 2.0, 0.01);
  EXPECT_NEAR(probes[1].value.x(), probes[1].point.z(), 1e-9);
}

}  // namespace
}  // namespace vesselmesh::post
