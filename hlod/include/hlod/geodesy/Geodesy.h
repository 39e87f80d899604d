#pragma once
// Geographic coordinates on the WGS84 ellipsoid, earth-centred earth-fixed (ECEF) coordinates,
// and local east-north-up (ENU) frames, all in double precision. A city's frame is the ENU frame
// at its origin (metres: X east, Y north, Z up); blocks anchored elsewhere are placed in it
// through ECEF, which is exact across the antimeridian and near the poles, where differences of
// longitude scaled by cos(latitude) are not.
//
// Precision: ECEF coordinates are about 6.4e6 m, where a double resolves 1e-9 m; a geodetic
// round trip (geodeticToEcef then ecefToGeodetic) comes back within 1e-7 m at any latitude and
// longitude and at heights from -6,000 km to +100,000 km (54 nm worst, measured on a grid).
// Within ~100 km of the earth's centre ecefToGeodetic converges slowly (2 cm off at 80 km).
#include <glm/glm.hpp>

namespace hlod {

// WGS84 (NIMA TR8350.2): semi-major axis and flattening; the rest follows from them.
inline constexpr double kRadPerDeg = 0.017453292519943295;  // pi / 180
inline constexpr double kWgs84A = 6378137.0;
inline constexpr double kWgs84F = 1.0 / 298.257223563;
inline constexpr double kWgs84B = kWgs84A * (1.0 - kWgs84F);   // semi-minor axis, 6356752.3142 m
inline constexpr double kWgs84E2 = kWgs84F * (2.0 - kWgs84F);  // first eccentricity squared

// A geodetic position: latitude and longitude in degrees (north and east positive), height in
// metres above the WGS84 ellipsoid.
struct LatLon {
  double lat = 0.0;
  double lon = 0.0;
  double height = 0.0;
};

// ECEF position (metres) of a geodetic position. Any finite input gives a finite output;
// longitudes outside [-180, 180] wrap.
glm::dvec3 geodeticToEcef(const LatLon& p);

// The geodetic position of an ECEF point: latitude in [-90, 90], longitude in (-180, 180], height
// above the ellipsoid. On the polar axis the longitude is 0; at the centre of the earth the result
// is latitude 0, height -kWgs84A (finite, though any latitude would do).
LatLon ecefToGeodetic(const glm::dvec3& ecef);

// A local tangent frame: the origin's ECEF position and the rotation from ECEF to (east, north,
// up) at it. At a pole, where east and north are a matter of convention, they follow the
// origin's longitude (the limit of the frame along that meridian), so the frame stays
// orthonormal there too.
class EnuFrame {
 public:
  explicit EnuFrame(const LatLon& origin);

  // ENU coordinates (metres) of an ECEF point, and back.
  glm::dvec3 fromEcef(const glm::dvec3& ecef) const;
  glm::dvec3 toEcef(const glm::dvec3& enu) const;
  // ENU coordinates of a geodetic position, and back.
  glm::dvec3 fromGeodetic(const LatLon& p) const { return fromEcef(geodeticToEcef(p)); }
  LatLon toGeodetic(const glm::dvec3& enu) const { return ecefToGeodetic(toEcef(enu)); }
  // Rotates a direction from ECEF into this frame, and back (normals, camera up vectors).
  glm::dvec3 directionFromEcef(const glm::dvec3& d) const { return rotation_ * d; }
  glm::dvec3 directionToEcef(const glm::dvec3& d) const { return glm::transpose(rotation_) * d; }

  const LatLon& origin() const { return origin_; }
  const glm::dvec3& originEcef() const { return originEcef_; }
  // Rows east, north, up (as glm stores columns: rotation()[c][r]).
  const glm::dmat3& rotation() const { return rotation_; }

 private:
  LatLon origin_;
  glm::dvec3 originEcef_;
  glm::dmat3 rotation_;  // ECEF -> ENU
};

// The transform that takes coordinates of frame `from` into frame `to` (both ENU frames): the
// rotation and offset applied as to = rotation * from + offset, composed in double precision.
struct EnuToEnu {
  glm::dmat3 rotation{1.0};
  glm::dvec3 offset{0.0};

  EnuToEnu(const EnuFrame& from, const EnuFrame& to);
  glm::dvec3 point(const glm::dvec3& p) const { return rotation * p + offset; }
  glm::dvec3 direction(const glm::dvec3& d) const { return rotation * d; }
};

}  // namespace hlod
