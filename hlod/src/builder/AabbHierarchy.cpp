// Stage 4 of Manocha sec. 2.2: the AABB hierarchy over the redefined objects
// (builder/AabbHierarchy.h).
#include "builder/AabbHierarchy.h"

#include <algorithm>
#include <cassert>
#include <numeric>

namespace hlod {

namespace {

std::uint64_t trianglesOf(std::span<const PartitionItem> items,
                          const std::vector<std::uint32_t>& group) {
  std::uint64_t t = 0;
  for (std::uint32_t i : group) t += items[i].triangles;
  return t;
}

// The node's objects in up to fanOut groups: the heaviest group that splits is split next.
std::vector<std::vector<std::uint32_t>> divide(std::span<const PartitionItem> items,
                                               std::vector<std::uint32_t> group, int fanOut) {
  std::vector<std::vector<std::uint32_t>> groups;
  groups.push_back(std::move(group));
  std::vector<bool> whole(1, false);  // tried and found unsplittable
  while (int(groups.size()) < fanOut) {
    std::size_t pick = groups.size();
    for (std::size_t g = 0; g < groups.size(); ++g)
      if (!whole[g] && groups[g].size() > 1 &&
          (pick == groups.size() ||
           trianglesOf(items, groups[g]) > trianglesOf(items, groups[pick])))
        pick = g;
    if (pick == groups.size()) break;
    std::optional<Split> s = splitInTwo(items, groups[pick], SplitAt::Median);
    if (!s) {
      whole[pick] = true;
      continue;
    }
    // The halves take the place of the group, in order, so that siblings stay in space order.
    groups[pick] = std::move(s->lower);
    groups.insert(groups.begin() + std::ptrdiff_t(pick) + 1, std::move(s->upper));
    whole.insert(whole.begin() + std::ptrdiff_t(pick) + 1, false);
  }
  return groups;
}

}  // namespace

std::vector<AabbNode> buildAabbHierarchy(std::span<const PartitionItem> objects, int fanOut) {
  assert(fanOut >= 2);
  std::vector<AabbNode> nodes;
  if (objects.empty()) return nodes;
  std::vector<std::vector<std::uint32_t>> members;  // per node, until it is divided
  std::vector<std::uint32_t> all(objects.size());
  std::iota(all.begin(), all.end(), 0u);
  nodes.emplace_back();
  members.push_back(std::move(all));
  // Breadth-first: nodes[] grows level by level, children appended together.
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    std::vector<std::uint32_t> group = std::move(members[n]);
    members[n] = {};
    nodes[n].box = boxOf(objects, group);
    nodes[n].triangles = trianglesOf(objects, group);
    std::vector<std::vector<std::uint32_t>> children;
    if (group.size() > 1) children = divide(objects, group, fanOut);
    if (children.size() < 2) {
      if (group.size() == 1) {
        nodes[n].object = group.front();
        continue;
      }
      // Objects whose centres all coincide: no plane parts them, so fanOut runs of them.
      children.assign(std::size_t(std::min<std::size_t>(group.size(), std::size_t(fanOut))), {});
      for (std::size_t k = 0; k < group.size(); ++k)
        children[k * children.size() / group.size()].push_back(group[k]);
    }
    nodes[n].firstChild = std::uint32_t(nodes.size());
    nodes[n].childCount = std::uint32_t(children.size());
    for (auto& c : children) {
      AabbNode child;
      child.parent = std::uint32_t(n);
      child.level = nodes[n].level + 1;
      nodes.push_back(child);
      members.push_back(std::move(c));
    }
  }
  return nodes;
}

}  // namespace hlod
