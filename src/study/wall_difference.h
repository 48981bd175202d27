// Whole-wall measures of how far a mesh's wall field is from the reference's (issue 46): less
// fragile than one ring's minimum or one point, where a stagnation point moves.
// The mesh's field is interpolated onto the reference's wall (at each reference point, the mesh
// wall's closest point, linear on its triangle); over the reference's wall, with each point's
// area a third of its triangles':
//   L2  = sqrt(sum A_i |d_i|^2 / sum A_i) / mean,   P95 = the area-weighted 95th percentile of |d_i| / mean,
// d_i the difference at point i (a vector for WSS, a number for TAWSS and OSI), mean the
// reference's area-weighted mean of |its field|. Dimensionless (a fraction; the report gives %).
#pragma once

#include "mesh/trimesh.h"

#include <array>
#include <vector>

namespace vesselmesh::study {

// Where each point of `target` falls on `source`: its closest point's triangle corners and their
// linear weights.
struct WallMap {
  std::vector<std::array<int, 3>> corners;
  std::vector<std::array<double, 3>> weights;
};
WallMap map_onto(const TriMesh& source, const TriMesh& target);

std::vector<Vec3> interpolate(const WallMap& map, const std::vector<Vec3>& field);
std::vector<double> interpolate(const WallMap& map, const std::vector<double>& field);

// Per point: a third of the area of the triangles around it.
std::vector<double> lumped_areas(const TriMesh& mesh);

struct WallDifference {
  double l2 = 0.0, p95 = 0.0;  // over the reference's mean
  double mean = 0.0;           // the reference's area-weighted mean |field|
};
WallDifference wall_difference(const std::vector<double>& area, const std::vector<Vec3>& field,
                               const std::vector<Vec3>& reference);
WallDifference wall_difference(const std::vector<double>& area, const std::vector<double>& field,
                               const std::vector<double>& reference);

}  // namespace vesselmesh::study
