// The library's functions that call Gmsh, as this program has them: each opens Gmsh's module
// on first use and forwards to it (see modules/gmsh_module.h for why).
#include "modules/gmsh_module.h"
#include "io/msh.h"
#include "modules.h"
#include "volume/gmsh_fill.h"

namespace vesselmesh {
namespace {

const io::GmshCalls& gmsh_calls() {
  static const auto* calls =
      static_cast<const io::GmshCalls*>(cli::open_module(io::kGmshModuleFile, "vesselmesh_gmsh_calls", io::kGmshCallsLayout));
  return *calls;
}

}  // namespace

namespace io {
void write_msh(const std::string& path, const TriMesh& mesh, const std::map<int, std::string>& label_names) {
  gmsh_calls().write_surface_msh(path, mesh, label_names);
}
TriMesh read_msh_surface(const std::string& path, std::map<int, std::string>* label_names) {
  return gmsh_calls().read_msh_surface(path, label_names);
}
void write_msh(const std::string& path, const TetMesh& mesh) { gmsh_calls().write_volume_msh(path, mesh); }
TetMesh read_msh_volume(const std::string& path) { return gmsh_calls().read_msh_volume(path); }
}  // namespace io

namespace remesh {
GmshRemeshResult reparametrize(const TriMesh& input, const std::vector<Sym3>& metrics, const GmshRemeshOptions& options,
                               const Reporter& reporter) {
  return gmsh_calls().reparametrize(input, metrics, options, reporter);
}
}  // namespace remesh

namespace volume {
FillResult gmsh_fill(const std::vector<Vec3>& points, const std::vector<Triangle>& boundary, FillAlgorithm algorithm,
                     int threads, const Reporter& reporter, const SizeFunction& size) {
  return gmsh_calls().gmsh_fill(points, boundary, algorithm, threads, reporter, size);
}
}  // namespace volume

}  // namespace vesselmesh
