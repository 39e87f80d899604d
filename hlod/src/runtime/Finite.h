#pragma once
// A vector with no NaN or infinite coordinate: what the camera paths check at their boundary.
// Private to the runtime.
#include <cmath>

#include <glm/glm.hpp>

namespace hlod {

inline bool finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace hlod
