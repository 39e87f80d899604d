#pragma once
// The boundary checks and the luma plane shared by the image metrics (private to metrics/).
#include <string_view>
#include <vector>

#include "hlod/Mesh.h"
#include "hlod/Result.h"

namespace hlod::metrics {

// Ok when image has a non-zero size and width * height * 4 bytes; else an Error naming metric.
Status checkImage(const Image& image, std::string_view metric, std::string_view role);

// Ok when both images are well-formed and of equal size; else an Error naming metric.
Status checkComparable(const Image& reference, const Image& test, std::string_view metric);

// Rec. 601 luma Y' = 0.299 R + 0.587 G + 0.114 B of each pixel on the 8-bit values (0..255, not
// rounded), row 0 at the top. image must be well-formed (checkImage).
std::vector<double> luma601(const Image& image);

}  // namespace hlod::metrics
