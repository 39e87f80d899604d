#pragma once
// The world axis a model stands on: the one rule for which axis is up, per input format, and the
// horizontal plane around it (for orbits and default views).
#include <cstdint>
#include <optional>
#include <string_view>

#include <glm/glm.hpp>

#include "hlod/Mesh.h"

namespace hlod {

// Stored in skeleton.bin as a u32: only these three values are valid.
enum class UpAxis : std::uint32_t { X = 0, Y = 1, Z = 2 };

// The up axis of an imported model: z for what the importer knows to be a city (CityJSON sets
// Model::zUp), otherwise y, the convention of OBJ, glTF/GLB, PLY, OFF and STL. City folders are
// z-up as well (their blocks are built in metres, Z up).
inline UpAxis upAxisOf(const Model& model) {
  return model.zUp ? UpAxis::Z : UpAxis::Y;
}

inline glm::dvec3 upVector(UpAxis up) {
  glm::dvec3 v(0.0);
  v[int(up)] = 1.0;
  return v;
}

// "x", "y" or "z".
inline const char* upAxisName(UpAxis up) {
  return up == UpAxis::X ? "x" : up == UpAxis::Y ? "y" : "z";
}

// "x", "y" or "z" (as --up takes it); nullopt for anything else.
inline std::optional<UpAxis> parseUpAxis(std::string_view s) {
  if (s == "x") return UpAxis::X;
  if (s == "y") return UpAxis::Y;
  if (s == "z") return UpAxis::Z;
  return std::nullopt;
}

// Two unit axes of the plane perpendicular to up, cyclic after it so that (first, second, up)
// is right-handed: X, Y for z up; Z, X for y up; Y, Z for x up.
inline void horizontalAxes(UpAxis up, glm::dvec3& first, glm::dvec3& second) {
  const int u = int(up);
  first = upVector(UpAxis((u + 1) % 3));
  second = upVector(UpAxis((u + 2) % 3));
}

// The directions a model's cameras stand in: up, and two horizontal axes, (first, second, up)
// right-handed and orthonormal. An up axis gives one (horizontalAxes); a model lying on the earth
// in earth-centred coordinates gets its east-north-up frame (hlod/runtime/Framing.h,
// modelUpFrame).
struct UpFrame {
  glm::dvec3 first{1.0, 0.0, 0.0}, second{0.0, 1.0, 0.0}, up{0.0, 0.0, 1.0};
  bool earthCentred = false;  // east, north and the ellipsoid's normal at the model's centre
};

inline UpFrame upFrame(UpAxis up) {
  UpFrame f;
  horizontalAxes(up, f.first, f.second);
  f.up = upVector(up);
  return f;
}

}  // namespace hlod
