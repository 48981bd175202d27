#include "synth/shapes.h"

#include "analysis/open_ends.h"
#include "mesh/clean.h"
#include "mesh/error.h"
#include "mesh/geometry.h"
#include "mesh/statistics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace vesselmesh::synth {
namespace {

constexpr double kPi = std::numbers::pi;

// Every triangle faces the same way as the given outward direction at its centroid.
template <typename Outward>
void expect_facing_outward(const TriMesh& m, Outward outward) {
  for (int t = 0; t < m.num_triangles(); ++t) {
    const Vec3 n = mesh::triangle_area_vector(m, t);
    ASSERT_GT(n.dot(outward(mesh::triangle_centroid(m, t))), 0.0) << "triangle " << t;
  }
}

TEST(Shapes, SpherePointsLieOnTheSphereAlsoWhenJittered) {
  for (double jitter : {0.0, 0.3}) {
    const Vec3 centre(1, 2, 3);
    const TriMesh m = sphere({.radius = 5.0, .center = centre, .resolution = 0.5, .jitter = jitter});
    for (const Vec3& p : m.points) EXPECT_NEAR((p - centre).norm(), 5.0, 1e-12);
    expect_facing_outward(m, [&](const Vec3& c) { return Vec3(c - centre); });
    const mesh::Statistics s = mesh::statistics(m);
    EXPECT_TRUE(s.closed);
    EXPECT_EQ(s.genus, 0);
    // Geodesic edges vary by up to 1.3 h; jitter moves both ends by up to 0.3 of a step.
    EXPECT_LE(s.edge_length.max, 0.5 * (1.3 + 2.2 * jitter));
  }
}

TEST(Shapes, JitterIsSeededAndMakesTheMeshIrregular) {
  const TriMesh a = sphere({.radius = 2.0, .resolution = 0.3, .jitter = 0.3, .seed = 5});
  const TriMesh b = sphere({.radius = 2.0, .resolution = 0.3, .jitter = 0.3, .seed = 5});
  const TriMesh c = sphere({.radius = 2.0, .resolution = 0.3, .jitter = 0.3, .seed = 6});
  const TriMesh plain = sphere({.radius = 2.0, .resolution = 0.3});
  EXPECT_EQ(a.points, b.points);
  EXPECT_NE(a.points, c.points);
  const auto sa = mesh::statistics(a), sp = mesh::statistics(plain);
  EXPECT_LT(sa.min_angle.min, sp.min_angle.min - 5.0);
  EXPECT_GT(sa.min_angle.min, 5.0);  // irregular, not broken
}

TEST(Shapes, EllipsoidPointsSatisfyItsEquation) {
  const Vec3 axes(6, 4, 3);
  const TriMesh m = ellipsoid({.semi_axes = axes, .resolution = 0.4, .jitter = 0.3});
  for (const Vec3& p : m.points) EXPECT_NEAR(p.cwiseQuotient(axes).squaredNorm(), 1.0, 1e-12);
  expect_facing_outward(m, [&](const Vec3& c) { return Vec3(c.cwiseQuotient(axes.cwiseProduct(axes))); });
  EXPECT_LE(mesh::statistics(m).edge_length.max, 0.4 * (1.3 + 2.2 * 0.3));
}

TEST(Shapes, CylinderPointsLieOnTheCylinder) {
  const double R = 3.0, L = 20.0;
  const TriMesh m = cylinder({.radius = R, .length = L, .resolution = 0.5, .jitter = 0.3});
  for (const Vec3& p : m.points) {
    EXPECT_NEAR(p.head<2>().norm(), R, 1e-12);
    EXPECT_GE(p.z(), 0.0);
    EXPECT_LE(p.z(), L);
  }
  expect_facing_outward(m, [](const Vec3& c) { return Vec3(c.x(), c.y(), 0.0); });
  // Jitter moves rim points along the rim only: the ends stay planar.
  for (const auto& end : analysis::open_ends(m))
    for (int v : end.loop) EXPECT_TRUE(m.points[v].z() == 0.0 || m.points[v].z() == L);
}

TEST(Shapes, DiagonalsAreRandomOrRegular) {
  const TriMesh random = cylinder({.radius = 2, .length = 5, .resolution = 0.5});
  const TriMesh regular = cylinder({.radius = 2, .length = 5, .resolution = 0.5, .random_diagonals = false});
  EXPECT_EQ(random.points, regular.points);
  EXPECT_NE(random.triangles, regular.triangles);
}

TEST(Shapes, CappedCylinderIsClosedWithLabelledCaps) {
  const TriMesh m = cylinder({.radius = 2, .length = 6, .resolution = 0.3, .capped = true});
  const mesh::Statistics s = mesh::statistics(m);
  EXPECT_TRUE(s.closed);
  EXPECT_EQ(s.genus, 0);
  EXPECT_NEAR(s.volume, kPi * 4 * 6, 0.01 * kPi * 4 * 6);
  EXPECT_GT(s.min_angle.min, 15.0);  // rings, not a fan
  ASSERT_EQ(m.labels.size(), m.triangles.size());
  TriMesh copy = m;
  EXPECT_EQ(mesh::clean(copy).total_repairs(), 0);
}

TEST(Shapes, TorusPointsSatisfyItsEquation) {
  const double R = 10, r = 3;
  const TriMesh m = torus({.major_radius = R, .minor_radius = r, .resolution = 0.5, .jitter = 0.3});
  for (const Vec3& p : m.points) {
    const double q = p.head<2>().norm() - R;
    EXPECT_NEAR(q * q + p.z() * p.z(), r * r, 1e-9);
  }
  expect_facing_outward(m, [&](const Vec3& c) {
    const Vec3 axis_point = R * Vec3(c.x(), c.y(), 0.0).normalized();
    return Vec3(c - axis_point);
  });
  EXPECT_EQ(mesh::statistics(m).genus, 1);
}

TEST(Shapes, BendIsATubeAroundItsCenterline) {
  const BendOptions o{.radius = 2.0, .bend_radius = 10.0, .angle_deg = 120.0, .resolution = 0.4, .jitter = 0.3};
  const TriMesh m = bend(o);
  const double length = bend_length(o);
  EXPECT_NEAR(length, 10 + 10 * 2 * kPi / 3 + 10, 1e-12);
  for (size_t i = 0; i < m.points.size(); i += 7) {
    const Vec3& p = m.points[i];
    // Closest centerline point by sampling, then refining by ternary search.
    double best = 0.0, best_d = 1e300;
    for (int k = 0; k <= 2000; ++k) {
      const double s = length * k / 2000;
      const double d = (bend_centerline(o, s).position - p).norm();
      if (d < best_d) best_d = d, best = s;
    }
    double lo = std::max(0.0, best - length / 2000), hi = std::min(length, best + length / 2000);
    for (int it = 0; it < 100; ++it) {
      const double a = lo + (hi - lo) / 3, b = hi - (hi - lo) / 3;
      if ((bend_centerline(o, a).position - p).norm() < (bend_centerline(o, b).position - p).norm()) hi = b;
      else lo = a;
    }
    EXPECT_NEAR((bend_centerline(o, lo).position - p).norm(), o.radius, 1e-6) << "point " << i;
  }
  const auto ends = analysis::open_ends(m);
  ASSERT_EQ(ends.size(), 2u);
  const Vec3 inlet_normal(0, -1, 0), outlet_normal = bend_centerline(o, length).tangent;
  for (const auto& e : ends)
    EXPECT_GT(std::max(e.normal.dot(inlet_normal), e.normal.dot(outlet_normal)), 1.0 - 1e-9);
}

TEST(Shapes, NozzleLiesOnTheFdaProfileWithItsEndsAndCreases) {
  const NozzleOptions o;  // the FDA benchmark's sizes, sudden-expansion orientation
  const TriMesh m = nozzle(o);
  const double cone = 4.0 / std::tan(10.0 * kPi / 180.0);  // 22.685 mm
  const auto [z_in, z_out] = nozzle_extent(o);
  EXPECT_NEAR(z_in, -(40.0 + cone + 40.0), 1e-9);
  EXPECT_NEAR(z_out, 120.0, 1e-9);
  EXPECT_DOUBLE_EQ(nozzle_radius(o, -70.0), 6.0);
  EXPECT_NEAR(nozzle_radius(o, -40.0 - cone / 2), 4.0, 1e-12);
  EXPECT_DOUBLE_EQ(nozzle_radius(o, -20.0), 2.0);
  EXPECT_DOUBLE_EQ(nozzle_radius(o, 0.0), 6.0);  // the step's plane: the larger radius
  int on_step = 0;
  for (const Vec3& p : m.points) {
    const double r = std::hypot(p.x(), p.y());
    if (p.z() == 0.0) {
      ++on_step;
      EXPECT_TRUE(r > 2.0 - 1e-9 && r < 6.0 + 1e-9) << r;
    } else {
      ASSERT_NEAR(r, nozzle_radius(o, p.z()), 1e-9) << p.transpose();
    }
  }
  EXPECT_GT(on_step, 100);
  // Outward: away from the axis, and against the flow on the step (the fluid lies downstream).
  expect_facing_outward(m, [](const Vec3& c) { return c.z() == 0.0 ? Vec3(0, 0, -1) : Vec3(c.x(), c.y(), 0); });
  const mesh::Statistics st = mesh::statistics(m);
  EXPECT_EQ(st.boundary_loops, 2);
  const double volume = kPi * (36.0 * 160.0 + 4.0 * 40.0) + kPi * cone / 3.0 * (36.0 + 12.0 + 4.0);
  EXPECT_NEAR(st.volume, volume, 0.003 * volume);  // polygons inside the circles
  EXPECT_GT(st.min_angle.min, 30.0);
  const std::vector<analysis::OpenEnd> ends = analysis::open_ends(m);
  ASSERT_EQ(ends.size(), 2u);
  for (const analysis::OpenEnd& e : ends) {
    EXPECT_TRUE(std::abs(e.center.z() - z_in) < 1e-9 || std::abs(e.center.z() - z_out) < 1e-9) << e.center.z();
    EXPECT_NEAR(e.radius, 6.0, 0.02);
  }
}

TEST(Shapes, ConicalDiffuserIsTheMirrorImage) {
  const NozzleOptions se{.inlet_length = 10.0, .outlet_length = 30.0, .resolution = 0.8};
  NozzleOptions cd = se;
  cd.orientation = NozzleOrientation::conical_diffuser;
  // The diffuser's inlet pipe is the expansion's outlet pipe seen from the other side.
  NozzleOptions mirrored = se;
  std::swap(mirrored.inlet_length, mirrored.outlet_length);
  for (double z = -80.0; z <= 80.0; z += 0.37)
    if (std::abs(z) > 1e-9) {
      EXPECT_DOUBLE_EQ(nozzle_radius(cd, z), nozzle_radius(mirrored, -z)) << z;
    }
  EXPECT_NEAR(nozzle_extent(cd).first, -10.0, 1e-9);
  const TriMesh m = nozzle(cd);
  for (const Vec3& p : m.points)
    if (p.z() != 0.0) {
      ASSERT_NEAR(std::hypot(p.x(), p.y()), nozzle_radius(cd, p.z()), 1e-9) << p.transpose();
    }
  expect_facing_outward(m, [](const Vec3& c) { return c.z() == 0.0 ? Vec3(0, 0, 1) : Vec3(c.x(), c.y(), 0); });
  EXPECT_GT(mesh::statistics(m).volume, 0.0);
}

TEST(Shapes, BadOptionsAreOptionErrors) {
  EXPECT_THROW(nozzle({.throat_radius = 6.5}), OptionError);
  EXPECT_THROW(nozzle({.cone_half_angle_deg = 90.0}), OptionError);
  EXPECT_THROW(nozzle({.inlet_length = -1.0}), OptionError);
  EXPECT_THROW(nozzle({.jitter = 0.1}), OptionError);
  EXPECT_THROW(sphere({.radius = -1.0}), OptionError);
  EXPECT_THROW(sphere({.radius = 1.0, .resolution = 0.0}), OptionError);
  EXPECT_THROW(sphere({.radius = 1.0, .resolution = 1e-5}), OptionError);  // billions of triangles
  EXPECT_THROW(cylinder({.jitter = 0.9}), OptionError);
  EXPECT_THROW(torus({.major_radius = 2.0, .minor_radius = 3.0}), OptionError);
  EXPECT_THROW(bend({.radius = 3.0, .bend_radius = 2.0}), OptionError);
  EXPECT_THROW(bend({.angle_deg = 270.0}), OptionError);
  EXPECT_THROW(ellipsoid({.semi_axes = Vec3(1, 0, 1)}), OptionError);
}

}  // namespace
}  // namespace vesselmesh::synth
