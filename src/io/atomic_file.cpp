#include "io/atomic_file.h"

#include "mesh/error.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <system_error>

#include <unistd.h>

namespace vesselmesh::io {

namespace fs = std::filesystem;

void write_atomically(const std::string& path, const std::function<void(const std::string&)>& write) {
  const fs::path target(path);
  const fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw InputError(fmt::format("{}: cannot write: folder '{}' does not exist", path, folder.string()));
  if (fs::is_directory(target, ec))
    throw InputError(fmt::format("{}: cannot write: it is a folder", path));
  // A name unique to this process and call, hidden, with the target's extension.
  static std::mt19937_64 rng(std::random_device{}());
  const fs::path temporary =
      folder / fmt::format(".{}.tmp{}-{:x}{}", target.stem().string(), ::getpid(), rng(),
                           target.extension().string());
  try {
    write(temporary.string());
  } catch (...) {
    fs::remove(temporary, ec);
    throw;
  }
  if (!fs::exists(temporary, ec))
    throw InternalError(fmt::format("{}: the writer produced no file", path));
  fs::rename(temporary, target, ec);
  if (ec) {
    fs::remove(temporary, ec);
    throw InputError(fmt::format("{}: cannot write: {}", path, ec.message()));
  }
}

void write_text(const std::string& path, const std::string& text) {
  write_atomically(path, [&](const std::string& temporary) {
    std::ofstream out(temporary, std::ios::binary);
    out << text;
    if (!out.flush()) throw InputError(fmt::format("{}: write failed", path));
  });
}

std::string read_file(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw InputError(fmt::format("{}: is a folder, not a file", path));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open: {}", path, std::strerror(errno)));
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) throw InputError(fmt::format("{}: cannot read its size", path));
  std::string bytes(static_cast<size_t>(size), '\0');
  in.seekg(0);
  in.read(bytes.data(), size);
  if (!in) throw InputError(fmt::format("{}: read failed after {} bytes", path, in.gcount()));
  return bytes;
}

bool is_file_name_safe(const std::string& name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
  });
}

}  // namespace vesselmesh::io
