// Wavefront OBJ surfaces: "v x y z [w]" points and "f a b c ..." faces (a, a/t, a//n, a/t/n;
// negative indices count back from the last point), polygons split into triangles (fans).
// Groups and objects ("g", "o") become triangle labels 1, 2, ... in order of appearance when
// there are several. Other statements are read past. Errors name the file and the line.
#pragma once

#include "mesh/trimesh.h"

#include <string>
#include <string_view>

namespace vesselmesh::io {

TriMesh parse_obj(std::string_view text, const std::string& name);
TriMesh read_obj(const std::string& path);

}  // namespace vesselmesh::io
