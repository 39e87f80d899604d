// GLB (binary glTF, buffers inside): the input is the whole file, read as model.glb.
#include "ImportFuzz.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::importAndCheck("glb", fuzz::view(data, size));
  return 0;
}
