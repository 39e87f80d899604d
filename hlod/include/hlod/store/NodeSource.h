#pragma once
// Where node payloads come from: the node store on disk, or an in-memory source in tests.
// The loader thread reads a payload a chunk at a time (so a load can be pre-empted), then
// decodes it. Implementations must allow readPayloadChunk from a thread other than the creator's.
#include <cstddef>
#include <cstdint>
#include <span>

#include "hlod/Mesh.h"
#include "hlod/Result.h"
#include "hlod/store/Skeleton.h"

namespace hlod {

class NodeSource {
 public:
  virtual ~NodeSource() = default;

  virtual const Skeleton& skeleton() const = 0;

  // Reads bytes [offset, offset + out.size()) of node's payload. Bounds-checked: a range outside
  // the payload, or outside the file, is an Error.
  virtual Status readPayloadChunk(std::uint32_t node, std::uint64_t offset,
                                  std::span<std::byte> out) const = 0;

  // Verifies the checksum of a whole payload and decodes it. A corrupt payload is an Error.
  virtual Result<LocalMesh> decodePayload(std::uint32_t node,
                                          std::span<const std::byte> bytes) const = 0;
};

}  // namespace hlod
