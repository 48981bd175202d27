// libFuzzer target: the STL reader, then the mesh doctor (see fuzz_targets.h and the README).
//   build-fuzz/tests/fuzz/fuzz_stl_reader tests/fuzz/corpus/stl
#include "fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return vesselmesh::fuzz::read_surface_bytes(vesselmesh::fuzz::Reader::stl, data, size);
}
