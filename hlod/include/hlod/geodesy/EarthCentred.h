#pragma once
// Models in earth-centred, earth-fixed coordinates (ECEF, EPSG:4978: a terrain or a scan exported
// as is, a 3D Tiles content): they lie about 6,400 km from the origin, and "up" there is the
// ellipsoid's normal, not an axis. Cameras, paths and the page's orbit and walk stand on it.
#include <glm/glm.hpp>

#include "hlod/Mesh.h"
#include "hlod/UpAxis.h"

namespace hlod {

// A point lies on the earth in ECEF when it is 6,000 to 7,000 km from the origin (the WGS84
// ellipsoid's radii are 6,357 and 6,378 km; some hundred km of height or depth either way).
constexpr double kEarthCentredMin = 6.0e6, kEarthCentredMax = 7.0e6;
bool isEarthCentred(const glm::dvec3& point);

// A model lies on the earth in ECEF when its box's centre does and the box is smaller than the
// distance to the origin allows a map to be (1,000 km across: beyond that, one "up" no longer
// fits the whole model).
bool isEarthCentred(const Aabb& bounds);

// The east-north-up frame at an ECEF point (its geodetic position's), as an UpFrame: first east,
// second north, up the ellipsoid's normal.
UpFrame enuUpFrame(const glm::dvec3& ecef);

}  // namespace hlod
