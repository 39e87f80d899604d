#pragma once
// Where the precision tests put their scenes: at the origin, and in earth-centred coordinates
// (ECEF, WGS84) through the east-north-up frame at Berkeley, 6,400 km from the origin.
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "hlod/geodesy/Geodesy.h"

namespace hardcase {

struct Place {
  std::string name;
  std::unique_ptr<hlod::EnuFrame> enu;  // null: local coordinates are world coordinates
  glm::dvec3 point(const glm::dvec3& local) const { return enu ? enu->toEcef(local) : local; }
  glm::dvec3 direction(const glm::dvec3& local) const {
    return enu ? enu->directionToEcef(local) : local;
  }
};

inline std::vector<Place> places() {
  std::vector<Place> p;
  p.push_back({"at the origin", nullptr});
  p.push_back({"6,400 km from the origin (ECEF)",
               std::make_unique<hlod::EnuFrame>(hlod::LatLon{37.87, -122.27, 30.0})});
  return p;
}

}  // namespace hardcase
