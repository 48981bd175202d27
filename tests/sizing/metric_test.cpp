#include "sizing/metric.h"

#include <gtest/gtest.h>

#include <cmath>

namespace vesselmesh::sizing {
namespace {

TEST(Metric, IsotropicAndDirectionalSizes) {
  const Sym3 iso = isotropic_metric(0.5);
  EXPECT_NEAR(metric_length(iso, Vec3(1, 0, 0)), 2.0, 1e-12);
  EXPECT_NEAR(metric_length(iso, Vec3(0, 0.5, 0)), 1.0, 1e-12);
  const Vec3 d1 = Vec3(1, 1, 0).normalized(), d2 = Vec3(-1, 1, 0).normalized(), d3(0, 0, 1);
  const Sym3 m = metric_from_sizes(d1, 2.0, d2, 0.5, d3, 1.0);
  EXPECT_NEAR(metric_length(m, 2.0 * d1), 1.0, 1e-12);
  EXPECT_NEAR(metric_length(m, 0.5 * d2), 1.0, 1e-12);
  Vec3 sizes;
  Eigen::Matrix3d directions;
  metric_sizes(m, sizes, directions);
  EXPECT_NEAR(sizes[0], 0.5, 1e-12);  // ascending sizes
  EXPECT_NEAR(sizes[2], 2.0, 1e-12);
  EXPECT_NEAR(std::abs(directions.col(0).dot(d2)), 1.0, 1e-12);
  EXPECT_NEAR(std::abs(directions.col(2).dot(d1)), 1.0, 1e-12);
}

TEST(Metric, IntersectionIsFinerThanBothAndExactForAlignedMetrics) {
  const Sym3 a = metric_from_sizes(Vec3::UnitX(), 1.0, Vec3::UnitY(), 0.5, Vec3::UnitZ(), 2.0);
  const Sym3 b = metric_from_sizes(Vec3::UnitX(), 0.5, Vec3::UnitY(), 1.0, Vec3::UnitZ(), 3.0);
  const Sym3 c = intersect(a, b);
  EXPECT_NEAR(metric_length(c, Vec3::UnitX()), 2.0, 1e-9);  // sizes 0.5, 0.5, 2
  EXPECT_NEAR(metric_length(c, Vec3::UnitY()), 2.0, 1e-9);
  EXPECT_NEAR(metric_length(c, Vec3::UnitZ()), 0.5, 1e-9);
  // Rotated metrics: every direction at least as fine as in either input.
  const Sym3 d = metric_from_sizes(Vec3(1, 1, 0).normalized(), 0.3, Vec3(-1, 1, 0).normalized(), 2.0, Vec3::UnitZ(), 1.0);
  const Sym3 e = intersect(a, d);
  for (const Vec3& v : {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0), Vec3(1, -1, 0.3), Vec3(0.2, 0.5, 1)}) {
    EXPECT_GE(metric_length(e, v), metric_length(a, v) - 1e-9);
    EXPECT_GE(metric_length(e, v), metric_length(d, v) - 1e-9);
  }
  EXPECT_EQ(intersect(a, a).v, intersect(a, a).v);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(intersect(a, a).v[i], a.v[i], 1e-9);
}

TEST(Metric, ClampScaleAndTangentDensity) {
  const Sym3 m = metric_from_sizes(Vec3::UnitX(), 0.1, Vec3::UnitY(), 5.0, Vec3::UnitZ(), 1.0);
  const Sym3 c = clamp_sizes(m, 0.2, 2.0);
  EXPECT_NEAR(metric_length(c, Vec3::UnitX()), 5.0, 1e-9);
  EXPECT_NEAR(metric_length(c, Vec3::UnitY()), 0.5, 1e-9);
  EXPECT_NEAR(metric_length(c, Vec3::UnitZ()), 1.0, 1e-9);
  EXPECT_NEAR(metric_length(scale_sizes(m, 2.0), Vec3::UnitZ()), 0.5, 1e-12);
  // In the plane z = const the sizes are 0.1 and 5: density 1 / (0.1 * 5).
  EXPECT_NEAR(tangent_density(m, Vec3::UnitZ()), 2.0, 1e-9);
  EXPECT_NEAR(tangent_density(isotropic_metric(0.5), Vec3(1, 2, 3).normalized()), 4.0, 1e-9);
}

}  // namespace
}  // namespace vesselmesh::sizing
