// The occlusion-switch's messages (hlod/runtime/VisibleSetDelta.h) as a process reads them off
// its socket: the input is the bytes. A message that decodes must encode back to the same bytes,
// and its delta, applied to a set it does not fit, must be an Error, never a crash.
#include <algorithm>
#include <cstdlib>
#include <vector>

#include "FuzzSupport.h"
#include "hlod/runtime/VisibleSetDelta.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::byte> bytes(reinterpret_cast<const std::byte*>(data), size);
  auto body = hlod::switchBodyBytes(bytes);
  fuzz::report("switchBodyBytes", body);
  auto m = hlod::decodeSwitchMessage(bytes, 1u << 16);
  fuzz::report("decodeSwitchMessage", m);
  if (!m.ok()) return 0;
  if (!body.ok() ||
      hlod::encodeSwitchMessage(*m) != std::vector<std::byte>(bytes.begin(), bytes.end()))
    std::abort();
  // Applied to the set of its removed ids, the delta must give back a set without them.
  auto v = hlod::applyVisibleSetDelta(m->delta.removed, m->delta);
  fuzz::report("applyVisibleSetDelta", v);
  if (v.ok())
    for (std::uint32_t id : m->delta.removed)
      if (std::binary_search(v->begin(), v->end(), id)) std::abort();
  return 0;
}
