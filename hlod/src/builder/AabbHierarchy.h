#pragma once
// The AABB hierarchy, stage 4 of Manocha sec. 2.2: "Compute an AABB (axis-aligned bounding box)
// bounding volume hierarchy on the final redefined set of objects (top-down)". A node's objects
// are divided into up to fanOut children by repeated splits in two (splitInTwo at the median of
// their triangles, so that the tree is balanced, criterion 2 of sec. 2.1.1, along the axis whose
// halves overlap least, criterion 3), the group with the most triangles split first; a node of
// one object is a leaf. Private to the builder.
#include <cstdint>
#include <span>
#include <vector>

#include "builder/SplitAxis.h"

namespace hlod {

struct AabbNode {
  Aabb box;                            // of its objects' boxes
  std::uint32_t parent = 0xffffffffu;  // none for the root
  std::uint32_t firstChild = 0, childCount = 0;
  std::uint32_t level = 0;             // the root's is 0
  std::uint32_t object = 0xffffffffu;  // a leaf: its object (an index into the items)
  std::uint64_t triangles = 0;         // of its objects
};

// Nodes breadth-first from the root (node 0), each node's children contiguous and after it (the
// order the node store wants); children in the order of their splits (lower side first). Every
// item is the object of exactly one leaf. Empty for no items.
std::vector<AabbNode> buildAabbHierarchy(std::span<const PartitionItem> objects, int fanOut);

}  // namespace hlod
