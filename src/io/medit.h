// Medit (INRIA) ASCII .mesh surfaces and .sol metrics, the formats of MMG: for handing a
// surface and its size field to mmgs, and reading its result back.
#pragma once

#include "mesh/sym3.h"
#include "mesh/trimesh.h"

#include <string>
#include <string_view>
#include <vector>

namespace vesselmesh::io {

// Vertices and Triangles (their references become labels when not all equal); the other
// sections of a surface file (Edges, Corners, Ridges, Required*, Normals, Tangents, ...) are
// skipped. Errors name the file and line.
TriMesh parse_medit(std::string_view text, const std::string& name);
TriMesh read_medit(const std::string& path);

// MeshVersionFormatted 2 (double precision); labels as triangle references (0 without).
void write_medit(const std::string& path, const TriMesh& mesh);

// SolAtVertices: one symmetric tensor a point, in Medit's order (xx, xy, yy, xz, yz, zz).
void write_medit_metric(const std::string& path, const std::vector<Sym3>& metric);

}  // namespace vesselmesh::io
