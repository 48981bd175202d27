#include "io/volume_file.h"

#include "io/msh.h"
#include "io/msh_stream.h"
#include "io/vtk_formats.h"
#include "mesh/error.h"

#include <fmt/format.h>

#include <cctype>
#include <filesystem>

namespace vesselmesh::io {

namespace {

std::string lower_extension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension;
}

}  // namespace

TetMesh read_volume(const std::string& path) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error))
    throw InputError(fmt::format("{}: cannot open: no such file", path));
  const std::string extension = lower_extension(path);
  if (extension == ".msh") {
    std::optional<TetMesh> mesh = read_msh41_volume(path);
    return mesh ? std::move(*mesh) : read_msh_volume(path);
  }
  if (extension == ".vtu") return read_vtu_volume(path);
  throw InputError(fmt::format("{}: a volume mesh is read from .msh (Gmsh) or .vtu (with cell data `tag`), as "
                               "'vesselmesh volume' writes them",
                               path));
}

void check_volume_output(const std::string& path) {
  const std::string extension = lower_extension(path);
  if (extension != ".msh" && extension != ".vtu")
    throw OptionError(fmt::format("{}: a volume mesh is written as .vtu (VTK, with layer data) or .msh (Gmsh 4.1)", path));
}

void write_volume(const std::string& path, const TetMesh& mesh, const std::vector<Field>& point_data) {
  check_volume_output(path);
  if (lower_extension(path) == ".vtu") write_vtu(path, mesh, point_data);
  else write_msh(path, mesh);
}

}  // namespace vesselmesh::io
