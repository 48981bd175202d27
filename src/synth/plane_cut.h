// Cutting a tube open with a plane: the part of the surface beyond the plane, within a
// given distance of the plane's axis, is removed; triangles that cross the plane are split
// exactly on it, so the new boundary loop lies in the plane.
#pragma once

#include "mesh/trimesh.h"

#include <functional>

namespace vesselmesh::synth {

struct CutPlane {
  Vec3 point;         // on the plane, on the tube's axis
  Vec3 normal;        // unit; the side it points to is removed
  double reach = 0.0; // only points within this distance of the axis line are cut
};

// Points closer to the plane than `snap` (and within reach) are first moved onto it by
// `move_onto_plane` (which must keep them on the surface), so that no sliver is made.
// Returns the cut surface; labels are carried, unused points dropped.
TriMesh cut_by_plane(const TriMesh& mesh, const CutPlane& plane, double snap,
                     const std::function<Vec3(const Vec3&)>& move_onto_plane);

}  // namespace vesselmesh::synth
