#pragma once
// Map projections of the projected CRSs city models come in, to WGS 84 latitude and longitude
// (and back, for tests and round trips), so that blocks of such a model get a geographic anchor.
//
// - RD New (EPSG:28992; EPSG:7415 is RD New + NAP height): the approximation formulas of
//   Schreutelkamp and Strang van Hees ("Benaderingsformules voor de transformatie tussen RD- en
//   WGS84-kaartcoordinaten", 2001), within about a metre over the Netherlands.
// - UTM (WGS 84: EPSG:32601-32660 north, 32701-32760 south; ETRS89: EPSG:25828-25838, within a
//   metre of WGS 84 in Europe): the transverse Mercator by Krueger's series in n (Karney 2011,
//   "Transverse Mercator with an accuracy of a few nanometers", to n^4: well under a millimetre
//   within a zone).
//
// Heights pass through unchanged: a NAP or other orthometric height is taken as the height above
// the ellipsoid (in the Netherlands they differ by about 43 m; anchors do not need it).
#include <optional>

#include <glm/glm.hpp>

#include "hlod/geodesy/Geodesy.h"

namespace hlod {

// RD New coordinates (x east, y north, metres) to WGS 84, and back.
LatLon rdNewToWgs84(const glm::dvec2& rd);
glm::dvec2 wgs84ToRdNew(const LatLon& p);

struct UtmZone {
  int zone = 31;  // 1..60
  bool north = true;
};

// UTM easting and northing (metres, false easting 500 km, false northing 10,000 km in the
// south) in `zone` to WGS 84, and back.
LatLon utmToWgs84(const UtmZone& zone, const glm::dvec2& eastingNorthing);
glm::dvec2 wgs84ToUtm(const UtmZone& zone, const LatLon& p);

// The UTM zone of an EPSG code (32601-32660, 32701-32760, 25828-25838); nullopt otherwise.
std::optional<UtmZone> utmZoneOf(int epsg);

// True for the projected EPSG codes above (RD New, UTM).
bool hasInverseProjection(int epsg);

// A point (x, y, height) in projected EPSG `epsg` as WGS 84 latitude, longitude and height;
// nullopt for a code without an inverse here.
std::optional<LatLon> projectedToWgs84(int epsg, const glm::dvec3& p);

}  // namespace hlod
