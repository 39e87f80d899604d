// The occlusion-switch's visible-set deltas (Manocha sec. 4.4-4.5). See
// hlod/runtime/VisibleSetDelta.h.
#include "hlod/runtime/VisibleSetDelta.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cstring>
#include <iterator>
#include <string>

namespace hlod {

namespace {

constexpr std::uint32_t kMagic = 0x534f4c48;  // "HLOS" little-endian

void putU32(std::vector<std::byte>& out, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) out.push_back(std::byte((v >> (8 * k)) & 0xff));
}

std::uint32_t getU32(std::span<const std::byte> in, std::size_t at) {
  std::uint32_t v = 0;
  for (int k = 0; k < 4; ++k) v |= std::uint32_t(in[at + k]) << (8 * k);
  return v;
}

bool sortedUnique(std::span<const std::uint32_t> ids) {
  return std::adjacent_find(ids.begin(), ids.end(), std::greater_equal<>()) == ids.end();
}

// delta_{i,i-1} and delta_{i-1,i} are disjoint by definition; both sorted.
bool disjoint(std::span<const std::uint32_t> a, std::span<const std::uint32_t> b) {
  for (auto i = a.begin(), j = b.begin(); i != a.end() && j != b.end();) {
    if (*i == *j) return false;
    *i < *j ? ++i : ++j;
  }
  return true;
}

}  // namespace

VisibleSetDelta visibleSetDelta(std::span<const std::uint32_t> previous,
                                std::span<const std::uint32_t> current) {
  assert(sortedUnique(previous) && sortedUnique(current));
  VisibleSetDelta d;
  std::set_difference(current.begin(), current.end(), previous.begin(), previous.end(),
                      std::back_inserter(d.added));
  std::set_difference(previous.begin(), previous.end(), current.begin(), current.end(),
                      std::back_inserter(d.removed));
  return d;
}

Result<std::vector<std::uint32_t>> applyVisibleSetDelta(std::span<const std::uint32_t> previous,
                                                        const VisibleSetDelta& delta) {
  if (!sortedUnique(delta.added) || !sortedUnique(delta.removed))
    return makeError("visible-set delta: ids out of order or repeated");
  if (!disjoint(delta.added, delta.removed))
    return makeError("visible-set delta: adds and removes the same node");
  std::vector<std::uint32_t> kept;
  kept.reserve(previous.size());
  std::set_difference(previous.begin(), previous.end(), delta.removed.begin(), delta.removed.end(),
                      std::back_inserter(kept));
  if (kept.size() + delta.removed.size() != previous.size())
    return makeError("visible-set delta: removes a node that is not in the set");
  std::vector<std::uint32_t> out;
  out.reserve(kept.size() + delta.added.size());
  std::set_union(kept.begin(), kept.end(), delta.added.begin(), delta.added.end(),
                 std::back_inserter(out));
  if (out.size() != kept.size() + delta.added.size())
    return makeError("visible-set delta: adds a node that is in the set already");
  return out;
}

std::vector<std::byte> encodeSwitchMessage(const SwitchMessage& m) {
  std::vector<std::byte> out;
  const std::size_t body = kSwitchCameraBytes + 4 * m.delta.size();
  out.reserve(kSwitchHeaderBytes + body);
  putU32(out, kMagic);
  putU32(out, m.frame);
  putU32(out, std::uint32_t(m.delta.added.size()));
  putU32(out, std::uint32_t(m.delta.removed.size()));
  putU32(out, std::uint32_t(body));
  for (double v : m.camera) {
    const auto bits = std::bit_cast<std::uint64_t>(v);
    putU32(out, std::uint32_t(bits));
    putU32(out, std::uint32_t(bits >> 32));
  }
  for (std::uint32_t id : m.delta.added) putU32(out, id);
  for (std::uint32_t id : m.delta.removed) putU32(out, id);
  return out;
}

Result<std::size_t> switchBodyBytes(std::span<const std::byte> header) {
  if (header.size() < kSwitchHeaderBytes) return makeError("switch message: short header");
  if (getU32(header, 0) != kMagic) return makeError("switch message: bad magic");
  const std::uint64_t added = getU32(header, 8), removed = getU32(header, 12);
  if (added > kSwitchMaxIds || removed > kSwitchMaxIds)
    return makeError("switch message: too many ids");
  const std::uint64_t body = getU32(header, 16);
  if (body != kSwitchCameraBytes + 4 * (added + removed))
    return makeError("switch message: length does not match its counts");
  return std::size_t(body);
}

Result<SwitchMessage> decodeSwitchMessage(std::span<const std::byte> bytes,
                                          std::uint32_t nodeCount) {
  auto body = switchBodyBytes(bytes);
  if (!body) return body.error();
  if (bytes.size() != kSwitchHeaderBytes + *body)
    return makeError("switch message: " + std::to_string(bytes.size()) + " bytes, expected " +
                     std::to_string(kSwitchHeaderBytes + *body));
  SwitchMessage m;
  m.frame = getU32(bytes, 4);
  std::size_t at = kSwitchHeaderBytes;
  for (double& v : m.camera) {
    const std::uint64_t bits =
        std::uint64_t(getU32(bytes, at)) | std::uint64_t(getU32(bytes, at + 4)) << 32;
    v = std::bit_cast<double>(bits);
    at += 8;
  }
  const std::uint32_t added = getU32(bytes, 8), removed = getU32(bytes, 12);
  for (std::uint32_t k = 0; k < added + removed; ++k, at += 4) {
    const std::uint32_t id = getU32(bytes, at);
    if (id >= nodeCount)
      return makeError("switch message: node " + std::to_string(id) + " is not in the store");
    (k < added ? m.delta.added : m.delta.removed).push_back(id);
  }
  if (!sortedUnique(m.delta.added) || !sortedUnique(m.delta.removed))
    return makeError("switch message: ids out of order or repeated");
  if (!disjoint(m.delta.added, m.delta.removed))
    return makeError("switch message: adds and removes the same node");
  return m;
}

double switchBandwidthBytes(double n, double h, double b) {
  return 8.0 * n + (b > 0.0 ? n * h / b : 0.0) + 3.0 * (72.0 + h);
}

}  // namespace hlod
