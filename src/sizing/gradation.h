// Size gradation: limits how fast the size may grow across the surface, so that a small size
// spreads to its neighbourhood instead of meeting a large one across a single edge.
// With growth factor g, along an edge e from point i to j, the metric of i spread to j is
// M_i / (1 + |e|_{M_i} ln g)^2 (sizes grow linearly with the distance in i's metric, slope
// ln g: about g per unit of metric length), and j keeps M_j cap (M_i spread): F. Alauzet, "Size
// gradation control of anisotropic meshes", FEAD 46 (2010), the anisotropic form of
// Borouchaki's H-correction. Isotropic fields keep scalars: h_j <= h_i + |e| ln g.
// Passes over the edges in index order until nothing changes: deterministic.
#pragma once

#include "mesh/point_graph.h"
#include "mesh/sym3.h"
#include "mesh/trimesh.h"

#include <vector>

namespace vesselmesh::sizing {

// In place; returns the number of passes made. `growth` <= 1 leaves the field as it is.
int grade_sizes(const TriMesh& mesh, std::vector<double>& sizes, double growth);
int grade_metrics(const TriMesh& mesh, std::vector<Sym3>& metrics, double growth);

// Isotropic sizes over a volume's point graph (the flow kind's interior): afterwards
// h_j <= h_i + |x_j - x_i| ln g along every edge, each size the least over all paths of
// h_i + (path length) ln g, found at once by Dijkstra's method from every point (a point settled
// once: no pass cap). Ties go by point index: deterministic. Returns the number of sizes lowered.
int grade_sizes(const std::vector<Vec3>& points, const mesh::PointGraph& graph, std::vector<double>& sizes,
                double growth);

}  // namespace vesselmesh::sizing
