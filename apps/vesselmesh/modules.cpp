#include "modules.h"

#include "mesh/error.h"

#include <dlfcn.h>
#include <fmt/format.h>

#include <filesystem>
#include <string>
#include <system_error>

namespace vesselmesh::cli {

const void* open_module(const char* file, const char* entry, int layout, bool global) {
  std::error_code error;
  const std::filesystem::path program = std::filesystem::read_symlink("/proc/self/exe", error);
  const std::filesystem::path folder = error ? std::filesystem::path(".") : program.parent_path();
  std::string tried;
  for (const std::filesystem::path& candidate : {folder / file, folder / "../lib/vesselmesh" / file}) {
    void* module = dlopen(candidate.c_str(), RTLD_NOW | (global ? RTLD_GLOBAL : RTLD_LOCAL));
    if (!module) {
      const char* why = dlerror();
      tried += fmt::format("\n  {}: {}", candidate.string(), why ? why : "not opened");
      continue;
    }
    using Entry = const void* (*)();
    const auto function = reinterpret_cast<Entry>(dlsym(module, entry));
    const void* table = function ? function() : nullptr;
    if (table && *static_cast<const int*>(table) == layout) return table;
    tried += fmt::format("\n  {}: built from other sources than this program (rebuild both)", candidate.string());
  }
  throw InputError(fmt::format("this command needs the module {}, which could not be opened:{}\nbuild the project "
                               "again (cmake --build) or reinstall vesselmesh",
                               file, tried));
}

}  // namespace vesselmesh::cli
