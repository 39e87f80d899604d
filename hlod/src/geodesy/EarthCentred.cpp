// Earth-centred models and their up: hlod/geodesy/EarthCentred.h.
#include "hlod/geodesy/EarthCentred.h"

#include "hlod/geodesy/Geodesy.h"

namespace hlod {

bool isEarthCentred(const glm::dvec3& point) {
  const double r = glm::length(point);
  return r > kEarthCentredMin && r < kEarthCentredMax;
}

bool isEarthCentred(const Aabb& bounds) {
  return !bounds.empty() && isEarthCentred(bounds.centre()) && glm::length(bounds.size()) < 1.0e6;
}

UpFrame enuUpFrame(const glm::dvec3& ecef) {
  const EnuFrame enu(ecefToGeodetic(ecef));
  UpFrame f;
  f.first = enu.directionToEcef({1.0, 0.0, 0.0});
  f.second = enu.directionToEcef({0.0, 1.0, 0.0});
  f.up = enu.directionToEcef({0.0, 0.0, 1.0});
  f.earthCentred = true;
  return f;
}

}  // namespace hlod
