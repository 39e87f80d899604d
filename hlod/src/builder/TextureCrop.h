#pragma once
// A node's texture: cropped to the texels the node's texture coordinates use and down-sampled by
// the node's simplification factor s, as Lakhia III-A down-samples a level's texture with its
// triangles (side / sqrt(s): the area by s; at least kMinTextureSide pixels, never enlarged).
// Where the crops of one level's nodes overlap, the builder shares one (kSharedTextureOverlap,
// HlodBuilder.h). Private to the builder.
#include <memory>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "hlod/Mesh.h"

namespace hlod {

constexpr int kMinTextureSide = 8;

// A rectangle of texels [x0, x1) x [y0, y1).
struct TexelRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  double area() const { return double(x1 - x0) * double(y1 - y0); }
};
// The texels that texCoords use, with one of margin: the whole texture when one of them lies
// outside [0,1] (wrapping) or there are none.
TexelRect usedTexels(const Image& texture, std::span<const glm::vec2> texCoords);

// Texture coordinates of the whole texture to those of its rect.
void remapToRect(const Image& texture, const TexelRect& rect, std::vector<glm::vec2>& texCoords);

// The rect of texture, box-filtered to about 1/sqrt(factor) of its side (at least
// kMinTextureSide pixels, never enlarged).
std::shared_ptr<const Image> cropImage(const Image& texture, const TexelRect& rect, double factor);

// Crops a texture to the texel rectangle that texCoords (all in [0,1]) use, rewriting texCoords
// to the crop, and box-filters it to about 1/sqrt(factor) of its side (at least kMinTextureSide
// pixels, never enlarged). Texture coordinates outside [0,1] (wrapping) keep the whole texture.
// Null for an empty texture or one whose pixels do not match its size.
std::shared_ptr<const Image> prepareNodeTexture(const Image& texture,
                                                std::vector<glm::vec2>& texCoords, double factor);

}  // namespace hlod
