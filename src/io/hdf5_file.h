// HDF5 files (the XDMF export's heavy data, io/export.h), written from one process with the HDF5
// library PETSc's build brings (Debian's hdf5-openmpi: one library in the process, as PETSc's).
// Built with PETSc's code (the program opens it with that module, modules/petsc_module.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace vesselmesh::io {

// A dataset: its path in the file ("/mesh/geometry"; the groups made as needed), its dimensions
// (row-major) and its values, real (64-bit floats) or integer (64-bit), as many as the dimensions'
// product.
struct Hdf5Dataset {
  std::string name;
  std::vector<uint64_t> dims;
  std::vector<double> real;
  std::vector<int64_t> integer;
  bool is_integer = false;
};

// Writes the datasets into a new file at `path` (whole or not at all: written beside it, then
// renamed). InputError naming the file when it cannot be written, with HDF5's own words.
void write_hdf5(const std::string& path, const std::vector<Hdf5Dataset>& datasets);

}  // namespace vesselmesh::io
