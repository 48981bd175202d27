// Hemodynamic indices of a wall shear stress history, as VaMPy's documentation defines them,
// over the window [t0, t1] the samples span (T = t1 - t0), per wall point:
//   TAWSS = 1/T int |tau| dt                            (Pa)
//   OSI   = 1/2 (1 - |int tau dt| / int |tau| dt)       (-, 0 to 1/2)
//   RRT   = 1 / ((1 - 2 OSI) TAWSS) = T / |int tau dt|  (1/Pa)
//   TWSSG = 1/T int |d tau / dt| dt                     (Pa/s)
// and the time-mean vector 1/T int tau dt (Pa; `mean_wss`, what a measured mean flow's shear is).
// The integrals are by the trapezoidal rule over the samples given (every time step when the
// solver accumulates, the saved frames when `vesselmesh wss` does); d tau/dt is the difference
// of successive samples. Where tau is zero throughout, OSI is 0 and RRT is NaN (no residence
// time can be told).
#pragma once

#include "mesh/trimesh.h"

#include <optional>
#include <string>
#include <vector>

namespace vesselmesh::post {

struct WssIndices {
  double start = 0.0, end = 0.0;  // s
  int samples = 0;
  std::vector<double> tawss, osi, rrt, twssg;
  std::vector<Vec3> mean;  // the time-mean wall shear stress 1/T int tau dt (Pa): the written `mean_wss`
};

class WssIndexAccumulator {
 public:
  // Samples come in increasing time; each has one vector per wall point (the same count).
  void add(double time, const std::vector<Vec3>& tau);
  int samples() const { return samples_; }
  // Throws InputError with fewer than two samples (no time span).
  WssIndices result() const;

  // The running sums, to save and resume (a checkpoint).
  struct State {
    int samples = 0;
    double start = 0.0, last_time = 0.0;
    std::vector<Vec3> last, integral;
    std::vector<double> magnitude_integral, change;
  };
  State state() const { return {samples_, start_, last_time_, last_, integral_, magnitude_integral_, change_}; }
  void restore(const State& s) {
    samples_ = s.samples;
    start_ = s.start;
    last_time_ = s.last_time;
    last_ = s.last;
    integral_ = s.integral;
    magnitude_integral_ = s.magnitude_integral;
    change_ = s.change;
  }

 private:
  int samples_ = 0;
  double start_ = 0.0, last_time_ = 0.0;
  std::vector<Vec3> last_, integral_;
  std::vector<double> magnitude_integral_, change_;
};

// A checkpoint's sums `saved` (at `time`, its step `step` long) for a window that starts at
// `window_start` (a run extended on restart: its last period moved on): kept where they began in
// it; none where it starts after `time` (its samples yet to come); begun again from their last
// sample where it starts there. Where it began between their start and `time` the samples from
// then on are inside the sums, which cannot be cut: nullopt.
std::optional<WssIndexAccumulator::State> window_sums(const WssIndexAccumulator::State& saved, double window_start,
                                                      double time, double step);

// The indices as VTK PolyData on the wall, point data tawss (Pa), osi, rrt (1/Pa), twssg (Pa/s),
// written atomically.
void write_indices(const std::string& path, const TriMesh& wall, const WssIndices& indices);

}  // namespace vesselmesh::post
