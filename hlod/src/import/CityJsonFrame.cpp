#include "import/CityJsonFrame.h"

#include <algorithm>
#include <cmath>

namespace hlod::import {

Result<CityJsonFrame> CityJsonFrame::make(int epsg, const Aabb& box, ModelCrs& crs) {
  CityJsonFrame frame;
  crs.epsg = epsg;
  frame.kind_ = epsg ? crsKind(epsg) : CrsKind::Projected;
  if (frame.kind_ == CrsKind::Projected || box.empty()) {
    frame.kind_ = CrsKind::Projected;
    crs.description = describeEpsg(epsg) + ": coordinates kept as they are";
    return frame;
  }
  LatLon origin;
  if (frame.kind_ == CrsKind::Geographic) {
    // Many tools write longitude first against EPSG's order; a first coordinate past 90
    // degrees can only be a longitude.
    frame.lonLat_ = std::max(std::abs(box.min.x), std::abs(box.max.x)) > 90.0 &&
                    std::max(std::abs(box.min.y), std::abs(box.max.y)) <= 90.0;
    const glm::dvec3 c = box.centre();
    origin = frame.lonLat_ ? LatLon{c.y, c.x, c.z} : LatLon{c.x, c.y, c.z};
  } else {
    origin = ecefToGeodetic(box.centre());
  }
  frame.enu_.emplace(origin);
  crs.toEnu = true;
  crs.originLat = origin.lat;
  crs.originLon = origin.lon;
  crs.originHeight = origin.height;
  crs.description = describeEpsg(epsg) + ": converted to east-north-up metres";
  return frame;
}

std::optional<glm::dvec3> CityJsonFrame::toModel(const glm::dvec3& p) const {
  if (!enu_) return p;
  if (kind_ == CrsKind::Geocentric) return enu_->fromEcef(p);
  const LatLon g = lonLat_ ? LatLon{p.y, p.x, p.z} : LatLon{p.x, p.y, p.z};
  if (!(std::abs(g.lat) <= 90.0)) return std::nullopt;
  return enu_->fromGeodetic(g);
}

}  // namespace hlod::import
