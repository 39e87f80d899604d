#pragma once
// EPSG codes of coordinate reference systems as CityJSON names them, and the few kinds hlodr
// treats differently: projected systems (metres: kept as they are), geographic ones (degrees:
// converted to a local east-north-up frame) and geocentric ones (ECEF metres: likewise).
#include <string>
#include <string_view>

namespace hlod {

enum class CrsKind { Projected, Geographic, Geocentric };

// The EPSG code in a reference-system string: "https://www.opengis.net/def/crs/EPSG/0/7415"
// (CityJSON 1.1, 2.0), "urn:ogc:def:crs:EPSG::7415" (1.0), "EPSG:7415"; 0 when there is none.
int epsgFromReference(std::string_view reference);

// Geographic: 4326 and 4979 (WGS 84), 4258 and 4937 (ETRS89), 4269 (NAD83), 4283 (GDA94),
// 7844 (GDA2020), 4167 (NZGD2000), 4612 and 6668 (JGD2000, JGD2011), 4490 (CGCS2000): all
// latitude, longitude, (ellipsoidal height) in EPSG's axis order, on ellipsoids within a metre
// of WGS 84's. Geocentric: 4978 (WGS 84), 4936 (ETRS89), 7789 (ITRF2014). Anything else is taken
// as projected.
CrsKind crsKind(int epsg);

// "EPSG:7415 (projected)" and so on.
std::string describeEpsg(int epsg);

}  // namespace hlod
