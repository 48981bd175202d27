// A cache-friendly numbering of a volume mesh: reverse Cuthill-McKee (George & Liu 1981) over
// the point graph (points sharing a cell), so that a point's neighbours have nearby numbers: the
// flow solver's matrix rows then touch nearby memory, and consecutive ranges of points are
// compact pieces of the lumen (what a process owns under MPI). Meshers number points as they
// make them (a layer's levels one after the other, a Delaunay fill in insertion order), far
// from each other for neighbours.
// Each connected part starts from a pseudo-peripheral point (the far end of repeated breadth-first
// sweeps from its least-degree point); a point's unvisited neighbours are taken by increasing
// degree, ties by index: the same mesh gives the same order, run after run.
#pragma once

#include "mesh/tetmesh.h"

#include <vector>

namespace vesselmesh::mesh {

// order[new] = old over the mesh's points; points no cell uses come last, in their order.
std::vector<int> cuthill_mckee_order(const TetMesh& mesh);

// The mesh with its points in `order` (order[new] = old, a permutation of the points), its
// tetrahedra and prisms sorted by their corners' new numbers (least first; their layer and
// column data follow them), its boundary triangles in their order, renumbered.
TetMesh renumbered(const TetMesh& mesh, const std::vector<int>& order);

// The half bandwidth of the point graph: the largest |a - b| over points a, b sharing a cell.
int point_bandwidth(const TetMesh& mesh);

}  // namespace vesselmesh::mesh
