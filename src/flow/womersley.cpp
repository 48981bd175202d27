#include "flow/womersley.h"

#include "mesh/error.h"

#include <cmath>

namespace vesselmesh::flow {
namespace {

// sum_k (-1)^k (z/2)^(2k+order) / (k! (k+order)!), to the last bit that changes the sum.
Complex bessel_series(Complex z, int order) {
  const Complex q = -0.25 * z * z;
  Complex term = order == 0 ? Complex(1.0) : 0.5 * z;
  Complex sum = term;
  for (int k = 1; k < 200; ++k) {
    term *= q / (static_cast<double>(k) * (k + order));
    sum += term;
    if (std::abs(term) < 1e-17 * std::abs(sum)) break;
  }
  return sum;
}

}  // namespace

Complex bessel_j0(Complex z) { return bessel_series(z, 0); }
Complex bessel_j1(Complex z) { return bessel_series(z, 1); }

Womersley::Womersley(std::vector<Complex> harmonics, double omega, double radius, double nu)
    : q_(std::move(harmonics)), omega_(omega), radius_(radius), nu_(nu) {
  VM_CHECK(!q_.empty() && radius > 0.0 && nu > 0.0, "Womersley flow parameters");
  const Complex i32 = std::pow(Complex(0.0, 1.0), 1.5);
  lambda_.resize(q_.size());
  for (size_t n = 1; n < q_.size(); ++n) lambda_[n] = i32 * alpha() * std::sqrt(static_cast<double>(n));
}

Womersley Womersley::from_waveform(const Waveform& flow, int count, double radius, double nu) {
  const double period = flow.period();
  if (!(period > 0.0)) return Womersley({Complex(flow(0.0) * 1e-6)}, 0.0, radius, nu);
  // The trapezoidal rule on a fine uniform grid of the piecewise-linear waveform.
  const int samples = 4096;
  std::vector<Complex> q(count + 1, Complex(0.0));
  for (int k = 0; k < samples; ++k) {
    const double t = period * k / samples;
    const double value = flow(t) * 1e-6;
    for (int n = 0; n <= count; ++n)
      q[n] += value * std::exp(Complex(0.0, -2.0 * M_PI * n * k / samples)) * (n == 0 ? 1.0 : 2.0) /
              static_cast<double>(samples);
  }
  return Womersley(q, 2.0 * M_PI / period, radius, nu);
}

double Womersley::alpha() const { return radius_ * std::sqrt(omega_ / nu_); }

Complex Womersley::shape(int n, double rho) const {
  const double area = M_PI * radius_ * radius_;
  if (n == 0) return 2.0 * (1.0 - rho * rho) / area;
  const Complex L = lambda_[n], j0 = bessel_j0(L), j1 = bessel_j1(L);
  return (1.0 - bessel_j0(L * rho) / j0) / (1.0 - 2.0 * j1 / (L * j0)) / area;
}

double Womersley::flow(double t) const {
  double sum = 0.0;
  for (size_t n = 0; n < q_.size(); ++n) sum += (q_[n] * std::exp(Complex(0.0, n * omega_ * t))).real();
  return sum;
}

double Womersley::velocity(double rho, double t) const {
  double sum = 0.0;
  for (size_t n = 0; n < q_.size(); ++n)
    sum += (q_[n] * std::exp(Complex(0.0, n * omega_ * t)) * shape(static_cast<int>(n), rho)).real();
  return sum;
}

double Womersley::wall_shear_stress(double t, double viscosity) const {
  const double r3 = M_PI * radius_ * radius_ * radius_;
  double sum = 0.0;
  for (size_t n = 0; n < q_.size(); ++n) {
    Complex tau;
    if (n == 0) {
      tau = 4.0 * viscosity / r3;
    } else {
      const Complex L = lambda_[n], j0 = bessel_j0(L), j1 = bessel_j1(L);
      tau = -(viscosity / r3) * L * L * j1 / (L * j0 - 2.0 * j1);
    }
    sum += (q_[n] * std::exp(Complex(0.0, n * omega_ * t)) * tau).real();
  }
  return sum;
}

}  // namespace vesselmesh::flow
