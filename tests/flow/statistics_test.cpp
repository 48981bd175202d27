#include "flow/statistics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace vesselmesh::flow {
namespace {

// u = a + b sin(2 pi t / T) sampled at N equal steps over one period: the mean a and the RMS of the
// fluctuation |b| / sqrt 2 exactly (the sums of sin and sin^2 over a whole period, N >= 3).
TEST(FlowStatistics, ASineOverAPeriodHasItsMeanAndAmplitudeOverRootTwo) {
  const double period = 0.8, a = 0.3, b = -0.12;
  const int steps = 40;
  const double dt = period / steps;
  FlowStatistics s;
  for (int k = 1; k <= steps; ++k) {
    const double t = 0.5 + k * dt, wave = std::sin(2 * std::numbers::pi * t / period);
    // Point 0 oscillates along x, point 1 along y and z at other amplitudes; pressure a + 10 b sin.
    s.add(t, dt, {Vec3(a + b * wave, -1.0, 2.0), Vec3(0.0, 2 * b * wave, a - 3 * b * wave)},
          {100 * a + 10 * b * wave, 7.0});
  }
  EXPECT_EQ(s.steps(), steps);
  EXPECT_NEAR(s.state().start, 0.5, 1e-12);
  EXPECT_NEAR(s.state().end, 0.5 + period, 1e-12);
  EXPECT_NEAR(s.state().weight, period, 1e-12);
  const std::vector<Vec3> rms = s.rms_velocity();
  const double amplitude = std::abs(b) / std::sqrt(2.0);
  EXPECT_NEAR((s.mean_velocity()[0] - Vec3(a, -1.0, 2.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((rms[0] - Vec3(amplitude, 0.0, 0.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((s.mean_velocity()[1] - Vec3(0.0, 0.0, a)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((rms[1] - Vec3(0.0, 2 * amplitude, 3 * amplitude)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(s.mean_pressure()[0], 100 * a, 1e-10);
  EXPECT_NEAR(s.mean_pressure()[1], 7.0, 1e-12);
}

// Each step counts for its length: 1 s at 1 m/s and 3 s at 5 m/s have the mean 4 and the variance
// (1 x 9 + 3 x 1) / 4 = 3.
TEST(FlowStatistics, UnequalStepsWeighByTheirLength) {
  FlowStatistics s;
  s.add(1.0, 1.0, {Vec3(1.0, 0.0, 0.0)}, {2.0});
  s.add(4.0, 3.0, {Vec3(5.0, 0.0, 0.0)}, {6.0});
  EXPECT_NEAR(s.mean_velocity()[0].x(), 4.0, 1e-14);
  EXPECT_NEAR(s.rms_velocity()[0].x(), std::sqrt(3.0), 1e-14);
  EXPECT_NEAR(s.mean_pressure()[0], 5.0, 1e-14);
  EXPECT_DOUBLE_EQ(s.state().start, 0.0);
  // Carried on from its state (a checkpoint's) as if never stopped.
  FlowStatistics resumed(s.state());
  resumed.add(6.0, 2.0, {Vec3(-2.0, 0.0, 0.0)}, {0.0});
  s.add(6.0, 2.0, {Vec3(-2.0, 0.0, 0.0)}, {0.0});
  EXPECT_EQ(resumed.steps(), 3);
  EXPECT_DOUBLE_EQ(resumed.rms_velocity()[0].x(), s.rms_velocity()[0].x());
  EXPECT_NEAR(resumed.mean_velocity()[0].x(), (1.0 + 15.0 - 4.0) / 6.0, 1e-14);
}

// A fluctuation a billionth of the mean (a laminar flow's round-off): E[u^2] - E[u]^2 would lose it
// to cancellation (1e-12 of 1e3^2 is 1e-6, a spread of 1e-3); West's update keeps it.
TEST(FlowStatistics, SmallFluctuationsOnALargeMeanKeepTheirSize) {
  FlowStatistics s;
  for (int k = 1; k <= 1000; ++k)
    s.add(0.001 * k, 0.001, {Vec3(1e3 + (k % 2 ? 1e-6 : -1e-6), 0.0, 0.0)}, {0.0});
  EXPECT_NEAR(s.rms_velocity()[0].x(), 1e-6, 1e-9);
  const std::vector<Field> f = s.fields();
  ASSERT_EQ(f.size(), 3u);
  EXPECT_EQ(f[0].name, "mean_velocity");
  EXPECT_EQ(f[0].components, 3);
  EXPECT_EQ(f[1].name, "rms_velocity");
  EXPECT_EQ(f[2].name, "mean_pressure");
  EXPECT_EQ(f[2].count(), 1);
}

}  // namespace
}  // namespace vesselmesh::flow
