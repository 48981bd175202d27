#include "post/indices.h"

#include "mesh/error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace vesselmesh::post {
namespace {

constexpr double kPi = std::numbers::pi;

// One period T sampled at n + 1 times (both ends), tau(t) given per point.
template <class F>
WssIndices over_one_period(double T, int n, F tau) {
  WssIndexAccumulator a;
  for (int k = 0; k <= n; ++k) {
    const double t = T * k / n;
    a.add(t, tau(t));
  }
  return a.result();
}

TEST(WssIndices, SteadyForwardShear) {
  // tau = 2 e_z + 0.5 sin(wt) e_z: never reverses. TAWSS = 2, OSI = 0, RRT = 1/2,
  // TWSSG = (1/T) int |0.5 w cos wt| dt = 4 * 0.5 / T.
  const double T = 0.8, w = 2 * kPi / T;
  const WssIndices r = over_one_period(T, 4000, [&](double t) {
    return std::vector<Vec3>{Vec3(0, 0, 2.0 + 0.5 * std::sin(w * t))};
  });
  EXPECT_EQ(r.samples, 4001);
  EXPECT_DOUBLE_EQ(r.start, 0.0);
  EXPECT_NEAR(r.end, T, 1e-12);
  EXPECT_NEAR(r.tawss[0], 2.0, 1e-6);
  EXPECT_NEAR(r.osi[0], 0.0, 1e-9);
  EXPECT_NEAR(r.rrt[0], 0.5, 1e-6);
  EXPECT_NEAR(r.twssg[0], 2.0 / T, 1e-5);
}

TEST(WssIndices, PurelyOscillatingShear) {
  // tau = sin(wt) e_x: TAWSS = 2/pi, the mean vector is zero, OSI = 1/2, RRT undefined (NaN).
  const double T = 1.0, w = 2 * kPi / T;
  const WssIndices r = over_one_period(T, 2000, [&](double t) {
    return std::vector<Vec3>{Vec3(std::sin(w * t), 0, 0), Vec3(0.3, 0, 0)};
  });
  EXPECT_NEAR(r.tawss[0], 2.0 / kPi, 1e-6);
  EXPECT_NEAR(r.osi[0], 0.5, 1e-9);
  EXPECT_TRUE(std::isnan(r.rrt[0]));
  EXPECT_NEAR(r.twssg[0], 4.0 / T, 1e-4);
  // The second point is constant: TAWSS = 0.3, OSI = 0, RRT = 1/0.3, TWSSG = 0.
  EXPECT_NEAR(r.tawss[1], 0.3, 1e-12);
  EXPECT_NEAR(r.osi[1], 0.0, 1e-12);
  EXPECT_NEAR(r.rrt[1], 1.0 / 0.3, 1e-9);
  EXPECT_NEAR(r.twssg[1], 0.0, 1e-12);
}

TEST(WssIndices, RotatingShearHasHalfOsiAndConstantMagnitude) {
  // A vector of length 1.5 turning once: TAWSS = 1.5, OSI = 1/2, |d tau/dt| = 1.5 w.
  const double T = 0.5, w = 2 * kPi / T;
  const WssIndices r = over_one_period(T, 3000, [&](double t) {
    return std::vector<Vec3>{1.5 * Vec3(std::cos(w * t), std::sin(w * t), 0)};
  });
  EXPECT_NEAR(r.tawss[0], 1.5, 1e-9);
  EXPECT_NEAR(r.osi[0], 0.5, 1e-6);
  EXPECT_NEAR(r.twssg[0], 1.5 * w, 1e-3 * 1.5 * w);
}

TEST(WssIndices, PartlyReversingShearMatchesItsIntegrals) {
  // tau = (0.2 + sin wt) e_z reverses for part of the cycle: with s0 = asin(0.2) it is negative
  // for wt in (pi + s0, 2 pi - s0), and int_0^{2 pi} |a + sin x| dx = 4 a s0 + 4 cos s0.
  const double T = 1.0, w = 2 * kPi / T, a = 0.2;
  const double s0 = std::asin(a);
  const double magnitude = (4.0 * a * s0 + 4.0 * std::cos(s0)) / (2 * kPi);  // the mean of |tau|
  const WssIndices r = over_one_period(T, 20000, [&](double t) {
    return std::vector<Vec3>{Vec3(0, 0, a + std::sin(w * t))};
  });
  EXPECT_NEAR(r.tawss[0], magnitude, 1e-6);
  EXPECT_NEAR(r.osi[0], 0.5 * (1.0 - a / magnitude), 1e-6);
  EXPECT_NEAR(r.rrt[0], 1.0 / a, 1e-5);
  EXPECT_NEAR((r.mean[0] - Vec3(0, 0, a)).norm(), 0.0, 1e-9);  // the time mean: the vector's, a e_z
}

// The time-mean vector of a shear turning and reversing: (0.3 + cos wt, 0.1 + sin wt, -0.2) over a period
// has the mean (0.3, 0.1, -0.2), whose length is TAWSS (1 - 2 OSI).
TEST(WssIndices, TheMeanVectorIsTheTimeMean) {
  const double T = 0.8, w = 2 * kPi / T;
  const WssIndices r = over_one_period(T, 4000, [&](double t) {
    return std::vector<Vec3>{Vec3(0.3 + std::cos(w * t), 0.1 + std::sin(w * t), -0.2), Vec3(1, 2, 3)};
  });
  ASSERT_EQ(r.mean.size(), 2u);
  EXPECT_NEAR((r.mean[0] - Vec3(0.3, 0.1, -0.2)).norm(), 0.0, 1e-9);
  EXPECT_NEAR(r.mean[0].norm(), r.tawss[0] * (1.0 - 2.0 * r.osi[0]), 1e-12);
  EXPECT_NEAR((r.mean[1] - Vec3(1, 2, 3)).norm(), 0.0, 1e-12);
}

TEST(WssIndices, RefusesTooFewOrDisorderedSamples) {
  WssIndexAccumulator a;
  EXPECT_THROW(a.result(), InputError);
  a.add(0.1, {Vec3(1, 0, 0)});
  EXPECT_THROW(a.result(), InputError);
  EXPECT_THROW(a.add(0.1, {Vec3(1, 0, 0)}), InputError);            // not later
  EXPECT_THROW(a.add(0.2, {Vec3(1, 0, 0), Vec3(1, 0, 0)}), InputError);  // another point count
  a.add(0.2, {Vec3(1, 0, 0)});
  EXPECT_EQ(a.samples(), 2);
  EXPECT_NEAR(a.result().tawss[0], 1.0, 1e-12);
}


// A checkpoint's sums for a window that moved on (a run extended on restart): kept where they began in
// it, dropped where it starts after the checkpoint, begun again from the last sample where it starts at
// it (the same indices as sums begun there), none where it began in between.
TEST(WssIndices, ACheckpointsSumsFollowAWindowThatMovedOn) {
  WssIndexAccumulator a;
  for (int k = 0; k <= 4; ++k) a.add(0.1 * k, {Vec3(1.0 + k, 0, 0)});  // t = 0 to 0.4
  const WssIndexAccumulator::State saved = a.state();
  EXPECT_EQ(window_sums(saved, 0.0, 0.4, 0.1)->samples, 5);  // began in the window: kept
  EXPECT_EQ(window_sums(saved, 0.6, 0.4, 0.1)->samples, 0);  // the window after the checkpoint
  EXPECT_FALSE(window_sums(saved, 0.2, 0.4, 0.1).has_value());  // began before, the window's start inside
  const std::optional<WssIndexAccumulator::State> at = window_sums(saved, 0.4, 0.4, 0.1);
  ASSERT_TRUE(at.has_value());
  WssIndexAccumulator resumed, fresh;
  resumed.restore(*at);
  EXPECT_EQ(resumed.samples(), 1);
  fresh.add(0.4, {Vec3(5, 0, 0)});
  for (WssIndexAccumulator* x : {&resumed, &fresh}) x->add(0.5, {Vec3(-3, 0, 0)});
  EXPECT_DOUBLE_EQ(resumed.result().tawss[0], fresh.result().tawss[0]);
  EXPECT_DOUBLE_EQ(resumed.result().osi[0], fresh.result().osi[0]);
  EXPECT_DOUBLE_EQ(resumed.result().start, 0.4);
}

}  // namespace
}  // namespace vesselmesh::post
