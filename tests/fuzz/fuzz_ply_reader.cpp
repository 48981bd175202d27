// libFuzzer target: the PLY reader, then the mesh doctor (see fuzz_targets.h and the README).
//   build-fuzz/tests/fuzz/fuzz_ply_reader tests/fuzz/corpus/ply
#include "fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return vesselmesh::fuzz::read_surface_bytes(vesselmesh::fuzz::Reader::ply, data, size);
}
