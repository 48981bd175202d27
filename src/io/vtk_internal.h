// Shared by the VTK-based readers and writers of io/ (not a public header).
#pragma once

#include "io/vtk_formats.h"

#include <string>
#include <vector>

namespace vesselmesh::io {

// VTK reports errors through its output window and logger; they are kept (not printed) and
// read back here. Call keep_vtk_errors() before using VTK on this thread.
void keep_vtk_errors();
bool vtk_failed();
std::string vtk_error_text();
const char* vtk_format_name(VtkFormat format);

// Joins a piece's fields onto those of the pieces before: the first piece sets them, later
// pieces keep only the arrays every piece has (same name and components).
void append_piece_fields(std::vector<Field>& fields, std::vector<Field>& piece, bool first);

// Point data after a merge of points (mesh::merge_identical_points' `remap`, to `points` points):
// each merged point's values are the first one's.
void merge_point_fields(std::vector<Field>& fields, const std::vector<int>& remap, int points);

// Last steps of every reader: labels taken from the chosen integer cell array (or the first
// of ModelFaceID, tag, CellEntityIds, gmsh:physical), points with identical coordinates
// merged (point data from the first). `cell_fields` hold one tuple per triangle.
SurfaceData finish_surface(SurfaceData raw, std::vector<Field> cell_fields, const std::string& label_array,
                           const std::string& name);

}  // namespace vesselmesh::io
