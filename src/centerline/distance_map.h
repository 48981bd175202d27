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

// The local radius where no centerlines can be traced (a closed segmentation with rounded ends):
// at each surface point, the radius of its inner pole (VoronoiGraph::pole_radius; the surface
// closed at its open ends, if any, for the inside test), the largest over two rings of
// triangles and then averaged (see the .cpp). About R on a pipe of radius R; at a bump of the
// wall it stays about the vessel's radius, where 1/max|k| (the other fallback) falls to the
// bump's. Points no inside ball touches take the median first. InputError when no Voronoi
// vertex lies inside (not a closed lumen).
std::vector<double> pole_radius(const TriMesh& surface, const Reporter& reporter = silent_reporter());

}  // namespace vesselmesh::centerline
