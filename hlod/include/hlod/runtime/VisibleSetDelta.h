#pragma once
// The occlusion-switch's messages (Manocha, "Interactive Display of Complex Environments",
// shared/seeds, sec. 4.4-4.5): the process doing hardware culling (HC) sends the change of the
// potential visible set, not the set, to the one rendering occluders (OR) and the one rendering
// the visible geometry (RVG). With delta_{j,k} = V_j - V_k, during frame i HC sends delta_{i,i-1}
// (nodes that became visible) and delta_{i-1,i} (nodes no longer visible), and each receiver
// rebuilds
//     V_i = (V_{i-1} - delta_{i-1,i}) U delta_{i,i-1}.
// Node ids are the store's: every process reads the same store, so an id names the same node
// everywhere (sec. 4.5: 4 bytes per node instead of its triangles). Pure: no sockets, no GL.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "hlod/Result.h"

namespace hlod {

// Sets are sorted vectors of node ids without repeats.
struct VisibleSetDelta {
  std::vector<std::uint32_t> added;    // delta_{i,i-1}: in V_i, not in V_{i-1}
  std::vector<std::uint32_t> removed;  // delta_{i-1,i}: in V_{i-1}, not in V_i
  std::size_t size() const { return added.size() + removed.size(); }
};

// delta between the previous set and the current one (both sorted, without repeats).
VisibleSetDelta visibleSetDelta(std::span<const std::uint32_t> previous,
                                std::span<const std::uint32_t> current);
// V_i from V_{i-1} and the delta. An Error where the delta does not fit the set (a removed node
// that is not in it, an added one that is, one both added and removed, or ids out of order): the
// sender and the receiver disagree, and going on would draw the wrong nodes.
Result<std::vector<std::uint32_t>> applyVisibleSetDelta(std::span<const std::uint32_t> previous,
                                                        const VisibleSetDelta& delta);

// One HC message: the frame, its camera (sec. 4.5's 72 bytes: position, target and up as nine
// doubles) and the delta. Wire format, little-endian: the header (kSwitchHeaderBytes: magic
// "HLOS", frame, the counts of added and removed ids, the byte count that follows), the camera,
// then the added ids and the removed ids, 4 bytes each.
struct SwitchMessage {
  std::uint32_t frame = 0;
  std::array<double, 9> camera{};
  VisibleSetDelta delta;
};
inline constexpr std::size_t kSwitchHeaderBytes = 20;
inline constexpr std::size_t kSwitchCameraBytes = 72;
// The most ids one message may carry (a store has fewer nodes than this).
inline constexpr std::uint32_t kSwitchMaxIds = 1u << 26;

std::vector<std::byte> encodeSwitchMessage(const SwitchMessage& message);
// The length of the body that follows a header (an Error for a header that is not one).
Result<std::size_t> switchBodyBytes(std::span<const std::byte> header);
// A whole message (header and body). Checked: the magic, the counts against the length, ids
// below nodeCount and sorted.
Result<SwitchMessage> decodeSwitchMessage(std::span<const std::byte> bytes,
                                          std::uint32_t nodeCount);

// Sec. 4.5: the bytes per frame for n node ids sent, headers of h bytes, b ids per packet:
// 8n + nh/b + 3(72 + h).
double switchBandwidthBytes(double n, double h, double b);

}  // namespace hlod
