// A node payload, both as payload.bin stores it and as it is decoded: the input is inflated
// (raw DEFLATE, for a decoded size named by its first 4 bytes, at most 1 MiB) and the result
// decoded, and the input itself is decoded as an uncompressed payload. A decoded mesh must be
// what decodePayloadBytes promises: finite values, indices in range.
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "FuzzSupport.h"
#include "hlod/store/NodeStore.h"

namespace {

void decodeAndCheck(std::span<const std::byte> bytes) {
  auto mesh = hlod::decodePayloadBytes(bytes, glm::dvec3(1.0, -2.0, 3.0));
  fuzz::report("decodePayloadBytes", mesh);
  if (!mesh.ok()) return;
  if (mesh->indices.size() % 3 != 0 || mesh->normals.size() != mesh->positions.size()) std::abort();
  for (auto i : mesh->indices)
    if (i >= mesh->positions.size()) std::abort();
  for (const auto& p : mesh->positions)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) std::abort();
  if (mesh->texture &&
      mesh->texture->pixels.size() != std::size_t(mesh->texture->width) * mesh->texture->height * 4)
    std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::byte> input(reinterpret_cast<const std::byte*>(data), size);
  decodeAndCheck(input);
  if (size >= 4) {
    std::uint32_t memoryBytes = 0;
    std::memcpy(&memoryBytes, data, 4);
    memoryBytes &= (1u << 20) - 1;
    auto raw = hlod::inflatePayload(input.subspan(4), memoryBytes);
    fuzz::report("inflatePayload", raw);
    if (raw.ok()) {
      if (raw->size() != memoryBytes) std::abort();
      decodeAndCheck(*raw);
    }
  }
  return 0;
}
