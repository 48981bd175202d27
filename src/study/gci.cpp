#include "study/gci.h"

#include "mesh/error.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace vesselmesh::study {

double GridConvergence::band() const { return std::abs(phi1) * gci_fine; }

namespace {
constexpr double kLeastOrder = 0.5, kMostOrder = 2.0;
}

GridConvergence grid_convergence(double n1, double n2, double n3, double phi1, double phi2, double phi3,
                                 int dimension) {
  if (!(n1 > n2 && n2 > n3 && n3 > 0.0))
    throw InputError(fmt::format("grid convergence: the grids' point counts must fall from the finest ({}, {}, {})",
                                 n1, n2, n3));
  VM_CHECK(dimension == 2 || dimension == 3, "grid_convergence: dimension 2 or 3");
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  GridConvergence g;
  g.phi1 = phi1;
  g.phi2 = phi2;
  g.phi3 = phi3;
  g.r21 = std::pow(n1 / n2, 1.0 / dimension);
  g.r32 = std::pow(n2 / n3, 1.0 / dimension);
  g.order = g.extrapolated = g.extrapolated_error = g.gci_fine = g.asymptotic_ratio = nan;
  const double e21 = phi2 - phi1, e32 = phi3 - phi2;
  g.approximate_error = phi1 != 0.0 ? std::abs(e21 / phi1) : nan;
  g.spread = phi1 != 0.0 ? std::max(std::abs(e21), std::abs(phi3 - phi1)) / std::abs(phi1) : nan;
  const double scale = std::max({std::abs(phi1), std::abs(phi2), std::abs(phi3)});
  if (std::abs(e21) <= 1e-12 * scale) {
    g.status = "the two finest agree";
    return g;
  }
  if (std::abs(e21) >= std::abs(e32)) {  // the differences do not shrink with refinement
    g.status = "no convergence";
    return g;
  }
  g.oscillatory = e21 * e32 < 0.0;
  const double s = g.oscillatory ? -1.0 : 1.0;
  const double ln_ratio = std::log(std::abs(e32 / e21)), ln_r21 = std::log(g.r21);
  double p = std::abs(ln_ratio) / ln_r21;
  bool settled = false;
  for (int it = 0; it < 500 && std::isfinite(p); ++it) {
    const double a = std::pow(g.r21, p) - s, b = std::pow(g.r32, p) - s;
    if (!(a > 0.0 && b > 0.0)) break;
    const double next = std::abs(ln_ratio + std::log(a / b)) / ln_r21;
    if (std::abs(next - p) <= 1e-12 * std::max(1.0, p)) {
      p = next;
      settled = true;
      break;
    }
    p = next;
  }
  if (!settled || !(p >= kLeastOrder)) {
    g.status = settled && p > 0.0 ? fmt::format("no convergence (order {:.2g})", p) : "no convergence";
    return g;
  }
  g.found = true;
  g.status = g.oscillatory ? "oscillatory" : "monotone";
  g.order = p;
  p = std::min(p, kMostOrder);
  const double r21p = std::pow(g.r21, p), r32p = std::pow(g.r32, p);
  g.extrapolated = (r21p * phi1 - phi2) / (r21p - 1.0);
  g.extrapolated_error = g.extrapolated != 0.0 ? std::abs((g.extrapolated - phi1) / g.extrapolated) : nan;
  g.gci_fine = 1.25 * g.approximate_error / (r21p - 1.0);
  const double gci32 = phi2 != 0.0 ? 1.25 * std::abs(e32 / phi2) / (r32p - 1.0) : nan;
  g.asymptotic_ratio = gci32 / (r21p * g.gci_fine);
  return g;
}

}  // namespace vesselmesh::study
