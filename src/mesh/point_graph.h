// The point graph of a volume mesh: which points share a cell, in compressed rows. One builder for
// the numbering (mesh/reorder.h) and the split of a mesh among processes (flow/mesh_part.h).
#pragma once

#include "mesh/tetmesh.h"

#include <vector>

namespace vesselmesh::mesh {

// Row v: the points sharing a cell with v, sorted, v itself left out.
struct PointGraph {
  std::vector<int> start, next;  // row v is next[start[v] .. start[v + 1])
  int degree(int v) const { return start[v + 1] - start[v]; }
};

// Over `points` points, from the cells given (a prism's six corners all neighbours). A corner out of
// range is an InternalError.
PointGraph point_graph(int points, const std::vector<Tet>& tets, const std::vector<Prism>& prisms = {});

// The same graph with its points renumbered: `order[new] = old` (a permutation), rows and their
// entries in the new numbers, each row sorted.
PointGraph renumbered(const PointGraph& graph, const std::vector<int>& order);

}  // namespace vesselmesh::mesh
