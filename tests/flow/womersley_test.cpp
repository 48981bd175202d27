#include "flow/womersley.h"

#include <gtest/gtest.h>

#include <cmath>

namespace vesselmesh::flow {
namespace {

// The power series loses digits to cancellation as |z| grows (terms up to e^|z| / sqrt|z|):
// 1e-14 at |z| = 2, a few 1e-12 at 15.
TEST(Bessel, RealArgumentsMatchTheStandardLibrary) {
  for (double x : {0.0, 0.5, 2.0, 7.3, 15.0}) {
    const double tolerance = x < 5.0 ? 1e-13 : 1e-10;
    EXPECT_NEAR(bessel_j0(x).real(), std::cyl_bessel_j(0.0, x), tolerance) << x;
    EXPECT_NEAR(bessel_j1(x).real(), std::cyl_bessel_j(1.0, x), tolerance) << x;
    EXPECT_NEAR(bessel_j0(x).imag(), 0.0, 1e-15);
  }
}

// Kelvin's functions: J0(x i^{3/2}) = ber(x) + i bei(x) (Abramowitz & Stegun, table 9.12).
TEST(Bessel, KelvinFunctions) {
  const Complex i32 = std::pow(Complex(0.0, 1.0), 1.5);
  const Complex j = bessel_j0(i32 * 1.0);
  EXPECT_NEAR(j.real(), 0.9843817812, 1e-9);
  EXPECT_NEAR(j.imag(), 0.2495660400, 1e-9);
  const Complex k = bessel_j0(i32 * 5.0);
  EXPECT_NEAR(k.real(), -6.2300824830, 1e-8);
  EXPECT_NEAR(k.imag(), 0.1160343854, 1e-8);
}

// Each harmonic's profile carries its flow: the disc integral of s_n / (pi R^2) is 1; the wall
// shear stress is -mu du/dr at the wall.
TEST(Womersley, ProfilesCarryUnitFlowAndGiveTheWallShear) {
  const double R = 2e-3, nu = 3.3e-6, omega = 16.0 * nu / (R * R);  // alpha = 4
  const Womersley w({Complex(1e-6), Complex(0.5e-6, 0.2e-6), Complex(0.0, 0.3e-6)}, omega, R, nu);
  EXPECT_NEAR(w.alpha(), 4.0, 1e-12);
  for (int n = 0; n < 3; ++n) {
    Complex flux(0.0);
    const int steps = 4000;
    for (int k = 0; k < steps; ++k) {
      const double rho = (k + 0.5) / steps;
      flux += w.shape(n, rho) * 2.0 * M_PI * rho * R * R / static_cast<double>(steps);
    }
    EXPECT_NEAR(std::abs(flux - 1.0), 0.0, 1e-6) << "harmonic " << n;
  }
  const double mu = nu * 1060.0;
  for (double t : {0.0, 0.1, 0.33}) {
    const double h = 1e-6;
    const double dudr = (w.velocity(1.0, t) - w.velocity(1.0 - h, t)) / (h * R);
    EXPECT_NEAR(w.wall_shear_stress(t, mu), -mu * dudr, 1e-5 * std::abs(mu * dudr) + 1e-9) << t;
    EXPECT_NEAR(w.velocity(1.0, t), 0.0, 1e-12);
  }
  EXPECT_NEAR(w.flow(0.0), 1e-6 + 0.5e-6, 1e-18);
}

TEST(Womersley, FromAWaveformsSeries) {
  const double period = 0.5;
  std::vector<double> t, q;
  for (int k = 0; k <= 200; ++k) {
    t.push_back(period * k / 200);
    q.push_back(2.0 + std::cos(2.0 * M_PI * t.back() / period));  // mL/s
  }
  const Womersley w = Womersley::from_waveform(Waveform(t, q), 4, 2e-3, 3.3e-6);
  EXPECT_NEAR(w.coefficients()[0].real(), 2e-6, 1e-12);
  EXPECT_NEAR(std::abs(w.coefficients()[1]), 1e-6, 1e-9);
  EXPECT_NEAR(std::abs(w.coefficients()[2]), 0.0, 1e-9);
  EXPECT_NEAR(w.flow(0.1), 1e-6 * (2.0 + std::cos(2.0 * M_PI * 0.1 / period)), 1e-9);
}

}  // namespace
}  // namespace vesselmesh::flow
