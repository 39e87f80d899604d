// OFF: the input is the whole file, read as model.off.
#include "ImportFuzz.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::importAndCheck("off", fuzz::view(data, size));
  return 0;
}
