// A synthetic disturbance of an inflow (issue 47). The laboratories' inlets are not quiet (the FDA
// nozzle's LDV measured axial and radial fluctuations of 3.8 % and 2.6 % of the centreline velocity
// in its inlet pipe at Re_throat = 2000), and a jet that nothing disturbs breaks down late, or not
// at all, in a solver whose own noise then decides where. The disturbance is a sum of random
// Fourier modes in space and time (Kraichnan's random flow generation, J. Chem. Phys. 1970, without
// the divergence constraint: it lives on the inlet's face) of a fixed seed: a function of the
// position and the time only, so the same on any number of processes, after a restart, and run
// after run.
#pragma once

#include "mesh/trimesh.h"

#include <array>
#include <vector>

namespace vesselmesh::flow {

class InflowPerturbation {
 public:
  static constexpr int kModes = 64;  // per component

  // intensity: each component's RMS over time, a fraction of the local speed (> 0); length (m): the
  // largest eddies' (the end's radius: wavenumbers from 1 to 4 over it); speed (m/s): the end's
  // mean inflow speed, which sets the frequencies (an eddy of wavenumber k passes at about that
  // speed: omega = k x speed x a factor from 0.5 to 1.5).
  InflowPerturbation(double intensity, double length, double speed);

  // The disturbance at x (m, from the end's centre) at time t (s), per unit of local speed: each
  // component's RMS over time is the intensity, its mean zero.
  Vec3 operator()(const Vec3& x, double t) const;

 private:
  struct Mode {
    Vec3 k;        // 1/m
    double omega;  // 1/s
    double phase;
  };
  std::array<std::vector<Mode>, 3> modes_;
  double amplitude_ = 0.0;  // per mode: intensity x sqrt(2 / kModes)
};

}  // namespace vesselmesh::flow
