// Womersley's pulsatile flow in a straight rigid pipe: the inflow profile of a `womersley`
// velocity boundary and the analytic solution the solver is tested against.
//
// A periodic flow rate Q(t) = Re sum_n Q_n e^{i n w t} (the waveform's Fourier series) has the
// velocity u(r, t) = Re sum_n Q_n e^{i n w t} s_n(r / R) / (pi R^2), with s_0 = 2 (1 - rho^2) and
// s_n = (1 - J0(L rho) / J0(L)) / (1 - 2 J1(L) / (L J0(L))), L = i^{3/2} alpha sqrt(n),
// alpha = R sqrt(w / nu) (Womersley 1955). Each s_n has unit mean over the disc. The wall shear
// stress along the flow is Re sum_n Q_n e^{i n w t} tau_n, tau_0 = 4 mu / (pi R^3),
// tau_n = -(mu / (pi R^3)) L^2 J1(L) / (L J0(L) - 2 J1(L)).
#pragma once

#include "flow/case.h"

#include <complex>
#include <vector>

namespace vesselmesh::flow {

using Complex = std::complex<double>;

// Bessel functions of the first kind of a complex argument (power series; |z| <= 40).
Complex bessel_j0(Complex z);
Complex bessel_j1(Complex z);

class Womersley {
 public:
  // `harmonics`: the Fourier coefficients Q_0, Q_1, ... (m3/s) of a flow of angular frequency
  // `omega` (rad/s) in a pipe of `radius` (m), kinematic viscosity `nu` (m2/s).
  Womersley(std::vector<Complex> harmonics, double omega, double radius, double nu);
  // The Fourier series of a periodic waveform (mL/s, sampled over its period) up to `count`
  // harmonics, in m3/s; a constant waveform gives Poiseuille's flow.
  static Womersley from_waveform(const Waveform& flow, int count, double radius, double nu);

  double alpha() const;
  int harmonics() const { return static_cast<int>(q_.size()); }
  const std::vector<Complex>& coefficients() const { return q_; }
  double omega() const { return omega_; }
  // s_n(rho) / (pi R^2): the axial velocity per unit flow of harmonic n at rho = r / R.
  Complex shape(int n, double rho) const;
  double flow(double t) const;                  // m3/s
  double velocity(double rho, double t) const;  // m/s along the pipe
  double wall_shear_stress(double t, double viscosity) const;  // Pa, along the flow

 private:
  std::vector<Complex> q_;
  std::vector<Complex> lambda_;
  double omega_, radius_, nu_;
};

}  // namespace vesselmesh::flow
