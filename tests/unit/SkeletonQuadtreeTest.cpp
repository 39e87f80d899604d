// The block quadtree in skeleton.bin (since format version 6): it round-trips, and forged or
// corrupt quadtree bytes are an error with a message, never a crash, and never a tree that would
// hide a root from the selectors.
#include <gtest/gtest.h>

#include <cstring>
#include <optional>
#include <set>
#include <tuple>

#include "RuntimeTestScene.h"
#include "StoreBytes.h"
#include "hlod/builder/HlodBuilder.h"
#include "hlod/store/NodeStore.h"

using namespace hlod;
using hlod::test::fixChecksum;

namespace {

Skeleton anchoredCity() {
  test::SyntheticCity c;
  c.blocksX = 6;
  c.blocksY = 5;
  c.depth = 1;
  Skeleton s = test::makeSyntheticCity(c);
  s.params.simplifier = "meshopt";
  const EnuFrame frame(LatLon{51.91, 4.45, 0.0});
  std::vector<std::optional<LatLon>> anchors;
  for (std::uint32_t r : s.roots) anchors.push_back(frame.toGeodetic(s.nodes[r].bounds.centre()));
  s.quadtree = quadtreeOfRoots(s, anchors);
  return s;
}

StoreFacts factsOf(const Skeleton& s) {
  StoreFacts f;
  f.blockCount = std::uint32_t(s.roots.size());
  for (const NodeInfo& n : s.nodes)
    f.payloadBytes = std::max(f.payloadBytes, n.payloadOffset + n.payloadSize);
  return f;
}

// Where the quadtree section starts: its size counted back from the checksum.
std::size_t quadtreeOffset(const std::vector<std::byte>& bytes, const BlockQuadtree& q) {
  return bytes.size() - 8 - (4 + 4 * 8 + 3 * 4 + q.cells.size() * 76 + q.blocks.size() * 20);
}

// What a decoded quadtree promises the culling: every root once, in its anchor's leaf cell.
void expectEveryRootOnce(const Skeleton& s) {
  if (s.quadtree.empty()) return;
  std::multiset<std::uint32_t> listed;
  for (const QuadCell& c : s.quadtree.cells)
    for (std::uint32_t k = c.firstBlock; k < c.firstBlock + c.blockCount; ++k)
      listed.insert(s.quadtree.blocks[k].root);
  EXPECT_EQ(listed, std::multiset<std::uint32_t>(s.roots.begin(), s.roots.end()));
}

}  // namespace

TEST(SkeletonQuadtree, TheQuadtreeRoundTrips) {
  const Skeleton s = anchoredCity();
  ASSERT_EQ(s.quadtree.domain, QuadtreeDomain::Geographic);
  auto d = decodeSkeleton(encodeSkeleton(s, factsOf(s)));
  ASSERT_TRUE(d.ok()) << d.message();
  const BlockQuadtree& q = d->skeleton.quadtree;
  EXPECT_EQ(q.domain, s.quadtree.domain);
  EXPECT_EQ(q.rect, kWholeGlobe);
  EXPECT_EQ(q.depth, s.quadtree.depth);
  ASSERT_EQ(q.cells.size(), s.quadtree.cells.size());
  ASSERT_EQ(q.blocks.size(), 30u);
  for (std::size_t i = 0; i < q.cells.size(); ++i) {
    const QuadCell &a = q.cells[i], &b = s.quadtree.cells[i];
    EXPECT_EQ(std::tie(a.level, a.x, a.y, a.firstChild, a.childCount, a.firstBlock, a.blockCount),
              std::tie(b.level, b.x, b.y, b.firstChild, b.childCount, b.firstBlock, b.blockCount));
    EXPECT_EQ(a.bounds.min, b.bounds.min);
    EXPECT_EQ(a.bounds.max, b.bounds.max);
  }
  for (std::size_t i = 0; i < q.blocks.size(); ++i) {
    EXPECT_EQ(q.blocks[i].root, s.quadtree.blocks[i].root);
    EXPECT_EQ(q.blocks[i].anchor, s.quadtree.blocks[i].anchor);
  }
  // Without a quadtree (a hand-made skeleton) too.
  Skeleton bare = s;
  bare.quadtree = {};
  auto e = decodeSkeleton(encodeSkeleton(bare, factsOf(bare)));
  ASSERT_TRUE(e.ok()) << e.message();
  EXPECT_TRUE(e->skeleton.quadtree.empty());
}

TEST(SkeletonQuadtree, EveryCorruptByteOfTheQuadtreeIsAnErrorOrATreeThatHidesNoRoot) {
  const Skeleton s = anchoredCity();
  const std::vector<std::byte> good = encodeSkeleton(s, factsOf(s));
  const std::size_t start = quadtreeOffset(good, s.quadtree);
  std::size_t errors = 0, cases = 0;
  for (std::size_t at = start; at + 8 < good.size(); ++at)
    for (unsigned flip : {0x01u, 0x10u, 0x80u, 0xffu}) {
      std::vector<std::byte> bad = good;
      bad[at] ^= std::byte(flip);
      fixChecksum(bad);
      ++cases;
      auto d = decodeSkeleton(bad);
      if (!d.ok()) {
        ++errors;
        EXPECT_NE(d.message().find("corrupt skeleton.bin"), std::string::npos) << d.message();
        continue;
      }
      expectEveryRootOnce(d->skeleton);  // e.g. a box grown, an anchor moved within its cell
    }
  EXPECT_GT(errors, cases / 2);
  // Cut short anywhere in the quadtree: an error.
  for (std::size_t n = start; n + 8 < good.size(); n += 7) {
    std::vector<std::byte> cut(good.begin(), good.begin() + std::ptrdiff_t(n));
    cut.resize(n + 8);
    fixChecksum(cut);
    EXPECT_FALSE(decodeSkeleton(cut).ok()) << n;
  }
}

TEST(SkeletonQuadtree, ForgedTreesAreRefusedWithTheirReason) {
  const Skeleton good = anchoredCity();
  auto refused = [&](const Skeleton& s, const std::string& why) {
    auto d = decodeSkeleton(encodeSkeleton(s, factsOf(s)));
    ASSERT_FALSE(d.ok()) << why;
    EXPECT_NE(d.message().find(why), std::string::npos) << d.message();
  };
  {
    Skeleton s = good;  // an anchor moved to another cell
    s.quadtree.blocks[0].anchor.x += 1.0;
    refused(s, "is not in its anchor's cell");
  }
  {
    Skeleton s = good;  // a leaf's box too small for its block
    for (QuadCell& c : s.quadtree.cells)
      if (c.blockCount > 0) {
        c.bounds.max.z -= 1.0;
        break;
      }
    refused(s, "box misses a block's");
  }
  {
    Skeleton s = good;  // one root listed twice, another never
    s.quadtree.blocks[1].root = s.quadtree.blocks[0].root;
    refused(s, "");
  }
  {
    Skeleton s = good;  // a block that is not a root
    s.quadtree.blocks[0].root = s.nodes[s.roots[0]].firstChild;
    refused(s, "");
  }
  {
    Skeleton s = good;  // the globe's quadtree not over the globe
    s.quadtree.rect.maxU = 170.0;
    refused(s, "does not cover the globe");
  }
  {
    Skeleton s = good;  // too deep
    s.quadtree.depth = 31;
    refused(s, "deeper than 30");
  }
  {
    Skeleton s = good;  // roots out of order
    std::swap(s.roots[0], s.roots[1]);
    refused(s, "ascending");
  }
}
