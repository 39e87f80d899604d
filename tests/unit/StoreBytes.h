// Test helpers that forge store files byte by byte.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "store/ByteIO.h"

namespace hlod::test {

// Rewrites the trailing FNV-1a 64 so that a forged field gets past the checksum.
inline void fixChecksum(std::vector<std::byte>& bytes) {
  const std::uint64_t h = store::fnv1a64(std::span<const std::byte>(bytes).first(bytes.size() - 8));
  std::memcpy(bytes.data() + bytes.size() - 8, &h, 8);
}

}  // namespace hlod::test
