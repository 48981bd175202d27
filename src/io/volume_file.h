// Reading and writing a volume mesh, whatever file `vesselmesh volume` wrote it to.
#pragma once

#include "mesh/tetmesh.h"

#include <string>
#include <vector>

namespace vesselmesh::io {

// A volume mesh from .msh (MSH 4.1 text streamed, io/msh_stream.h; any other MSH through Gmsh,
// io/msh.h) or .vtu (with cell data `tag`, io/vtk_formats.h). InputError naming the file for a
// missing file or another extension.
TetMesh read_volume(const std::string& path);

// Writes one by `path`'s extension: .msh (Gmsh 4.1, io/msh.h) or .vtu (VTK, with `point_data`,
// io/vtk_formats.h). OptionError naming the file for another extension: check_volume_output says
// it before any work.
void write_volume(const std::string& path, const TetMesh& mesh, const std::vector<Field>& point_data = {});
void check_volume_output(const std::string& path);

}  // namespace vesselmesh::io
