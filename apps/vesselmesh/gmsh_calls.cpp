// The library's functions that call Gmsh, as this program has them: each opens Gmsh's module
// on first use and forwards to it (see io/gmsh_module.h for why).
#include "io/gmsh_module.h"
#include "io/msh.h"
#include "mesh/error.h"
#include "volume/gmsh_fill.h"

#include <dlfcn.h>
#include <fmt/format.h>

#include <filesystem>
#include <system_error>

namespace vesselmesh {
namespace {

const io::GmshCalls& gmsh_calls() {
  static const io::GmshCalls* calls = []() -> const io::GmshCalls* {
    std::error_code error;
    const std::filesystem::path program = std::filesystem::read_symlink("/proc/self/exe", error);
    const std::filesystem::path folder = error ? std::filesystem::path(".") : program.parent_path();
    std::string tried;
    for (const std::filesystem::path& candidate :
         {folder / io::kGmshModuleFile, folder / io::kGmshModuleInstallFolder / io::kGmshModuleFile}) {
      void* module = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (!module) {
        const char* why = dlerror();
        tried += fmt::format("\n  {}: {}", candidate.string(), why ? why : "not opened");
        continue;
      }
      using Entry = const io::GmshCalls* (*)();
      const auto entry = reinterpret_cast<Entry>(dlsym(module, "vesselmesh_gmsh_calls"));
      const io::GmshCalls* table = entry ? entry() : nullptr;
      if (table && table->layout == io::kGmshCallsLayout) return table;
      tried += fmt::format("\n  {}: built from other sources than this program (rebuild both)", candidate.string());
    }
    throw InputError(fmt::format("this command needs Gmsh, whose module {} could not be opened:{}\nbuild the "
                                 "project again (cmake --build) or reinstall vesselmesh",
                                 io::kGmshModuleFile, tried));
  }();
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
                     int threads, const Reporter& reporter) {
  return gmsh_calls().gmsh_fill(points, boundary, algorithm, threads, reporter);
}
}  // namespace volume

}  // namespace vesselmesh
