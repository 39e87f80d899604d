// glTF (JSON): the input is the .gltf text, then optionally a line "@@BIN@@" and the bytes of
// model.bin, the external buffer the seeds' JSON names by URI.
#include "ImportFuzz.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto parts = fuzz::splitAt(fuzz::view(data, size), "\n@@BIN@@\n");
  fuzz::importAndCheck("gltf", parts.first, "model.bin", parts.second, parts.found);
  return 0;
}
