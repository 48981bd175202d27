#include "flow/inflow_perturbation.h"

#include "mesh/error.h"

#include <cmath>
#include <cstdint>
#include <random>

namespace vesselmesh::flow {

InflowPerturbation::InflowPerturbation(double intensity, double length, double speed)
    : amplitude_(intensity * std::sqrt(2.0 / kModes)) {
  VM_CHECK(intensity > 0.0 && length > 0.0 && speed > 0.0,
           "InflowPerturbation: a positive intensity, length and speed");
  std::mt19937_64 engine(
      20261129);  // the sequence is the standard's: the same modes on any library
  const auto uniform = [&engine] {
    return static_cast<double>(engine() >> 11) * 0x1.0p-53;
  };  // [0, 1)
  for (std::vector<Mode>& component : modes_)
    for (int m = 0; m < kModes; ++m) {
      const double cos_theta = 2.0 * uniform() - 1.0, phi = 2.0 * M_PI * uniform();
      const double sin_theta = std::sqrt(1.0 - cos_theta * cos_theta);
      const double k = (1.0 + 3.0 * uniform()) / length;
      Mode mode;
      mode.k = k * Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta);
      mode.omega = k * speed * (0.5 + uniform());
      mode.phase = 2.0 * M_PI * uniform();
      component.push_back(mode);
    }
}

Vec3 InflowPerturbation::operator()(const Vec3& x, double t) const {
  Vec3 out = Vec3::Zero();
  for (int i = 0; i < 3; ++i)
    for (const Mode& m : modes_[i]) out[i] += std::cos(m.k.dot(x) + m.omega * t + m.phase);
  return amplitude_ * out;
}

}  // namespace vesselmesh::flow
