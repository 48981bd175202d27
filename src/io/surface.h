// Reading and writing surfaces, the format told by the file's extension:
// read .stl (binary or ASCII), .vtp, .vtu, .ply, .obj, .msh, .mesh (Medit); write .stl, .vtp, .msh,
// .mesh.
//
// Reading converts lengths to millimetres from the unit the caller states (`units`, default
// mm). Writing is atomic: an output file is whole or absent.
#pragma once

#include "io/units.h"
#include "io/vtk_formats.h"
#include "mesh/reporter.h"

#include <optional>
#include <string>

namespace vesselmesh::io {

enum class SurfaceFormat { stl, vtp, vtu, ply, obj, msh, medit };

// From the extension (case-insensitive). Throws OptionError naming the accepted extensions.
SurfaceFormat surface_format(const std::string& path);

struct ReadOptions {
  std::optional<Unit> units;  // the file's length unit; mm when not given
  std::string label_array = {};  // VTK formats: the integer cell array holding triangle labels
};

struct SurfaceFile : SurfaceData {
  std::string path;
  std::string format;          // e.g. "binary STL"
  Unit unit = Unit::mm;        // the file's unit
  bool unit_given = false;     // false: mm was assumed
  double scale_to_mm = 1.0;    // applied to the points
};

// Points are in mm on return. Warns (through `reporter`) when no unit was given and the
// surface's size suggests another unit.
SurfaceFile read_surface(const std::string& path, const ReadOptions& options = {},
                         const Reporter& reporter = silent_reporter());

// Writes by extension (.stl, .vtp, .msh, .mesh); fields go to VTP only. Throws OptionError for an
// extension that cannot be written, as check_surface_output does before any work.
void check_surface_output(const std::string& path);
void write_surface(const std::string& path, const TriMesh& mesh,
                   const std::vector<Field>& point_data = {}, const std::vector<Field>& cell_data = {});

}  // namespace vesselmesh::io
