// The frames of a tileset (3D Tiles 1.1 sec. "Transforms", "y-up to z-up"): see TilesetFrame.h.
#include "tiles/TilesetFrame.h"

#include <cmath>
#include <cstdio>

#include "hlod/geodesy/GeoReference.h"

namespace hlod::tiles {

AxisMap yUpToZUp() {
  return AxisMap{{0, 2, 1}, {1.0f, -1.0f, 1.0f}};
}

AxisMap xUpToZUp() {
  return AxisMap{{2, 1, 0}, {-1.0f, 1.0f, 1.0f}};
}

AxisMap upToZ(UpAxis up) {
  switch (up) {
    case UpAxis::Y:
      return yUpToZUp();
    case UpAxis::X:
      return AxisMap{{1, 2, 0}, {1.0f, 1.0f, 1.0f}};
    case UpAxis::Z:
      break;
  }
  return AxisMap{};
}

glm::dmat4 enuToEcef(const EnuFrame& frame) {
  // rotation() is ECEF -> ENU; its transpose takes ENU directions to ECEF.
  glm::dmat4 m(glm::transpose(frame.rotation()));
  m[3] = glm::dvec4(frame.originEcef(), 1.0);
  return m;
}

namespace {

std::string describeOrigin(const char* what, const LatLon& o) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%s at %.6f %s %.6f %s, %.1f m", what, std::abs(o.lat),
                o.lat >= 0 ? "N" : "S", std::abs(o.lon), o.lon >= 0 ? "E" : "W", o.height);
  return buf;
}

}  // namespace

std::optional<GeoPlacement> geoPlacement(const Skeleton& skeleton) {
  if (skeleton.up != UpAxis::Z) return std::nullopt;
  const GeoReference geo = GeoReference::of(skeleton.crs);
  if (geo.frame()) {
    GeoPlacement p;
    p.origin = geo.frame()->origin();
    p.tileToEcef = enuToEcef(*geo.frame());
    p.description = describeOrigin("east-north-up", p.origin);
    return p;
  }
  if (!geo.known()) return std::nullopt;
  // A projected CRS: the map from projected metres to ECEF is not affine, so fit it at the
  // centre of the model's ground by central differences over its half extent. Its error grows
  // with the square of the distance from the centre (the earth's curvature: 8 cm at 1 km).
  Aabb box;
  for (const NodeInfo& n : skeleton.nodes) box.extend(n.bounds);
  if (box.empty()) return std::nullopt;
  const glm::dvec3 c(box.centre().x, box.centre().y, box.min.z);
  const double h = std::max(1.0, 0.5 * std::max(box.size().x, box.size().y));
  GeoPlacement p;
  p.origin = geo.toLatLon(c);
  glm::dmat3 j(0.0);
  for (int k = 0; k < 3; ++k) {
    glm::dvec3 d(0.0);
    d[k] = h;
    j[k] = (geo.toEcef(c + d) - geo.toEcef(c - d)) / (2.0 * h);
  }
  p.tileToEcef = glm::dmat4(j);
  p.tileToEcef[3] = glm::dvec4(geo.toEcef(c) - j * c, 1.0);
  p.description = describeOrigin((geo.describe() + ", fitted linearly").c_str(), p.origin);
  return p;
}

}  // namespace hlod::tiles
