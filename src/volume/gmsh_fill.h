// The interior's tetrahedra by Gmsh's 3D algorithms (Delaunay, Frontal, HXT), for
// fill_tetrahedra (volume/fill.h), which documents the arguments and the result. Gmsh's calls
// live here so that they can sit in the module the program opens only when it needs Gmsh
// (modules/gmsh_module.h).
#pragma once

#include "volume/fill.h"

namespace vesselmesh::volume {

FillResult gmsh_fill(const std::vector<Vec3>& points, const std::vector<Triangle>& boundary, FillAlgorithm algorithm,
                     int threads, const Reporter& reporter, const SizeFunction& size = {});

}  // namespace vesselmesh::volume
