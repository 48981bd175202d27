// The distance map (the seed paper's definition): for every surface point, its Euclidean
// distance to the nearest centerline segment, and the maximal inscribed sphere radius at that
// nearest centerline point (interpolated along the segment). Sizing uses it for the vessel's
// local size; the boundary layer for its thickness. AABB tree of the segments: n log n.
#pragma once

#include "centerline/extract.h"

#include <vector>

namespace vesselmesh::centerline {

struct DistanceMap {
  std::vector<double> distance;  // per surface point, in the mesh's unit
  std::vector<double> radius;    // MISR of the nearest centerline point
};

DistanceMap distance_map(const TriMesh& surface, const Centerlines& centerlines);

}  // namespace vesselmesh::centerline
