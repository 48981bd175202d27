// The discretization uncertainty of a quantity computed on three systematically refined grids:
// Richardson extrapolation and Roache's Grid Convergence Index, as in Celik, Ghia, Roache,
// Freitas, Coleman and Raad, "Procedure for estimation and reporting of uncertainty due to
// discretization in CFD applications", J. Fluids Eng. 130 (2008) 078001:
//   h = N^(-1/3) (N the grid's points), r21 = h2/h1, r32 = h3/h2 (1 the finest);
//   e21 = phi2 - phi1, e32 = phi3 - phi2, s = sign(e32/e21);
//   p = |ln|e32/e21| + q(p)| / ln r21, q(p) = ln((r21^p - s)/(r32^p - s)) (fixed-point);
//   phi_ext = (r21^p phi1 - phi2)/(r21^p - 1);
//   e_a = |(phi1 - phi2)/phi1|, e_ext = |(phi_ext - phi1)/phi_ext|, GCI_fine = 1.25 e_a/(r21^p - 1);
//   in the asymptotic range GCI32 / (r21^p GCI21) is near 1 (GCI32 = 1.25 |e32/phi2| / (r32^p - 1)).
// s < 0 is oscillatory convergence (the order still computed with s, as the paper does); an
// order that is not found (the iteration does not settle, or p < 0.5: r21^p - 1 near zero would
// make the GCI explode where two differences are nearly equal) leaves the extrapolation and the
// GCI undefined (NaN), said in `status`. An observed order above 2 (the P1 velocity's formal
// order; WSS, its gradient, has 1) is reported but taken as 2 for the extrapolation and the GCI,
// so that a lucky triplet does not claim a tiny uncertainty (Roache's advice to limit p).
#pragma once

#include <string>

namespace vesselmesh::study {

struct GridConvergence {
  double phi1 = 0.0, phi2 = 0.0, phi3 = 0.0;  // finest, medium, coarsest
  double r21 = 0.0, r32 = 0.0;
  double order = 0.0;               // observed p (NaN if not found)
  double extrapolated = 0.0;        // phi_ext (NaN if not found)
  double approximate_error = 0.0;   // e_a21, relative
  double extrapolated_error = 0.0;  // e_ext21, relative (NaN if not found)
  double gci_fine = 0.0;            // GCI_fine21, relative (NaN if not found)
  double asymptotic_ratio = 0.0;    // GCI32 / (r21^p GCI21) (NaN if not found)
  bool oscillatory = false;         // the two differences of opposite signs
  bool found = false;               // an order p > 0 was found
  std::string status;               // "monotone", "oscillatory", "the two finest agree", "no convergence"
  // The series' spread, max(|phi2 - phi1|, |phi3 - phi1|) / |phi1|: where no order is found the
  // finest value's uncertainty is unknown but not less than this.
  double spread = 0.0;
  // The GCI band: the finest value's uncertainty in the quantity's own unit (|phi1| GCI_fine).
  double band() const;
};

// `n1, n2, n3`: the grids' point counts, finest first (n1 > n2 > n3); `phi`: the quantity on them;
// `dimension`: 3 for volume grids (h = N^(-1/3)), 2 for the paper's planar examples. Throws
// InputError for counts that are not strictly decreasing. Monotone convergence needs the
// differences to shrink (|e21| < |e32|); where they do not, no order is claimed.
GridConvergence grid_convergence(double n1, double n2, double n3, double phi1, double phi2, double phi3,
                                 int dimension = 3);

}  // namespace vesselmesh::study
