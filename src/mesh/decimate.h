// A triangle surface made coarser for display (VTK's quadric decimation, behind this header): the
// report's interactive views hold at most a set number of triangles a wall. Not for simulation:
// the result keeps the shape to the eye, not the remesher's bounds.
#pragma once

#include "mesh/trimesh.h"

namespace vesselmesh::mesh {

// `surface` itself when it has at most `max_triangles` triangles; otherwise a surface of at most
// that many (quadric edge collapses, the volume and the open ends' rims kept).
TriMesh decimated(const TriMesh& surface, int max_triangles);

}  // namespace vesselmesh::mesh
