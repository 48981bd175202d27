// The entry table of libvesselmesh-gmsh.so (see gmsh_module.h); built into the module only.
#include "modules/gmsh_module.h"

#include "io/msh.h"
#include "volume/gmsh_fill.h"

extern "C" __attribute__((visibility("default"))) const vesselmesh::io::GmshCalls* vesselmesh_gmsh_calls() {
  using namespace vesselmesh;
  static const io::GmshCalls calls{
      io::kGmshCallsLayout,
      [](const std::string& path, const TriMesh& mesh, const std::map<int, std::string>& names) {
        io::write_msh(path, mesh, names);
      },
      &io::read_msh_surface,
      [](const std::string& path, const TetMesh& mesh) { io::write_msh(path, mesh); },
      &io::read_msh_volume,
      &remesh::reparametrize,
      &volume::gmsh_fill,
  };
  return &calls;
}
