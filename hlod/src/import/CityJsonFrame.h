#pragma once
// The frame a CityJSON model is imported into, decided by its CRS: projected coordinates stay as
// they are; geographic (latitude, longitude, height) and geocentric (ECEF) ones go into an
// east-north-up frame in metres at the centre of the data's box. Private to hlod/src/import.
#include <optional>
#include <vector>

#include "hlod/Mesh.h"
#include "hlod/Result.h"
#include "hlod/geodesy/Epsg.h"
#include "hlod/geodesy/Geodesy.h"

namespace hlod::import {

class CityJsonFrame {
 public:
  // The frame for data in EPSG code `epsg` (0: none declared) whose vertices span `box`; fills
  // crs. Geographic data is read latitude first, as EPSG orders it, unless its first coordinate
  // goes past 90 degrees while the second does not: then longitude first (lonLat() says so).
  static Result<CityJsonFrame> make(int epsg, const Aabb& box, ModelCrs& crs);

  // A vertex in the model's frame; nullopt for a geographic one whose latitude is past 90.
  std::optional<glm::dvec3> toModel(const glm::dvec3& source) const;
  bool lonLat() const { return lonLat_; }

 private:
  CrsKind kind_ = CrsKind::Projected;
  bool lonLat_ = false;
  std::optional<EnuFrame> enu_;
};

}  // namespace hlod::import
