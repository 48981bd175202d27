// Outlet RCR parameters from a target (issue 32): the total resistance of the outlets in parallel
// is the mean pressure over the mean inflow; Murray's law shares the flow among the outlets as
// their radius to the power n (n = 3: Murray's law; n = 2: by area), so that outlet j's
// resistance is the total over its share; each is split into proximal (a fraction, 0.09 by
// default as is common practice) and distal parts, and the total compliance is shared as the
// flow. The compliance, when not given, is the one whose time constant R_total C_total is
// `time_constant` (1 s by default, about a diastolic decay's).
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace vesselmesh::flow {

struct WindkesselTarget {
  double inflow = 0.0;                       // mean inflow, mL/s
  double systolic = 0.0, diastolic = 0.0;    // mmHg; mean pressure = diastolic + (systolic - diastolic) / 3
  double murray_exponent = 3.0;
  double proximal_fraction = 0.09;           // of each outlet's resistance
  std::optional<double> total_capacitance;   // m3/Pa
  double time_constant = 1.0;                // s, when the capacitance is not given
};

struct OutletWindkessel {
  std::string tag;
  double radius = 0.0;         // m
  double flow_fraction = 0.0;  // of the inflow
  double proximal_resistance = 0.0, distal_resistance = 0.0;  // Pa s / m3
  double capacitance = 0.0;                                   // m3 / Pa
};

// Mean pressure (Pa) of a target.
double mean_pressure(const WindkesselTarget& target);

// One entry per outlet (tag, radius in m), in their order. OptionError for a target out of range
// (a flow or pressure not positive, systolic below diastolic, an exponent outside [1, 4], a
// proximal fraction outside [0, 1)), InputError when there is no outlet or a radius is not
// positive.
std::vector<OutletWindkessel> murray_windkessel(const std::vector<std::pair<std::string, double>>& outlets,
                                                const WindkesselTarget& target);

}  // namespace vesselmesh::flow
