// The block quadtree of a built skeleton (Parry sec. 3; see quadtreeOfRoots in
// hlod/builder/HlodBuilder.h).
#include <algorithm>
#include <cassert>
#include <map>

#include "hlod/builder/HlodBuilder.h"

namespace hlod {

namespace {

// The two horizontal axes of a model standing on `up`.
glm::ivec2 horizontalAxes(UpAxis up) {
  switch (up) {
    case UpAxis::X:
      return {1, 2};
    case UpAxis::Y:
      return {0, 2};
    default:
      return {0, 1};
  }
}

}  // namespace

BlockQuadtree quadtreeOfRoots(const Skeleton& s, std::span<const std::optional<LatLon>> anchors) {
  assert(anchors.size() == s.roots.size());
  const glm::ivec2 axes = horizontalAxes(s.up);
  const bool geographic =
      !anchors.empty() && std::all_of(anchors.begin(), anchors.end(),
                                      [](const std::optional<LatLon>& a) { return a.has_value(); });
  std::vector<QuadBlockInput> blocks;
  // A block: the roots that share an anchor (one block split by material or size).
  std::map<std::pair<double, double>, Aabb> blockBoxes;
  for (std::size_t i = 0; i < s.roots.size(); ++i) {
    const NodeInfo& root = s.nodes[s.roots[i]];
    QuadBlockInput b;
    b.root = s.roots[i];
    b.bounds = root.bounds;
    const glm::dvec3 c = root.bounds.centre();
    b.anchor = geographic ? glm::dvec2(wrapLongitude(anchors[i]->lon), anchors[i]->lat)
                          : glm::dvec2(c[axes.x], c[axes.y]);
    blockBoxes[{b.anchor.x, b.anchor.y}].extend(root.bounds);
    blocks.push_back(b);
  }
  // The median block's larger horizontal side: the size the smallest cells should have.
  std::vector<double> sides;
  for (const auto& [anchor, box] : blockBoxes) {
    const glm::dvec3 size = box.size();
    sides.push_back(std::max(size[axes.x], size[axes.y]));
  }
  double blockSize = 0.0;
  if (!sides.empty()) {
    std::nth_element(sides.begin(), sides.begin() + sides.size() / 2, sides.end());
    blockSize = sides[sides.size() / 2];
  }
  if (geographic)
    return buildBlockQuadtree(QuadtreeDomain::Geographic, kWholeGlobe,
                              quadtreeDepthFor(kHalfMeridianMetres, blockSize), blocks);
  const QuadRect rect = squareAround(blocks);
  return buildBlockQuadtree(QuadtreeDomain::Model, rect,
                            quadtreeDepthFor(rect.maxV - rect.minV, blockSize), blocks);
}

}  // namespace hlod
