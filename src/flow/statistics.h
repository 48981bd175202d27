// The flow's time statistics (issue 47: a transitional jet is compared with the laboratories' by its
// mean and its fluctuations, not by one instant): per point, the time mean of the velocity (m/s) and
// of the pressure (Pa), and the RMS of the velocity's fluctuation about its mean, per component
// (m/s), over the time steps from a start time to the run's end ([output] statistics_from).
// Each step's flow stands for its step's length (the steps a CFL target chooses are unequal): the
// means and RMS are those of the flow held piecewise constant over the steps, each step's at its end.
// Running sums by West's weighted update of the mean and of the sum of squared deviations (D. H. D.
// West, Commun. ACM 22(9), 1979): no cancellation where the fluctuations are small beside the mean,
// as a laminar flow's are.
#pragma once

#include "mesh/trimesh.h"

#include <string>
#include <vector>

namespace vesselmesh::flow {

class FlowStatistics {
 public:
  struct State {
    double start = -1.0;   // s: the start of the first step counted; < 0: none yet
    double end = 0.0;      // s: the end of the last
    double weight = 0.0;   // s: the steps' lengths summed
    int steps = 0;
    std::vector<Vec3> mean_velocity;
    std::vector<Vec3> squares;  // per component, the sum over the steps of dt (u - mean)^2 (West's M2)
    std::vector<double> mean_pressure;
    // The mesh points the fields are of (a checkpoint's: by mesh number, whatever process held them).
    std::vector<int> points;
  };

  FlowStatistics() = default;
  explicit FlowStatistics(State state) : s_(std::move(state)) {}

  // One step of length dt (s) that ends at `time` (s), its flow per point (the same points at every
  // step).
  void add(double time, double dt, const std::vector<Vec3>& velocity, const std::vector<double>& pressure);

  int steps() const { return s_.steps; }
  const State& state() const { return s_; }
  const std::vector<Vec3>& mean_velocity() const { return s_.mean_velocity; }
  const std::vector<double>& mean_pressure() const { return s_.mean_pressure; }
  std::vector<Vec3> rms_velocity() const;
  // The point data of a result file: mean_velocity, rms_velocity (m/s), mean_pressure (Pa).
  std::vector<Field> fields() const;

 private:
  State s_;
};

// A checkpoint's statistics (their fields by mesh point, State::points) at the mesh points `local`,
// in that order (FlowStatistics's at a process's local points); InputError naming `path` where one
// is missing.
FlowStatistics::State statistics_at(const FlowStatistics::State& by_point, const std::vector<int>& local,
                                    const std::string& path);

}  // namespace vesselmesh::flow
