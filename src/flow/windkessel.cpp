#include "flow/windkessel.h"

#include "mesh/error.h"

#include <fmt/format.h>

#include <cmath>

namespace vesselmesh::flow {

namespace {
constexpr double kPascalPerMmHg = 133.322;
}

double mean_pressure(const WindkesselTarget& t) {
  return (t.diastolic + (t.systolic - t.diastolic) / 3.0) * kPascalPerMmHg;
}

std::vector<OutletWindkessel> murray_windkessel(const std::vector<std::pair<std::string, double>>& outlets,
                                                const WindkesselTarget& t) {
  if (!(t.inflow > 0.0)) throw OptionError(fmt::format("the mean inflow must be positive (found {} mL/s)", t.inflow));
  if (!(t.diastolic > 0.0) || !(t.systolic >= t.diastolic))
    throw OptionError(fmt::format("the pressure {}/{} mmHg: give systolic/diastolic, both positive, systolic first",
                                  t.systolic, t.diastolic));
  if (!(t.murray_exponent >= 1.0 && t.murray_exponent <= 4.0))
    throw OptionError(fmt::format("the Murray exponent {} is outside [1, 4] (3: Murray's law, 2: by area)",
                                  t.murray_exponent));
  if (!(t.proximal_fraction >= 0.0 && t.proximal_fraction < 1.0))
    throw OptionError(fmt::format("the proximal fraction {} is outside [0, 1)", t.proximal_fraction));
  if (t.total_capacitance && !(*t.total_capacitance > 0.0))
    throw OptionError(fmt::format("the total capacitance must be positive (found {} m3/Pa)", *t.total_capacitance));
  if (!(t.time_constant > 0.0)) throw OptionError("the time constant must be positive");
  if (outlets.empty()) throw InputError("no outlet to give a Windkessel to (the surface has one open end at most)");
  double weight = 0.0;
  for (const auto& [tag, radius] : outlets) {
    if (!(radius > 0.0)) throw InputError(fmt::format("outlet {} has radius {}: not an open end", tag, radius));
    weight += std::pow(radius, t.murray_exponent);
  }
  const double total_resistance = mean_pressure(t) / (t.inflow * 1e-6);
  const double total_capacitance = t.total_capacitance.value_or(t.time_constant / total_resistance);
  std::vector<OutletWindkessel> out;
  for (const auto& [tag, radius] : outlets) {
    OutletWindkessel w;
    w.tag = tag;
    w.radius = radius;
    w.flow_fraction = std::pow(radius, t.murray_exponent) / weight;
    const double resistance = total_resistance / w.flow_fraction;
    w.proximal_resistance = t.proximal_fraction * resistance;
    w.distal_resistance = resistance - w.proximal_resistance;
    w.capacitance = total_capacitance * w.flow_fraction;
    out.push_back(w);
  }
  return out;
}

}  // namespace vesselmesh::flow
