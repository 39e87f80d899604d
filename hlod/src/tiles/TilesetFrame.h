#pragma once
// The frames a tileset's coordinates go through (3D Tiles 1.1 sec. "Transforms"), shared by the
// export and the import. Private to hlod/src/tiles.
//   glTF (y up) --y-up to z-up--> tile frame (z up) --tile transforms--> tileset frame
// and, for hlodr's world: tile frame = the world with its up axis turned to z (upToZ).
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "hlod/UpAxis.h"
#include "hlod/geodesy/Geodesy.h"
#include "hlod/store/Skeleton.h"
#include "hlod/tiles/Glb.h"

namespace hlod::tiles {

// 3D Tiles sec. "y-up to z-up": glTF is turned about x by pi/2, (x, y, z) -> (x, -z, y).
AxisMap yUpToZUp();
// The same for the legacy asset.gltfUpAxis "X" (Cesium's X_UP_TO_Z_UP, a turn about y by
// -pi/2: (x, y, z) -> (-z, y, x)) and "Z" (nothing to turn).
AxisMap xUpToZUp();
// The world of a store standing on `up` turned so that up is z: z up is kept; y up becomes
// (x, -z, y) (glTF's own turn, so that a y-up store's GLBs hold its coordinates unchanged);
// x up becomes (y, z, x).
AxisMap upToZ(UpAxis up);

// Where a store lies on the earth, when it does: its tile frame (z up) to ECEF.
struct GeoPlacement {
  LatLon origin;  // the east-north-up frame's origin (or the fit's centre)
  glm::dmat4 tileToEcef{1.0};
  std::string description;  // for the user: "east-north-up at 37.8715 N 122.2730 W"
};
// The placement of a z-up store with a known geographic reference: its crs converted to ENU
// (exact: the ENU frame's rotation and origin), or a projected CRS hlodr can invert (the linear
// map that fits it at the model's centre: within millimetres over a few kilometres). Nothing for
// a store without one, or one that does not stand on z.
std::optional<GeoPlacement> geoPlacement(const Skeleton& skeleton);

// The rotation and origin of an ENU frame as a 4x4 from ENU to ECEF (column-major, as 3D Tiles
// writes `transform`).
glm::dmat4 enuToEcef(const EnuFrame& frame);

}  // namespace hlod::tiles
