// The occlusion-switch's visible-set deltas and messages (Manocha sec. 4.4-4.5).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "hlod/runtime/VisibleSetDelta.h"

namespace {

using hlod::VisibleSetDelta;

std::vector<std::uint32_t> randomSet(std::mt19937& rng, std::uint32_t nodes, double share) {
  std::vector<std::uint32_t> out;
  std::bernoulli_distribution in(share);
  for (std::uint32_t n = 0; n < nodes; ++n)
    if (in(rng)) out.push_back(n);
  return out;
}

}  // namespace

// V_i = (V_{i-1} - delta_{i-1,i}) U delta_{i,i-1}, over a sequence of sets as a receiver sees
// them, starting from the empty set.
TEST(VisibleSetDelta, TheReceiverRebuildsEverySetFromTheDeltas) {
  std::mt19937 rng(7);
  std::vector<std::uint32_t> sent, received;
  for (int frame = 0; frame < 200; ++frame) {
    const auto now = randomSet(rng, 300, frame % 3 == 0 ? 0.2 : 0.5);
    const VisibleSetDelta d = hlod::visibleSetDelta(sent, now);
    for (std::uint32_t n : d.added) EXPECT_FALSE(std::binary_search(sent.begin(), sent.end(), n));
    for (std::uint32_t n : d.removed) EXPECT_FALSE(std::binary_search(now.begin(), now.end(), n));
    auto rebuilt = hlod::applyVisibleSetDelta(received, d);
    ASSERT_TRUE(rebuilt) << rebuilt.message();
    ASSERT_EQ(*rebuilt, now) << "frame " << frame;
    received = std::move(*rebuilt);
    sent = now;
  }
  // An unchanged set costs nothing.
  EXPECT_EQ(hlod::visibleSetDelta(sent, sent).size(), 0u);
}

TEST(VisibleSetDelta, ADeltaThatDoesNotFitTheSetIsAnError) {
  const std::vector<std::uint32_t> v = {1, 4, 9};
  VisibleSetDelta removesAbsent;
  removesAbsent.removed = {5};
  EXPECT_FALSE(hlod::applyVisibleSetDelta(v, removesAbsent));
  VisibleSetDelta addsPresent;
  addsPresent.added = {4};
  EXPECT_FALSE(hlod::applyVisibleSetDelta(v, addsPresent));
  VisibleSetDelta unordered;
  unordered.added = {7, 2};
  EXPECT_FALSE(hlod::applyVisibleSetDelta(v, unordered));
  VisibleSetDelta fine;
  fine.added = {2, 7};
  fine.removed = {4};
  auto r = hlod::applyVisibleSetDelta(v, fine);
  ASSERT_TRUE(r);
  EXPECT_EQ(*r, (std::vector<std::uint32_t>{1, 2, 7, 9}));
}

TEST(SwitchMessage, EncodesAndDecodesWithTheCameraAndTheIds) {
  hlod::SwitchMessage m;
  m.frame = 41;
  m.camera = {1.5, -2.0, 3.25, 0.0, 1e6, -7.0, 0.0, 0.0, 1.0};
  m.delta.added = {3, 8, 1000};
  m.delta.removed = {0, 5};
  const auto bytes = hlod::encodeSwitchMessage(m);
  EXPECT_EQ(bytes.size(), hlod::kSwitchHeaderBytes + hlod::kSwitchCameraBytes + 4 * 5);
  auto body = hlod::switchBodyBytes(bytes);
  ASSERT_TRUE(body);
  EXPECT_EQ(*body, bytes.size() - hlod::kSwitchHeaderBytes);
  auto back = hlod::decodeSwitchMessage(bytes, 1001);
  ASSERT_TRUE(back) << back.message();
  EXPECT_EQ(back->frame, 41u);
  EXPECT_EQ(back->camera, m.camera);
  EXPECT_EQ(back->delta.added, m.delta.added);
  EXPECT_EQ(back->delta.removed, m.delta.removed);
}

TEST(SwitchMessage, ABrokenMessageIsRefused) {
  hlod::SwitchMessage m;
  m.delta.added = {2, 6};
  const auto good = hlod::encodeSwitchMessage(m);
  ASSERT_TRUE(hlod::decodeSwitchMessage(good, 7));
  // An id the store does not have.
  EXPECT_FALSE(hlod::decodeSwitchMessage(good, 6));
  // Truncated, and one byte too many.
  EXPECT_FALSE(hlod::decodeSwitchMessage(std::span(good).first(good.size() - 1), 7));
  auto longer = good;
  longer.push_back(std::byte{0});
  EXPECT_FALSE(hlod::decodeSwitchMessage(longer, 7));
  // Not a message: the magic.
  auto magic = good;
  magic[0] = std::byte{'X'};
  EXPECT_FALSE(hlod::switchBodyBytes(magic));
  // Counts that do not match the length.
  auto counts = good;
  counts[8] = std::byte{3};
  EXPECT_FALSE(hlod::switchBodyBytes(counts));
  // Absurd counts are refused before anything is allocated.
  auto absurd = good;
  absurd[11] = std::byte{0x7f};
  EXPECT_FALSE(hlod::switchBodyBytes(absurd));
  // Ids out of order.
  hlod::SwitchMessage unordered;
  unordered.delta.added = {6, 2};
  EXPECT_FALSE(hlod::decodeSwitchMessage(hlod::encodeSwitchMessage(unordered), 7));
  // A node both added and removed (found by the fuzz target: it rebuilt a set that kept a node
  // the delta removes).
  hlod::SwitchMessage both;
  both.delta.added = {2, 3};
  both.delta.removed = {3};
  EXPECT_FALSE(hlod::decodeSwitchMessage(hlod::encodeSwitchMessage(both), 7));
  EXPECT_FALSE(hlod::applyVisibleSetDelta(std::vector<std::uint32_t>{3}, both.delta));
}

// Sec. 4.5: 8n + nh/b + 3(72 + h).
TEST(SwitchMessage, TheBandwidthFormulaIsThePapers) {
  EXPECT_DOUBLE_EQ(hlod::switchBandwidthBytes(100, 20, 100), 800 + 20 + 3 * 92);
  EXPECT_DOUBLE_EQ(hlod::switchBandwidthBytes(1000, 40, 50), 8000 + 800 + 3 * 112);
  EXPECT_DOUBLE_EQ(hlod::switchBandwidthBytes(0, 20, 1), 3 * 92);
}
