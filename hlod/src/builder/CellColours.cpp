// A cell node's flat colours (builder/CellColours.h).
#include "builder/CellColours.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <memory>
#include <unordered_map>

namespace hlod {

namespace {

bool hasTexture(const LocalMesh& m) {
  return m.texture && !m.texture->empty() &&
         m.texture->pixels.size() == std::size_t(m.texture->width) * m.texture->height * 4 &&
         m.texCoords.size() == m.positions.size();
}

std::uint8_t toByte(float v) {
  return std::uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

}  // namespace

ColouredMesh mergeCellChildren(std::span<const LocalMesh> children) {
  ColouredMesh out;
  Mesh& m = out.mesh;
  m.oneSided = !children.empty();
  m.baseColor = glm::vec4(1.0f);
  std::unordered_map<std::uint32_t, std::uint32_t> colourIndex;  // RGBA8 -> colours
  for (const LocalMesh& c : children) {
    m.oneSided = m.oneSided && c.oneSided;
    const bool textured = hasTexture(c);
    const Image* image = textured ? c.texture.get() : nullptr;
    // A texel of a texture that repeats (coordinates outside [0,1]) wraps around.
    const auto texel = [&](glm::vec2 t) {
      const float x = t.x - std::floor(t.x), y = t.y - std::floor(t.y);
      const int px = std::min(image->width - 1, int(x * float(image->width)));
      const int py = std::min(image->height - 1, int(y * float(image->height)));
      const std::uint8_t* p = &image->pixels[(std::size_t(py) * image->width + px) * 4];
      return glm::vec4(p[0], p[1], p[2], p[3]) / 255.0f;
    };
    // Each triangle's mean colour over its texture footprint (15 barycentric points),
    // spread to its vertices weighted by its area.
    std::vector<glm::dvec4> sum(c.positions.size(), glm::dvec4(0.0));
    std::vector<double> weight(c.positions.size(), 0.0);
    for (std::size_t i = 0; i + 2 < c.indices.size(); i += 3) {
      const std::uint32_t v[3] = {c.indices[i], c.indices[i + 1], c.indices[i + 2]};
      glm::vec4 colour(1.0f);
      if (textured) {
        constexpr int kSteps = 4;
        glm::vec4 acc(0.0f);
        int n = 0;
        for (int a = 0; a <= kSteps; ++a)
          for (int b = 0; a + b <= kSteps; ++b, ++n) {
            const float u = float(a) / kSteps, w = float(b) / kSteps;
            acc += texel(c.texCoords[v[0]] * (1.0f - u - w) + c.texCoords[v[1]] * u +
                         c.texCoords[v[2]] * w);
          }
        colour = acc / float(n);
      }
      const double area =
          0.5 * glm::length(glm::cross(glm::dvec3(c.positions[v[1]] - c.positions[v[0]]),
                                       glm::dvec3(c.positions[v[2]] - c.positions[v[0]])));
      const double w = std::max(area, 1e-12);
      for (std::uint32_t k : v) {
        sum[k] += w * glm::dvec4(colour);
        weight[k] += w;
      }
    }
    const auto base = std::uint32_t(m.positions.size());
    for (std::size_t v = 0; v < c.positions.size(); ++v) {
      m.positions.push_back(c.centre + glm::dvec3(c.positions[v]));
      m.normals.push_back(v < c.normals.size() ? c.normals[v] : glm::vec3(0.0f, 0.0f, 1.0f));
      const glm::vec4 colour =
          (weight[v] > 0.0 ? glm::vec4(sum[v] / weight[v]) : glm::vec4(1.0f)) * c.baseColor;
      std::uint32_t key = 0;
      for (int ch = 0; ch < 4; ++ch) key = key << 8 | toByte(colour[ch]);
      auto [it, fresh] = colourIndex.try_emplace(key, std::uint32_t(out.colours.size()));
      if (fresh) out.colours.push_back(colour);
      m.texCoords.emplace_back(float(it->second), 0.0f);
    }
    for (std::uint32_t i : c.indices) m.indices.push_back(base + i);
  }
  return out;
}

Mesh flatColoured(const Mesh& simplified, std::span<const glm::vec4> colours, float smoothCos) {
  Mesh out;
  out.oneSided = simplified.oneSided;
  out.baseColor = glm::vec4(1.0f);
  const auto colourOf = [&](std::uint32_t v) {
    const auto i = std::size_t(simplified.texCoords[v].x);
    assert(i < colours.size());
    return colours[i];
  };
  // Per triangle its colour's texel; texels in the order first used.
  std::unordered_map<std::uint32_t, std::uint32_t> texelOf;
  std::vector<std::uint32_t> triangleTexel, texelColour;
  for (std::size_t i = 0; i + 2 < simplified.indices.size(); i += 3) {
    const glm::vec4 c = (colourOf(simplified.indices[i]) + colourOf(simplified.indices[i + 1]) +
                         colourOf(simplified.indices[i + 2])) /
                        3.0f;
    std::uint32_t key = 0;
    for (int ch = 0; ch < 4; ++ch) key = key << 8 | toByte(c[ch]);
    auto [it, fresh] = texelOf.try_emplace(key, std::uint32_t(texelColour.size()));
    if (fresh) texelColour.push_back(key);
    triangleTexel.push_back(it->second);
  }
  const int side = std::max(1, int(std::ceil(std::sqrt(double(texelColour.size())))));
  auto image = std::make_shared<Image>();
  image->width = image->height = side;
  image->pixels.assign(std::size_t(side) * side * 4, 255);
  for (std::size_t t = 0; t < texelColour.size(); ++t)
    for (int ch = 0; ch < 4; ++ch)
      image->pixels[4 * t + ch] = std::uint8_t(texelColour[t] >> (24 - 8 * ch));
  // Three vertices per triangle, with its face's normal (but where smoothCos allows): after a
  // simplification that joined separate parts, the input vertices' normals no longer match their
  // triangles, and shading them smoothly paints swirls across flat walls.
  for (std::size_t i = 0; i + 2 < simplified.indices.size(); i += 3) {
    const std::uint32_t* tri = &simplified.indices[i];
    const std::uint32_t texel = triangleTexel[i / 3];
    const glm::dvec3 n = glm::cross(simplified.positions[tri[1]] - simplified.positions[tri[0]],
                                    simplified.positions[tri[2]] - simplified.positions[tri[0]]);
    for (int k = 0; k < 3; ++k) {
      assert(tri[k] < simplified.positions.size());
      const glm::vec3 fallback =
          tri[k] < simplified.normals.size() ? simplified.normals[tri[k]] : glm::vec3(0, 0, 1);
      const glm::vec3 face = normalizedOr(glm::vec3(n), fallback);
      // A corner's own normal where it agrees with its face (smoothCos < 1: a curved part
      // stays round), the face's elsewhere.
      const bool smooth = smoothCos < 1.0f && tri[k] < simplified.normals.size() &&
                          glm::dot(simplified.normals[tri[k]], face) >= smoothCos;
      out.indices.push_back(std::uint32_t(out.positions.size()));
      out.positions.push_back(simplified.positions[tri[k]]);
      out.normals.push_back(smooth ? simplified.normals[tri[k]] : face);
      out.texCoords.push_back((glm::vec2(float(texel % side), float(texel / side)) + 0.5f) /
                              float(side));
    }
  }
  out.texture = std::move(image);
  return out;
}

void dropRepeatedTriangles(Mesh& mesh) {
  std::vector<std::array<std::uint32_t, 4>> keys;  // rotated so the smallest comes first, then t
  for (std::uint32_t t = 0; t * 3 < mesh.indices.size(); ++t) {
    const std::uint32_t* v = &mesh.indices[3 * t];
    const int k = v[0] <= v[1] && v[0] <= v[2] ? 0 : v[1] <= v[2] ? 1 : 2;
    keys.push_back({v[k], v[(k + 1) % 3], v[(k + 2) % 3], t});
  }
  std::sort(keys.begin(), keys.end());
  std::vector<std::uint8_t> keep(keys.size(), 0);
  for (std::size_t i = 0; i < keys.size(); ++i)
    if (i == 0 || !std::equal(keys[i].begin(), keys[i].begin() + 3, keys[i - 1].begin()))
      keep[keys[i][3]] = 1;
  std::vector<std::uint32_t> indices;
  for (std::uint32_t t = 0; t < keep.size(); ++t)
    if (keep[t]) indices.insert(indices.end(), &mesh.indices[3 * t], &mesh.indices[3 * t] + 3);
  mesh.indices = std::move(indices);
}

}  // namespace hlod
