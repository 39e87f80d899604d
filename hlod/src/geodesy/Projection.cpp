// Which projected EPSG codes hlodr can turn into latitude and longitude
// (hlod/geodesy/Projection.h).
#include "hlod/geodesy/Projection.h"

namespace hlod {

namespace {

bool isRdNew(int epsg) {
  // 28992: RD New; 7415: RD New + NAP height (a compound CRS, as 3D BAG and the Rotterdam
  // CityJSON declare).
  return epsg == 28992 || epsg == 7415;
}

}  // namespace

std::optional<UtmZone> utmZoneOf(int epsg) {
  if (epsg >= 32601 && epsg <= 32660) return UtmZone{epsg - 32600, true};
  if (epsg >= 32701 && epsg <= 32760) return UtmZone{epsg - 32700, false};
  // ETRS89 / UTM zones 28N-38N (Europe).
  if (epsg >= 25828 && epsg <= 25838) return UtmZone{epsg - 25800, true};
  return std::nullopt;
}

bool hasInverseProjection(int epsg) {
  return isRdNew(epsg) || utmZoneOf(epsg).has_value();
}

std::optional<LatLon> projectedToWgs84(int epsg, const glm::dvec3& p) {
  LatLon out;
  if (isRdNew(epsg)) {
    out = rdNewToWgs84({p.x, p.y});
  } else if (const auto zone = utmZoneOf(epsg)) {
    out = utmToWgs84(*zone, {p.x, p.y});
  } else {
    return std::nullopt;
  }
  out.height = p.z;
  return out;
}

}  // namespace hlod
