// PLY surfaces (ascii, binary little- and big-endian): the x, y, z of the "vertex" element and
// the "vertex_indices" lists of the "face" element, polygons split into triangles (fans).
// Other elements and properties are read past. Points with identical coordinates are
// merged. Errors (InputError) name the file and the line or byte.
#pragma once

#include "mesh/trimesh.h"

#include <string>
#include <string_view>

namespace vesselmesh::io {

TriMesh parse_ply(std::string_view bytes, const std::string& name);
TriMesh read_ply(const std::string& path);

}  // namespace vesselmesh::io
