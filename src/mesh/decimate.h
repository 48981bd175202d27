// A triangle surface made coarser for display (VTK's vtkDecimatePro, behind this header): the
// report's interactive views hold at most a set number of triangles a wall. Not for simulation:
// the result keeps the shape to the eye, not the remesher's bounds.
#pragma once

#include "mesh/trimesh.h"

namespace vesselmesh::mesh {

// `surface` itself when it has at most `max_triangles` triangles; otherwise a surface of at most
// that many (edge collapses by the least error, the topology and the open ends' rims kept; 3 s for
// 535k triangles to 50k).
TriMesh decimated(const TriMesh& surface, int max_triangles);

}  // namespace vesselmesh::mesh
