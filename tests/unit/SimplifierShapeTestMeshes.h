#pragma once
// Hand-built meshes on which coarse levels used to lose their shape: closed boxes and thin slabs
// with finely gridded faces, a flat facade with window recesses, a box standing against a wall.
// Faces carry their own vertices (normal, texture coordinate), as the city's blocks do.
#include <cmath>

#include "hlod/Mesh.h"

namespace hlod::testmesh {

// Appends a planar grid quad: corner o, edge vectors eu and ev, nu x nv cells, wound
// counter-clockwise seen from the side `normal` points to.
inline void gridQuad(Mesh& m, const glm::dvec3& o, const glm::dvec3& eu, const glm::dvec3& ev,
                     int nu, int nv, const glm::dvec3& normal) {
  const auto base = std::uint32_t(m.positions.size());
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i <= nu; ++i) {
      m.positions.push_back(o + eu * (double(i) / nu) + ev * (double(j) / nv));
      m.normals.push_back(glm::vec3(normal));
      m.texCoords.emplace_back(float(i) / float(nu), float(j) / float(nv));
    }
  const bool ccw = glm::dot(glm::cross(eu, ev), normal) > 0.0;
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const std::uint32_t a = base + std::uint32_t(j * (nu + 1) + i), b = a + 1,
                          c = a + std::uint32_t(nu + 1), d = c + 1;
      if (ccw)
        m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
      else
        m.indices.insert(m.indices.end(), {a, d, b, a, c, d});
    }
}

// A closed axis-aligned box, each face a grid of cells no larger than `cell`.
inline Mesh griddedBox(const glm::dvec3& lo, const glm::dvec3& hi, double cell) {
  Mesh m;
  m.oneSided = true;
  const glm::dvec3 size = hi - lo;
  auto cells = [&](double len) { return std::max(1, int(std::ceil(len / cell - 1e-9))); };
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    glm::dvec3 eu(0.0), ev(0.0);
    eu[u] = size[u];
    ev[v] = size[v];
    for (int positive = 0; positive < 2; ++positive) {
      glm::dvec3 o = lo, n(0.0);
      if (positive) o[axis] = hi[axis];
      n[axis] = positive ? 1.0 : -1.0;
      gridQuad(m, o, eu, ev, cells(size[u]), cells(size[v]), n);
    }
  }
  return m;
}

inline void appendTo(Mesh& dst, const Mesh& src) {
  const auto base = std::uint32_t(dst.positions.size());
  dst.positions.insert(dst.positions.end(), src.positions.begin(), src.positions.end());
  dst.normals.insert(dst.normals.end(), src.normals.begin(), src.normals.end());
  dst.texCoords.insert(dst.texCoords.end(), src.texCoords.begin(), src.texCoords.end());
  for (std::uint32_t i : src.indices) dst.indices.push_back(base + i);
}

// Courtyard paving: a 20 x 20 m slab 0.15 m thick (top, bottom and sides), 0.25 m cells.
inline Mesh thinSlab() {
  return griddedBox({0.0, 0.0, 0.0}, {20.0, 20.0, 0.15}, 0.25);
}

// A flat facade 24 m wide and 12 m high in the plane y = 0, facing -y, with a 4 x 3 grid of
// window recesses 0.3 m deep (reveals and back panes facing out of the recess). Open: it is one
// side of a building.
inline Mesh recessedFacade() {
  Mesh m;
  m.oneSided = true;
  const glm::dvec3 out(0.0, -1.0, 0.0);
  const double W = 24.0, H = 12.0, w = 2.0, h = 2.0, depth = 0.3;
  // The wall: columns and bands around the windows, as grids of 0.5 m cells.
  const double xs[] = {0, 2, 4, 8, 10, 14, 16, 20, 22, 24};
  const double zs[] = {0, 1, 3, 5, 7, 9, 11, 12};
  for (int i = 0; i + 1 < 10; ++i)
    for (int j = 0; j + 1 < 8; ++j) {
      const bool window =
          (i % 2 == 1) && (j % 2 == 1) && xs[i + 1] - xs[i] == w && zs[j + 1] - zs[j] == h;
      const glm::dvec3 o(xs[i], 0.0, zs[j]);
      const glm::dvec3 eu(xs[i + 1] - xs[i], 0, 0), ev(0, 0, zs[j + 1] - zs[j]);
      const int nu = int((xs[i + 1] - xs[i]) / 0.5), nv = int((zs[j + 1] - zs[j]) / 0.5);
      if (!window) {
        gridQuad(m, o, eu, ev, nu, nv, out);
        continue;
      }
      // The recess: a back pane and four reveals, each facing into the opening.
      gridQuad(m, o + glm::dvec3(0, depth, 0), eu, ev, nu, nv, out);
      gridQuad(m, o, ev, glm::dvec3(0, depth, 0), nv, 1, {1, 0, 0});
      gridQuad(m, o + eu, ev, glm::dvec3(0, depth, 0), nv, 1, {-1, 0, 0});
      gridQuad(m, o, eu, glm::dvec3(0, depth, 0), nu, 1, {0, 0, 1});
      gridQuad(m, o + ev, eu, glm::dvec3(0, depth, 0), nu, 1, {0, 0, -1});
    }
  (void)W, (void)H;
  return m;
}

// A wall (the plane x = 0, facing +x, 12 x 12 m, 0.5 m cells) with a closed 2 x 2 x 2 m box
// standing against it: the box's -x face lies on the wall, sharing its grid positions.
inline Mesh boxAgainstWall() {
  Mesh m;
  m.oneSided = true;
  gridQuad(m, {0, 0, 0}, {0, 12, 0}, {0, 0, 12}, 24, 24, {1, 0, 0});
  appendTo(m, griddedBox({0.0, 5.0, 0.0}, {2.0, 7.0, 2.0}, 0.5));
  return m;
}

}  // namespace hlod::testmesh
