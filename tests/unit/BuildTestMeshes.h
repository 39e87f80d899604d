#pragma once
// Hand-built meshes for the builder and node store tests.
#include <cmath>

#include "hlod/Mesh.h"

namespace hlod::testmesh {

// A wavy height field of n x n quads over [0, size]^2 (open border), with uvs over [0,1]^2.
inline Mesh wavyGrid(int n, double size = 10.0, glm::dvec3 offset = glm::dvec3(0.0)) {
  Mesh m;
  m.name = "grid";
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) {
      const double u = double(x) / n, v = double(y) / n;
      m.positions.push_back(
          offset + glm::dvec3(u * size, v * size, 0.3 * std::sin(7.0 * u) * std::cos(5.0 * v)));
      m.texCoords.emplace_back(float(u), float(v));
    }
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const std::uint32_t a = std::uint32_t(y * (n + 1) + x), b = a + 1,
                          c = a + std::uint32_t(n + 1), d = c + 1;
      m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
    }
  return m;
}

// A closed UV sphere (poles shared), radius r.
inline Mesh sphere(int rings, int sectors, double r = 1.0) {
  Mesh m;
  m.positions.emplace_back(0, 0, r);
  for (int i = 1; i < rings; ++i) {
    const double th = M_PI * i / rings;
    for (int j = 0; j < sectors; ++j) {
      const double ph = 2 * M_PI * j / sectors;
      m.positions.emplace_back(r * std::sin(th) * std::cos(ph), r * std::sin(th) * std::sin(ph),
                               r * std::cos(th));
    }
  }
  m.positions.emplace_back(0, 0, -r);
  const auto ring = [&](int i, int j) {
    return std::uint32_t(1 + (i - 1) * sectors + (j % sectors));
  };
  const auto south = std::uint32_t(m.positions.size() - 1);
  for (int j = 0; j < sectors; ++j)
    m.indices.insert(m.indices.end(), {0u, ring(1, j), ring(1, j + 1)});
  for (int i = 1; i + 1 < rings; ++i)
    for (int j = 0; j < sectors; ++j)
      m.indices.insert(m.indices.end(), {ring(i, j), ring(i + 1, j), ring(i + 1, j + 1), ring(i, j),
                                         ring(i + 1, j + 1), ring(i, j + 1)});
  for (int j = 0; j < sectors; ++j)
    m.indices.insert(m.indices.end(), {ring(rings - 1, j), south, ring(rings - 1, j + 1)});
  return m;
}

// An axis-aligned box from lo to hi: four vertices per face, each face its own normal and its own
// texture rectangle (a sixth of the u range), as a facade atlas would give.
inline Mesh box(const glm::dvec3& lo, const glm::dvec3& hi) {
  Mesh m;
  int face = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (int positive = 0; positive < 2; ++positive, ++face) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      glm::dvec3 n(0.0);
      n[axis] = positive ? 1.0 : -1.0;
      const auto base = std::uint32_t(m.positions.size());
      for (int k = 0; k < 4; ++k) {
        glm::dvec3 p;
        p[axis] = positive ? hi[axis] : lo[axis];
        p[u] = (k == 1 || k == 2) ? hi[u] : lo[u];
        p[v] = (k >= 2) ? hi[v] : lo[v];
        m.positions.push_back(p);
        m.normals.push_back(glm::vec3(n));
        m.texCoords.emplace_back((float(face) + ((k == 1 || k == 2) ? 0.9f : 0.1f)) / 6.0f,
                                 k >= 2 ? 0.9f : 0.1f);
      }
      // Wound counter-clockwise seen from outside.
      if (positive)
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
      else
        m.indices.insert(m.indices.end(), {base, base + 2, base + 1, base, base + 3, base + 2});
    }
  return m;
}

inline std::shared_ptr<const Image> checkerTexture(int w, int h) {
  auto img = std::make_shared<Image>();
  img->width = w;
  img->height = h;
  img->pixels.resize(std::size_t(w) * h * 4);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::uint8_t c = ((x / 4 + y / 4) % 2) ? 255 : 0;
      std::uint8_t* p = &img->pixels[(std::size_t(y) * w + x) * 4];
      p[0] = c;
      p[1] = std::uint8_t(x);
      p[2] = std::uint8_t(y);
      p[3] = 255;
    }
  return img;
}

}  // namespace hlod::testmesh
