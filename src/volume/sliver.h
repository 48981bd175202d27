// Sliver removal: a local clean-up of the tetrahedra a fill engine hands back, raising the
// least dihedral angle of the few flat ones (slivers) that its own optimization leaves.
//
// Every tetrahedron whose least dihedral angle is under the goal is worked on, in index order,
// with the operations of Klingner and Shewchuk ("Aggressive tetrahedral mesh improvement",
// IMR 2007), in their simplest forms:
//  - flips: 2-3 (the face it shares with a neighbour replaced by the edge joining their far
//    corners) and 3-2 (an edge with three tetrahedra around it replaced by a face);
//  - smoothing: a free corner moved (compass search) to where the least dihedral angle of the
//    tetrahedra around it is largest;
//  - collapse: a free corner removed, moved onto the neighbour that leaves its ball best;
//  - insertion: a new point at the sliver's centroid, joined to the faces of the cavity of the
//    tetrahedra it sees (the sliver and those across its faces), then smoothed; for a sliver
//    standing on the boundary, a point at the apex of a fair tetrahedron on that face, in the
//    cavity of the tetrahedra whose circumspheres hold it (Bowyer-Watson);
//  - when nothing cures a sliver, flips and moves on the tetrahedra across its faces (each kept
//    only if it raises their own least angle), so that the next pass sees it anew.
// Passes over what is still under the goal run until nothing changes.
// An operation is kept only when the least dihedral angle of the tetrahedra it replaces or
// moves rises, so the worst angle of the mesh never falls and no tetrahedron is inverted.
// Boundary faces (faces of one tetrahedron) are never changed and points below `first_free`
// never move, so the surface handed to the fill is kept exactly. Deterministic (one thread,
// index order).
#pragma once

#include "mesh/tetmesh.h"

#include <vector>

namespace vesselmesh::volume {

struct SliverOptions {
  double min_dihedral_deg = 10.0;  // the goal: tetrahedra under it are worked on
  int passes = 40;                 // over the tetrahedra still under the goal (until nothing changes)
};

struct SliverReport {
  int below_before = 0, below_after = 0;        // tetrahedra under the goal
  double least_before = 0.0, least_after = 0.0;  // degrees; over all tetrahedra
  int flips = 0, moves = 0, insertions = 0, collapses = 0;
  Vec3 worst_at = Vec3::Zero();  // centroid of the worst tetrahedron left
};

// `tets` positive; points from `first_free` on may move or go (the others renumbered), points
// may be added.
SliverReport remove_slivers(std::vector<Vec3>& points, std::vector<Tet>& tets, int first_free,
                            const SliverOptions& options = {});

// The least dihedral angle of a tetrahedron, in degrees; negative when it is flat or inverted.
double least_dihedral_deg(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

}  // namespace vesselmesh::volume
