#include "io/hdf5_file.h"

#include "mesh/error.h"

#include <fmt/format.h>
#include <hdf5.h>

#include <cstdio>
#include <filesystem>
#include <functional>

namespace vesselmesh::io {
namespace {

// HDF5's innermost message of its error stack (its default printing turned off).
std::string hdf5_message() {
  std::string message;
  const auto walk = [](unsigned, const H5E_error2_t* e, void* data) -> herr_t {
    if (e && e->desc) *static_cast<std::string*>(data) = e->desc;
    return 0;
  };
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, walk, &message);
  return message.empty() ? "no reason given" : message;
}

// Closes an HDF5 handle at scope's end.
struct Handle {
  hid_t id;
  std::function<herr_t(hid_t)> close;
  ~Handle() {
    if (id >= 0) close(id);
  }
};

}  // namespace

void write_hdf5(const std::string& path, const std::vector<Hdf5Dataset>& datasets) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const std::string part = path + ".part";
  const auto fail = [&](const std::string& what) {
    const std::string why = hdf5_message();
    std::remove(part.c_str());
    throw InputError(fmt::format("{}: cannot write the HDF5 file ({}: {})", path, what, why));
  };
  {
    Handle file{H5Fcreate(part.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose};
    if (file.id < 0) fail("creating it");
    Handle links{H5Pcreate(H5P_LINK_CREATE), H5Pclose};
    H5Pset_create_intermediate_group(links.id, 1);
    for (const Hdf5Dataset& d : datasets) {
      uint64_t count = 1;
      std::vector<hsize_t> dims(d.dims.begin(), d.dims.end());
      for (hsize_t n : dims) count *= n;
      VM_CHECK(count == (d.is_integer ? d.integer.size() : d.real.size()), "an HDF5 dataset's values fill it");
      Handle space{H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose};
      Handle set{H5Dcreate2(file.id, d.name.c_str(), d.is_integer ? H5T_STD_I64LE : H5T_IEEE_F64LE, space.id,
                            links.id, H5P_DEFAULT, H5P_DEFAULT),
                 H5Dclose};
      if (set.id < 0) fail("creating " + d.name);
      const herr_t written =
          d.is_integer ? H5Dwrite(set.id, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, d.integer.data())
                       : H5Dwrite(set.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, d.real.data());
      if (written < 0) fail("writing " + d.name);
    }
    if (H5Fflush(file.id, H5F_SCOPE_GLOBAL) < 0) fail("flushing it");
  }
  std::error_code ec;
  std::filesystem::rename(part, path, ec);
  if (ec) {
    std::remove(part.c_str());
    throw InputError(fmt::format("{}: cannot write the HDF5 file: {}", path, ec.message()));
  }
}

}  // namespace vesselmesh::io
