// Reading a volume mesh, whatever file `vesselmesh volume` wrote it to.
#pragma once

#include "mesh/tetmesh.h"

#include <string>

namespace vesselmesh::io {

// A volume mesh from .msh (MSH 4.1 text streamed, io/msh_stream.h; any other MSH through Gmsh,
// io/msh.h) or .vtu (with cell data `tag`, io/vtk_formats.h). InputError naming the file for a
// missing file or another extension.
TetMesh read_volume(const std::string& path);

}  // namespace vesselmesh::io
