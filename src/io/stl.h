// STL surfaces: binary and ASCII, told apart from the bytes (not the header's first word).
//
// Reading merges corners with bit-identical coordinates into shared points (an STL stores
// every triangle's corners separately), in order of first appearance, so the same file
// always gives the same mesh. Coordinates are returned as stored (no unit conversion).
// Errors (InputError) name the file and say what is wrong: empty, truncated, a triangle
// count that disagrees with the file size, NaN/Inf coordinates (with the triangle or line),
// malformed ASCII (with the line), or bytes that are no STL at all.
#pragma once

#include "mesh/trimesh.h"

#include <string>
#include <string_view>

namespace vesselmesh::io {

struct StlInfo {
  bool binary = true;
  std::string header;         // the 80-byte header (binary) or the solid's name (ASCII)
  long long raw_triangles = 0;  // facets in the file
};

// `name` is used in error messages (usually the file's path).
TriMesh parse_stl(std::string_view bytes, const std::string& name, StlInfo* info = nullptr);
TriMesh read_stl(const std::string& path, StlInfo* info = nullptr);

// Binary STL, float32 coordinates, facet normals from the triangles; written atomically.
// Labels are not stored (STL has no place for them).
void write_stl(const std::string& path, const TriMesh& mesh);

}  // namespace vesselmesh::io
