#include "post/indices.h"

#include "io/vtk_formats.h"
#include "mesh/error.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace vesselmesh::post {

void WssIndexAccumulator::add(double time, const std::vector<Vec3>& tau) {
  if (samples_ == 0) {
    start_ = time;
    integral_.assign(tau.size(), Vec3::Zero());
    magnitude_integral_.assign(tau.size(), 0.0);
    change_.assign(tau.size(), 0.0);
  } else {
    if (tau.size() != last_.size())
      throw InputError(fmt::format("wall shear stress at t = {:g} s has {} points, the earlier samples {}", time,
                                   tau.size(), last_.size()));
    if (!(time > last_time_))
      throw InputError(fmt::format("wall shear stress samples out of order: t = {:g} s after t = {:g} s", time,
                                   last_time_));
    const double dt = time - last_time_;
    for (size_t i = 0; i < tau.size(); ++i) {
      integral_[i] += 0.5 * dt * (tau[i] + last_[i]);
      magnitude_integral_[i] += 0.5 * dt * (tau[i].norm() + last_[i].norm());
      change_[i] += (tau[i] - last_[i]).norm();
    }
  }
  last_ = tau;
  last_time_ = time;
  samples_ += 1;
}

WssIndices WssIndexAccumulator::result() const {
  if (samples_ < 2)
    throw InputError(fmt::format("hemodynamic indices need at least two wall shear stress samples in time, got {}",
                                 samples_));
  WssIndices r;
  r.start = start_;
  r.end = last_time_;
  r.samples = samples_;
  const double span = last_time_ - start_;
  const size_t n = integral_.size();
  r.tawss.resize(n);
  r.osi.resize(n);
  r.rrt.resize(n);
  r.twssg.resize(n);
  r.mean.resize(n);
  for (size_t i = 0; i < n; ++i) {
    r.mean[i] = integral_[i] / span;
    const double mean_vector = integral_[i].norm();
    r.tawss[i] = magnitude_integral_[i] / span;
    r.osi[i] = magnitude_integral_[i] > 0.0
                   ? std::clamp(0.5 * (1.0 - mean_vector / magnitude_integral_[i]), 0.0, 0.5)
                   : 0.0;
    // A mean vector within rounding of zero (against the magnitude's integral) has no residence time.
    r.rrt[i] = mean_vector > 1e-12 * magnitude_integral_[i] && mean_vector > 0.0
                   ? span / mean_vector
                   : std::numeric_limits<double>::quiet_NaN();
    r.twssg[i] = change_[i] / span;
  }
  return r;
}

void write_indices(const std::string& path, const TriMesh& wall, const WssIndices& indices) {
  io::write_vtp(path, wall,
                {Field::scalar("tawss", indices.tawss), Field::scalar("osi", indices.osi),
                 Field::scalar("rrt", indices.rrt), Field::scalar("twssg", indices.twssg),
                 Field::vector("mean_wss", indices.mean)});
}

std::optional<WssIndexAccumulator::State> window_sums(const WssIndexAccumulator::State& saved, double window_start,
                                                      double time, double step) {
  const double half = 0.5 * step;
  if (saved.samples == 0 || saved.start >= window_start - half) return saved;
  if (time < window_start - half) return WssIndexAccumulator::State{};
  if (time > window_start + half) return std::nullopt;
  const size_t n = saved.last.size();
  return WssIndexAccumulator::State{1, saved.last_time, saved.last_time, saved.last, std::vector<Vec3>(n, Vec3::Zero()),
                                    std::vector<double>(n, 0.0), std::vector<double>(n, 0.0)};
}

}  // namespace vesselmesh::post
