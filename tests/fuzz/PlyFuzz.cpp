// PLY (ascii and binary): the input is the whole file, read as model.ply.
#include "ImportFuzz.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::importAndCheck("ply", fuzz::view(data, size));
  return 0;
}
