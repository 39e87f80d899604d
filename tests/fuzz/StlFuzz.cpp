// STL (ascii and binary): the input is the whole file, read as model.stl.
#include "ImportFuzz.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::importAndCheck("stl", fuzz::view(data, size));
  return 0;
}
