#include "flow/windkessel.h"

#include "mesh/error.h"

#include <gtest/gtest.h>

#include <cmath>

namespace vesselmesh::flow {
namespace {

// A target of a mean inflow (mL/s) and its pressures (mmHg), the rest as the defaults.
WindkesselTarget target_of(double inflow, double systolic, double diastolic) {
  WindkesselTarget t;
  t.inflow = inflow, t.systolic = systolic, t.diastolic = diastolic;
  return t;
}

// Two outlets of radii 2 and 1 mm at 120/80 mmHg and 10 mL/s: flows 8 : 1 (Murray), the outlets in
// parallel the mean pressure over the inflow, 9 % proximal, the compliance shared as the flow and
// its time constant 1 s; n = 2 shares by area.
TEST(Windkessel, MurraysLawSharesTheFlowAndTheParallelResistanceIsTheTarget) {
  const WindkesselTarget target = target_of(10.0, 120.0, 80.0);
  EXPECT_NEAR(mean_pressure(target), (80.0 + 40.0 / 3.0) * 133.322, 1e-9);
  const auto w = murray_windkessel({{"outlet_1", 2e-3}, {"outlet_2", 1e-3}}, target);
  ASSERT_EQ(w.size(), 2u);
  EXPECT_EQ(w[1].tag, "outlet_2");
  EXPECT_NEAR(w[0].flow_fraction, 8.0 / 9.0, 1e-12);
  EXPECT_NEAR(w[1].flow_fraction, 1.0 / 9.0, 1e-12);
  double conductance = 0.0, capacitance = 0.0;
  for (const OutletWindkessel& o : w) {
    const double r = o.proximal_resistance + o.distal_resistance;
    EXPECT_NEAR(o.proximal_resistance, 0.09 * r, 1e-9 * r);
    conductance += 1.0 / r;
    capacitance += o.capacitance;
    // The outlet's flow at the mean pressure is its share of the inflow.
    EXPECT_NEAR(mean_pressure(target) / r, o.flow_fraction * 10e-6, 1e-12 * 10e-6);
  }
  const double total = mean_pressure(target) / 10e-6;
  EXPECT_NEAR(1.0 / conductance, total, 1e-9 * total);
  EXPECT_NEAR(capacitance * total, 1.0, 1e-12);

  WindkesselTarget by_area = target;
  by_area.murray_exponent = 2.0;
  by_area.total_capacitance = 1e-8;
  const auto a = murray_windkessel({{"outlet_1", 2e-3}, {"outlet_2", 1e-3}}, by_area);
  EXPECT_NEAR(a[0].flow_fraction, 0.8, 1e-12);
  EXPECT_NEAR(a[0].capacitance + a[1].capacitance, 1e-8, 1e-20);
}

TEST(Windkessel, ATargetOutOfRangeIsRefused) {
  const std::vector<std::pair<std::string, double>> one = {{"outlet_1", 1e-3}};
  const WindkesselTarget good = target_of(5.0, 120.0, 80.0);
  EXPECT_NO_THROW(murray_windkessel(one, good));
  WindkesselTarget t = good;
  t.inflow = 0.0;
  EXPECT_THROW(murray_windkessel(one, t), OptionError);
  t = good;
  t.systolic = 70.0;
  EXPECT_THROW(murray_windkessel(one, t), OptionError);
  t = good;
  t.murray_exponent = 7.0;
  EXPECT_THROW(murray_windkessel(one, t), OptionError);
  t = good;
  t.proximal_fraction = 1.0;
  EXPECT_THROW(murray_windkessel(one, t), OptionError);
  EXPECT_THROW(murray_windkessel({}, good), InputError);
  EXPECT_THROW(murray_windkessel({{"outlet_1", 0.0}}, good), InputError);
}

}  // namespace
}  // namespace vesselmesh::flow
