// What the skeleton answers about its own tree (hlod/store/Skeleton.h).
#include "hlod/store/Skeleton.h"

namespace hlod {

std::vector<std::uint32_t> Skeleton::blockRoots() const {
  if (!hasCells()) return roots;
  std::vector<std::uint32_t> out;
  for (std::uint32_t i = 0; i < nodes.size(); ++i)
    if (!nodes[i].isCell() && nodes[i].level == 0) out.push_back(i);
  return out;
}

}  // namespace hlod
