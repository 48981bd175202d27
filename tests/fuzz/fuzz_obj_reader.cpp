// libFuzzer target: the OBJ reader, then the mesh doctor (see fuzz_targets.h and the README).
//   build-fuzz/tests/fuzz/fuzz_obj_reader tests/fuzz/corpus/obj
#include "fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return vesselmesh::fuzz::read_surface_bytes(vesselmesh::fuzz::Reader::obj, data, size);
}
