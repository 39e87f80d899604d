#pragma once
// Small hand-built scenes and image comparison helpers for the GL tests.
#include <cmath>
#include <cstdlib>
#include <memory>

#include <gtest/gtest.h>

#include "hlod/Mesh.h"
#include "renderer/GlContext.h"
#include "renderer/Renderer.h"

namespace gltest {

// An axis-aligned box as 12 triangles with flat normals, centred at c with half sizes h.
inline hlod::Mesh box(const glm::dvec3& c, const glm::dvec3& h, glm::vec4 colour) {
  hlod::Mesh m;
  m.baseColor = colour;
  const glm::dvec3 n[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (const auto& axis : n) {
    // Two tangent directions of this face.
    const glm::dvec3 t1 = std::abs(axis.x) > 0.5 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
    const glm::dvec3 t2 = glm::cross(axis, t1);
    const auto base = static_cast<std::uint32_t>(m.positions.size());
    for (int k = 0; k < 4; ++k) {
      const double s1 = (k == 1 || k == 2) ? 1.0 : -1.0, s2 = (k >= 2) ? 1.0 : -1.0;
      m.positions.push_back(c + h * (axis + s1 * t1 + s2 * t2));
      m.normals.emplace_back(axis);
      m.texCoords.emplace_back((s1 + 1) * 0.5, (s2 + 1) * 0.5);
    }
    for (std::uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) m.indices.push_back(base + i);
  }
  return m;
}

// A quad in the plane z = z0 spanning [x0,x1] x [y0,y1], facing +z.
inline hlod::Mesh quad(double x0, double y0, double x1, double y1, double z0, glm::vec4 colour) {
  hlod::Mesh m;
  m.baseColor = colour;
  m.positions = {{x0, y0, z0}, {x1, y0, z0}, {x1, y1, z0}, {x0, y1, z0}};
  m.normals.assign(4, glm::vec3(0, 0, 1));
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

// A 2x2 checker texture: red, green / blue, white.
inline std::shared_ptr<hlod::Image> checker() {
  auto img = std::make_shared<hlod::Image>();
  img->width = img->height = 2;
  img->pixels = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255};
  return img;
}

inline glm::ivec4 pixel(const hlod::Image& img, int x, int y) {
  const auto* p = &img.pixels[(static_cast<std::size_t>(y) * img.width + x) * 4];
  return {p[0], p[1], p[2], p[3]};
}

struct ImageDiff {
  double meanAbs = 0.0;         // mean absolute difference per channel, 0..255
  int maxAbs = 0;               // largest channel difference
  double differingShare = 0.0;  // share of pixels with any channel differing by more than 8
};

inline ImageDiff compare(const hlod::Image& a, const hlod::Image& b) {
  ImageDiff d;
  if (a.width != b.width || a.height != b.height) {
    d.meanAbs = d.maxAbs = 255;
    d.differingShare = 1.0;
    return d;
  }
  double sum = 0;
  std::size_t differing = 0;
  for (std::size_t i = 0; i < a.pixels.size(); i += 4) {
    int worst = 0;
    for (int c = 0; c < 3; ++c) {
      const int diff = std::abs(int(a.pixels[i + c]) - int(b.pixels[i + c]));
      sum += diff;
      worst = std::max(worst, diff);
    }
    d.maxAbs = std::max(d.maxAbs, worst);
    if (worst > 8) ++differing;
  }
  const std::size_t n = a.pixels.size() / 4;
  d.meanAbs = sum / (3.0 * n);
  d.differingShare = double(differing) / n;
  return d;
}

// Creates a context of the given backend or skips the test with the reason.
inline std::unique_ptr<renderer::GlContext> contextOrSkip(renderer::Backend backend) {
  auto c = renderer::createContext(backend);
  if (!c) return nullptr;
  return std::move(*c);
}

}  // namespace gltest
