#include "study/gci.h"

#include "mesh/error.h"

#include <gtest/gtest.h>

#include <cmath>

namespace vesselmesh::study {
namespace {

// Celik et al. (2008), Table 1, its first column (a planar grid: h = N^(-1/2)): N = 18000, 8000,
// 4500 cells, phi = 6.063, 5.972, 5.863 give r21 = 1.5, r32 = 1.333, p = 1.53, phi_ext = 6.1685,
// e_a = 1.5 %, e_ext = 1.7 %, GCI_fine = 2.2 %.
TEST(GridConvergence, CeliksWorkedExample) {
  const GridConvergence g = grid_convergence(18000, 8000, 4500, 6.063, 5.972, 5.863, 2);
  ASSERT_TRUE(g.found) << g.status;
  EXPECT_EQ(g.status, "monotone");
  EXPECT_NEAR(g.r21, 1.5, 1e-12);
  EXPECT_NEAR(g.r32, 4.0 / 3.0, 1e-12);
  EXPECT_NEAR(g.order, 1.53, 0.005);
  EXPECT_NEAR(g.extrapolated, 6.1685, 0.001);
  EXPECT_NEAR(100 * g.approximate_error, 1.5, 0.05);
  EXPECT_NEAR(100 * g.extrapolated_error, 1.7, 0.05);
  EXPECT_NEAR(100 * g.gci_fine, 2.2, 0.05);
  EXPECT_NEAR(g.band(), 6.063 * g.gci_fine, 1e-12);
}

// A quantity that is exactly phi0 + C h^2 on volume grids of unequal ratios: order 2, the
// extrapolation phi0 to round-off, the asymptotic ratio 1; and from above (C < 0) the same.
TEST(GridConvergence, ExactSecondOrderIsRecovered) {
  const double n[3] = {200000, 60000, 25000};
  for (double c : {3.0, -3.0}) {
    double phi[3];
    for (int k = 0; k < 3; ++k) phi[k] = 0.42 + c * std::pow(n[k], -2.0 / 3.0);
    const GridConvergence g = grid_convergence(n[0], n[1], n[2], phi[0], phi[1], phi[2]);
    ASSERT_TRUE(g.found) << g.status;
    EXPECT_NEAR(g.order, 2.0, 1e-8);
    EXPECT_NEAR(g.extrapolated, 0.42, 1e-12);
    EXPECT_NEAR(g.asymptotic_ratio, phi[0] / phi[1], 1e-9);  // 1 but for the relative errors' phi1 / phi2
    EXPECT_NEAR(g.extrapolated_error, std::abs(phi[0] - 0.42) / 0.42, 1e-9);
    EXPECT_GT(g.gci_fine, g.extrapolated_error);  // the factor of safety 1.25
  }
}

// Oscillating differences (signs alternate) give an order with s = -1, said; differences that
// grow with refinement and a finest pair that agrees give none; counts out of order are errors.
TEST(GridConvergence, OscillationDivergenceAndAgreementAreSaid) {
  const GridConvergence osc = grid_convergence(8000, 1000, 125, 1.01, 0.98, 1.10);
  EXPECT_TRUE(osc.oscillatory);
  EXPECT_EQ(osc.status, "oscillatory");
  EXPECT_TRUE(osc.found);
  EXPECT_NEAR(osc.order, std::log(0.12 / 0.03) / std::log(2.0), 1e-9);  // equal ratios: q = 0
  const GridConvergence diverging = grid_convergence(8000, 1000, 125, 1.3, 1.1, 1.0);
  EXPECT_FALSE(diverging.found);
  EXPECT_EQ(diverging.status, "no convergence");
  EXPECT_TRUE(std::isnan(diverging.gci_fine));
  EXPECT_NEAR(diverging.approximate_error, 0.2 / 1.3, 1e-12);  // still reported
  EXPECT_NEAR(diverging.spread, 0.3 / 1.3, 1e-12);              // the least the uncertainty can be
  const GridConvergence agree = grid_convergence(8000, 1000, 125, 1.0, 1.0, 1.2);
  EXPECT_FALSE(agree.found);
  EXPECT_EQ(agree.status, "the two finest agree");
  // An order under 0.5 (differences nearly equal) is not claimed; one above 2 is capped at 2.
  const GridConvergence slow = grid_convergence(8000, 1000, 125, 1.0, 1.1, 1.2 + 1e-3);
  EXPECT_FALSE(slow.found);
  EXPECT_NE(slow.status.find("no convergence (order"), std::string::npos) << slow.status;
  const GridConvergence fast = grid_convergence(8000, 1000, 125, 1.0, 1.001, 1.101);  // p = log2(100)
  ASSERT_TRUE(fast.found);
  EXPECT_NEAR(fast.order, std::log2(100.0), 1e-9);
  EXPECT_NEAR(fast.gci_fine, 1.25 * 0.001 / (4.0 - 1.0), 1e-12);  // with p = 2
  EXPECT_NEAR(fast.extrapolated, (4.0 * 1.0 - 1.001) / 3.0, 1e-12);
  EXPECT_THROW(grid_convergence(1000, 8000, 125, 1, 1, 1), InputError);
  EXPECT_THROW(grid_convergence(1000, 1000, 125, 1, 1, 1), InputError);
}

}  // namespace
}  // namespace vesselmesh::study
