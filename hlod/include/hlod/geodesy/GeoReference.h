#pragma once
// Where a model's coordinates lie on the earth: in an east-north-up frame at an origin (a city
// folder; a geographic or geocentric CityJSON, converted on import), in a projected CRS whose
// inverse hlodr knows (RD New, UTM: hlod/geodesy/Projection.h), or nowhere known (a mesh file, an
// unknown projected CRS). Blocks get their latitude/longitude anchors through it, and the inputs
// of a region are placed in one frame through ECEF with it.
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "hlod/Mesh.h"
#include "hlod/geodesy/Geodesy.h"

namespace hlod {

class GeoReference {
 public:
  enum class Kind { None, Enu, Projected };

  GeoReference() = default;  // Kind::None
  static GeoReference enu(const LatLon& origin);
  // epsg must have an inverse (hasInverseProjection).
  static GeoReference projected(int epsg);
  // The reference a CityJSON import declared: its ENU frame when converted, its projection when
  // hlodr has the inverse, else none.
  static GeoReference of(const ModelCrs& crs);

  Kind kind() const { return kind_; }
  bool known() const { return kind_ != Kind::None; }
  int epsg() const { return epsg_; }
  // The ENU frame, for Kind::Enu.
  const EnuFrame* frame() const { return frame_ ? &*frame_ : nullptr; }

  // A point's geodetic position and ECEF coordinates; known() must hold.
  LatLon toLatLon(const glm::dvec3& p) const;
  glm::dvec3 toEcef(const glm::dvec3& p) const;
  // "ENU at 51.9000 N 4.4500 E", "EPSG:7415 (RD New)", "none".
  std::string describe() const;

 private:
  Kind kind_ = Kind::None;
  int epsg_ = 0;
  std::optional<EnuFrame> frame_;
};

}  // namespace hlod
