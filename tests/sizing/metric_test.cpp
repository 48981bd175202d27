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

TEST(Metric, LogEuclideanInterpolationStaysSpdAndIsGeometricForIsotropicMetrics) {
  const Sym3 a = metric_from_sizes(Vec3::UnitX(), 1.0, Vec3::UnitY(), 0.25, Vec3::UnitZ(), 2.0);
  const Sym3 back = metric_exp(metric_log(a));
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(back.v[i], a.v[i], 1e-12 * 16.0);
  // Halfway between sizes 1 and 4 (isotropic): the geometric mean, size 2.
  const Sym3 logs[2] = {metric_log(isotropic_metric(1.0)), metric_log(isotropic_metric(4.0))};
  const double weights[2] = {0.5, 0.5};
  const Sym3 mid = interpolate_logs(logs, weights, 2);
  EXPECT_NEAR(metric_length(mid, Vec3(2.0, 0, 0)), 1.0, 1e-12);
  // Two crossed anisotropic metrics: the mean is SPD, its sizes between theirs.
  const Sym3 crossed[2] = {metric_log(metric_from_sizes(Vec3::UnitX(), 4.0, Vec3::UnitY(), 0.5, Vec3::UnitZ(), 1.0)),
                           metric_log(metric_from_sizes(Vec3::UnitY(), 4.0, Vec3::UnitX(), 0.5, Vec3::UnitZ(), 1.0))};
  Vec3 sizes;
  Eigen::Matrix3d directions;
  metric_sizes(interpolate_logs(crossed, weights, 2), sizes, directions);
  EXPECT_GT(sizes.minCoeff(), 0.5 - 1e-12);
  EXPECT_LT(sizes.maxCoeff(), 4.0 + 1e-12);
  EXPECT_NEAR(sizes[0], 1.0, 1e-9);  // sqrt(4 * 0.5) = 1.41 in x and y, 1 in z
  EXPECT_NEAR(sizes[2], std::sqrt(2.0), 1e-9);
}

TEST(Metric, EdgeLengthAndQualityInTheMetric) {
  // A metric stretched along x by 4: an equilateral triangle in the metric is 4 times wider.
  const Sym3 m = metric_from_sizes(Vec3::UnitX(), 4.0, Vec3::UnitY(), 1.0, Vec3::UnitZ(), 1.0);
  const Vec3 a(0, 0, 0), b(4, 0, 0), c(2, std::sqrt(3.0) / 2.0, 0);
  EXPECT_NEAR(edge_length(a, b, m, m), 1.0, 1e-12);
  EXPECT_NEAR(triangle_quality(a, b, c, m, m, m), 1.0, 1e-12);
  const Sym3 iso = isotropic_metric(1.0);
  EXPECT_LT(triangle_quality(a, b, c, iso, iso, iso), 0.5);  // flat in Euclidean terms
  // Between two sizes the length is measured with both ends' metrics (between 1 and 2 here).
  const double l = edge_length(a, Vec3(1, 0, 0), isotropic_metric(1.0), isotropic_metric(0.5));
  EXPECT_GT(l, 1.0);
  EXPECT_LT(l, 2.0);
}

}  // namespace
}  // namespace vesselmesh::sizing
