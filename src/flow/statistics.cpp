#include "flow/statistics.h"

#include "mesh/error.h"

#include <fmt/format.h>

#include <cmath>
#include <unordered_map>

namespace vesselmesh::flow {

void FlowStatistics::add(double time, double dt, const std::vector<Vec3>& velocity,
                         const std::vector<double>& pressure) {
  VM_CHECK(dt > 0.0 && velocity.size() == pressure.size(), "a statistics step: its length or its fields");
  if (s_.steps == 0) {
    s_.start = time - dt;
    s_.mean_velocity.assign(velocity.size(), Vec3::Zero());
    s_.squares.assign(velocity.size(), Vec3::Zero());
    s_.mean_pressure.assign(velocity.size(), 0.0);
  }
  VM_CHECK(velocity.size() == s_.mean_velocity.size(), "statistics of another set of points");
  s_.weight += dt;
  const double share = dt / s_.weight;
  for (size_t a = 0; a < velocity.size(); ++a) {
    const Vec3 before = velocity[a] - s_.mean_velocity[a];
    s_.mean_velocity[a] += share * before;
    s_.squares[a] += dt * before.cwiseProduct(velocity[a] - s_.mean_velocity[a]);
    s_.mean_pressure[a] += share * (pressure[a] - s_.mean_pressure[a]);
  }
  s_.end = time;
  s_.steps += 1;
}

std::vector<Vec3> FlowStatistics::rms_velocity() const {
  std::vector<Vec3> rms(s_.squares.size(), Vec3::Zero());
  if (s_.weight <= 0.0) return rms;
  for (size_t a = 0; a < rms.size(); ++a) rms[a] = (s_.squares[a] / s_.weight).cwiseMax(0.0).cwiseSqrt();
  return rms;
}

std::vector<Field> FlowStatistics::fields() const {
  return {Field::vector("mean_velocity", s_.mean_velocity), Field::vector("rms_velocity", rms_velocity()),
          Field::scalar("mean_pressure", s_.mean_pressure)};
}

FlowStatistics::State statistics_at(const FlowStatistics::State& by_point, const std::vector<int>& local,
                                    const std::string& path) {
  FlowStatistics::State out = by_point;
  out.points = local;
  std::unordered_map<int, size_t> at;
  for (size_t k = 0; k < by_point.points.size(); ++k) at.emplace(by_point.points[k], k);
  out.mean_velocity.assign(local.size(), Vec3::Zero());
  out.squares.assign(local.size(), Vec3::Zero());
  out.mean_pressure.assign(local.size(), 0.0);
  for (size_t k = 0; k < local.size(); ++k) {
    const auto found = at.find(local[k]);
    if (found == at.end())
      throw InputError(fmt::format("{}: its time statistics have no value at mesh point {}: run the case without "
                                   "--restart", path, local[k]));
    out.mean_velocity[k] = by_point.mean_velocity[found->second];
    out.squares[k] = by_point.squares[found->second];
    out.mean_pressure[k] = by_point.mean_pressure[found->second];
  }
  return out;
}

}  // namespace vesselmesh::flow
