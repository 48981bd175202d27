#include "io/volume_file.h"

#include "io/msh.h"
#include "io/msh_stream.h"
#include "io/vtk_formats.h"
#include "mesh/error.h"

#include <fmt/format.h>

#include <cctype>
#include <filesystem>

namespace vesselmesh::io {

TetMesh read_volume(const std::string& path) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error))
    throw InputError(fmt::format("{}: cannot open: no such file", path));
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (extension == ".msh") {
    std::optional<TetMesh> mesh = read_msh41_volume(path);
    return mesh ? std::move(*mesh) : read_msh_volume(path);
  }
  if (extension == ".vtu") return read_vtu_volume(path);
  throw InputError(fmt::format("{}: a volume mesh is read from .msh (Gmsh) or .vtu (with cell data `tag`), as "
                               "'vesselmesh volume' writes them",
                               path));
}

}  // namespace vesselmesh::io
