// The outer sides of a cell of blocks (builder/OuterSides.h).
#include "builder/OuterSides.h"

#include <algorithm>
#include <cassert>

namespace hlod {

std::vector<CutPlane> outerSides(std::span<const Aabb> boxes,
                                 std::span<const std::vector<CutPlane>> sides, UpAxis up) {
  assert(boxes.size() == sides.size());
  const int vertical = int(up);
  std::vector<CutPlane> out;
  for (std::size_t k = 0; k < boxes.size(); ++k)
    for (const CutPlane& c : sides[k]) {
      const int along = 3 - c.axis - vertical;  // the horizontal axis the plane runs along
      const bool below = boxes[k].centre()[c.axis] < c.value;
      bool inner = false;
      for (std::size_t j = 0; j < boxes.size() && !inner; ++j) {
        if (j == k || (boxes[j].centre()[c.axis] < c.value) == below) continue;
        const double overlap = std::min(boxes[k].max[along], boxes[j].max[along]) -
                               std::max(boxes[k].min[along], boxes[j].min[along]);
        inner =
            overlap > 0.0 && std::any_of(sides[j].begin(), sides[j].end(), [&](const CutPlane& o) {
              return o.axis == c.axis && o.value == c.value;
            });
      }
      if (!inner && std::none_of(out.begin(), out.end(), [&](const CutPlane& o) {
            return o.axis == c.axis && o.value == c.value;
          }))
        out.push_back(c);
    }
  return out;
}

}  // namespace hlod
