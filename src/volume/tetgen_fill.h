// The interior tetrahedra of a closed, outward-oriented triangle surface by TetGen 1.5 (Si 2015,
// ACM TOMS 41(2); Debian's libtet1.5, AGPL-3.0-or-later), fed in memory: the boundary kept as
// it is (-Y: no point added on it), quality refinement to a radius-edge ratio and a least
// dihedral angle (-q; the angle is a goal of TetGen's optimisation, not a guarantee: a few
// tetrahedra stay below it), sizes from the size function handed in (a tetrahedron is split while
// its circumradius exceeds `circumradius_factor` times the size at its centroid: TetGen's
// refinement callback), or without one from the boundary's edge lengths (-m: each boundary point's
// mean edge times a factor, interpolated inside). Deterministic, single-threaded. Only volume/fill
// calls it (through FillAlgorithm::tetgen).
#pragma once

#include "mesh/reporter.h"
#include "mesh/tetmesh.h"
#include "volume/fill.h"

#include <vector>

namespace vesselmesh::volume {

struct TetgenQuality {
  double radius_edge_ratio = 1.3;  // TetGen's -q bound (its default 2.0)
  double min_dihedral_deg = 10.0;  // TetGen's -q/angle bound (the interior goal)
  // TetGen's size at a boundary point: this times its mean edge (1.2: 1.1 to 1.4 times Gmsh
  // Delaunay's interior count on the remeshed anastomosis and the bench pipe; 1.0: 1.7 times).
  double size_factor = 1.2;
  // With a size function: a tetrahedron is split while its circumradius exceeds this times the
  // size at its centroid (a regular tetrahedron of edge h has circumradius 0.61 h). Set so that
  // the median interior edge is the size (0.75 gave 0.91 of it on the pipe of
  // tests/volume/interior_size_test.cpp).
  double circumradius_factor = 0.82;
};

// As fill_tetrahedra: `points` handed in, then those TetGen added; tetrahedra of positive
// volume. Throws InputError for a boundary that is not closed, or naming TetGen's reason when it
// fails (self-intersection, facets too close, ...).
FillResult tetgen_fill(const std::vector<Vec3>& points, const std::vector<Triangle>& boundary,
                       const TetgenQuality& quality = {}, const Reporter& reporter = silent_reporter(),
                       const SizeFunction& size = {});

}  // namespace vesselmesh::volume
