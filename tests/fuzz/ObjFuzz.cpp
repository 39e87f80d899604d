// OBJ with its MTL: the input is the OBJ text, then optionally a line "@@MTL@@" and the text of
// model.mtl (which the seeds' OBJ names with `mtllib model.mtl`).
#include "ImportFuzz.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto parts = fuzz::splitAt(fuzz::view(data, size), "\n@@MTL@@\n");
  fuzz::importAndCheck("obj", parts.first, "model.mtl", parts.second, parts.found);
  return 0;
}
