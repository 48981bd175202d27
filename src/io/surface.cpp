#include "io/surface.h"

#include "io/medit.h"
#include "io/msh.h"
#include "io/obj.h"
#include "io/ply.h"
#include "io/stl.h"
#include "mesh/error.h"
#include "mesh/geometry.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace vesselmesh::io {

SurfaceFormat surface_format(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".stl") return SurfaceFormat::stl;
  if (ext == ".vtp") return SurfaceFormat::vtp;
  if (ext == ".vtu") return SurfaceFormat::vtu;
  if (ext == ".ply") return SurfaceFormat::ply;
  if (ext == ".obj") return SurfaceFormat::obj;
  if (ext == ".msh") return SurfaceFormat::msh;
  if (ext == ".mesh") return SurfaceFormat::medit;
  throw OptionError(fmt::format("{}: unknown surface format '{}': use .stl, .vtp, .vtu, .ply, .obj, .msh or .mesh",
                                path, ext.empty() ? "(no extension)" : ext));
}

SurfaceFile read_surface(const std::string& path, const ReadOptions& options, const Reporter& reporter) {
  const SurfaceFormat format = surface_format(path);
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw InputError(fmt::format("{}: no such file", path));
  SurfaceFile file;
  file.path = path;
  switch (format) {
    case SurfaceFormat::stl: {
      StlInfo info;
      file.mesh = read_stl(path, &info);
      file.format = info.binary ? "binary STL" : "ASCII STL";
      break;
    }
    case SurfaceFormat::msh:
      file.mesh = read_msh_surface(path);
      file.format = "Gmsh MSH";
      break;
    case SurfaceFormat::medit:
      file.mesh = read_medit(path);
      file.format = "Medit";
      break;
    case SurfaceFormat::ply:
      file.mesh = read_ply(path);
      file.format = "PLY";
      break;
    case SurfaceFormat::obj:
      file.mesh = read_obj(path);
      file.format = "OBJ";
      break;
    case SurfaceFormat::vtp:
    case SurfaceFormat::vtu: {
      const bool vtp = format == SurfaceFormat::vtp;
      static_cast<SurfaceData&>(file) = read_vtk_surface(path, vtp ? VtkFormat::vtp : VtkFormat::vtu, options.label_array);
      file.format = vtp ? "VTK PolyData" : "VTK UnstructuredGrid";
      break;
    }
  }
  file.unit_given = options.units.has_value();
  file.unit = options.units.value_or(Unit::mm);
  file.scale_to_mm = millimetres_per(file.unit);
  if (file.scale_to_mm != 1.0)
    for (Vec3& p : file.mesh.points) p *= file.scale_to_mm;

  const auto [lo, hi] = mesh::bounding_box(file.mesh.points);
  const double size = (hi - lo).norm();
  if (!file.unit_given && size < 1.0)
    reporter.warning(fmt::format(
        "{}: the surface is only {:.3g} across if its unit is mm; if the file is in metres, "
        "pass --units m",
        path, size));
  else if (!file.unit_given && size > 2000.0)
    reporter.warning(fmt::format("{}: the surface is {:.4g} mm across; if the file is in micrometres, "
                                 "pass --units um",
                                 path, size));
  return file;
}

void check_surface_output(const std::string& path) {
  const SurfaceFormat format = surface_format(path);
  if (format != SurfaceFormat::stl && format != SurfaceFormat::vtp && format != SurfaceFormat::msh &&
      format != SurfaceFormat::medit)
    throw OptionError(fmt::format("{}: cannot write this format: use .stl, .vtp, .msh or .mesh", path));
}

void write_surface(const std::string& path, const TriMesh& mesh, const std::vector<Field>& point_data,
                   const std::vector<Field>& cell_data) {
  check_surface_output(path);
  switch (surface_format(path)) {
    case SurfaceFormat::stl: return write_stl(path, mesh);
    case SurfaceFormat::vtp: return write_vtp(path, mesh, point_data, cell_data);
    case SurfaceFormat::msh: return write_msh(path, mesh);
    default: return write_medit(path, mesh);
  }
}

}  // namespace vesselmesh::io
