// A model's place on the earth (hlod/geodesy/GeoReference.h).
#include "hlod/geodesy/GeoReference.h"

#include <cassert>
#include <cstdio>

#include "hlod/geodesy/Projection.h"

namespace hlod {

GeoReference GeoReference::enu(const LatLon& origin) {
  GeoReference g;
  g.kind_ = Kind::Enu;
  g.frame_.emplace(origin);
  return g;
}

GeoReference GeoReference::projected(int epsg) {
  assert(hasInverseProjection(epsg));
  GeoReference g;
  g.kind_ = Kind::Projected;
  g.epsg_ = epsg;
  return g;
}

GeoReference GeoReference::of(const ModelCrs& crs) {
  if (crs.toEnu) {
    GeoReference g = enu({crs.originLat, crs.originLon, crs.originHeight});
    g.epsg_ = crs.epsg;
    return g;
  }
  if (hasInverseProjection(crs.epsg)) return projected(crs.epsg);
  return {};
}

LatLon GeoReference::toLatLon(const glm::dvec3& p) const {
  assert(known());
  if (kind_ == Kind::Enu) return frame_->toGeodetic(p);
  return *projectedToWgs84(epsg_, p);
}

glm::dvec3 GeoReference::toEcef(const glm::dvec3& p) const {
  assert(known());
  if (kind_ == Kind::Enu) return frame_->toEcef(p);
  return geodeticToEcef(toLatLon(p));
}

std::string GeoReference::describe() const {
  char buf[96];
  switch (kind_) {
    case Kind::Enu:
      std::snprintf(buf, sizeof buf, "east-north-up metres at %.6f, %.6f", frame_->origin().lat,
                    frame_->origin().lon);
      return buf;
    case Kind::Projected:
      std::snprintf(buf, sizeof buf, "EPSG:%d (%s, inverse projection)", epsg_,
                    utmZoneOf(epsg_) ? "UTM" : "RD New");
      return buf;
    default:
      return "none";
  }
}

}  // namespace hlod
