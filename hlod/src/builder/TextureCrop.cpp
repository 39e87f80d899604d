// Texture crop of a node (builder/TextureCrop.h).
#include "builder/TextureCrop.h"

#include <algorithm>
#include <cmath>

#include "builder/ImageResize.h"

namespace hlod {

TexelRect usedTexels(const Image& texture, std::span<const glm::vec2> texCoords) {
  TexelRect r{0, 0, texture.width, texture.height};
  glm::vec2 lo(1.0f), hi(0.0f);
  bool inUnit = !texCoords.empty();
  for (const auto& t : texCoords) {
    if (!(t.x >= 0.0f && t.x <= 1.0f && t.y >= 0.0f && t.y <= 1.0f)) inUnit = false;
    lo = glm::min(lo, t);
    hi = glm::max(hi, t);
  }
  if (!inUnit) return r;
  // One texel of margin keeps bilinear filtering at the crop's edge on the right texels.
  TexelRect c{std::max(0, int(std::floor(lo.x * texture.width)) - 1),
              std::max(0, int(std::floor(lo.y * texture.height)) - 1),
              std::min(texture.width, int(std::ceil(hi.x * texture.width)) + 1),
              std::min(texture.height, int(std::ceil(hi.y * texture.height)) + 1)};
  return c.x1 <= c.x0 || c.y1 <= c.y0 ? r : c;
}

void remapToRect(const Image& texture, const TexelRect& rect, std::vector<glm::vec2>& texCoords) {
  const int cw = rect.x1 - rect.x0, ch = rect.y1 - rect.y0;
  if (cw == texture.width && ch == texture.height) return;
  for (auto& t : texCoords) {
    t.x = (t.x * float(texture.width) - float(rect.x0)) / float(cw);
    t.y = (t.y * float(texture.height) - float(rect.y0)) / float(ch);
  }
}

std::shared_ptr<const Image> cropImage(const Image& texture, const TexelRect& rect, double factor) {
  const int cw = rect.x1 - rect.x0, ch = rect.y1 - rect.y0;
  const bool cropped = cw != texture.width || ch != texture.height;
  const double scale = factor > 1.0 ? 1.0 / std::sqrt(factor) : 1.0;
  const int w = std::min(cw, std::max(std::min(cw, kMinTextureSide), int(std::lround(cw * scale))));
  const int h = std::min(ch, std::max(std::min(ch, kMinTextureSide), int(std::lround(ch * scale))));
  if (!cropped && w == cw && h == ch) return std::make_shared<Image>(texture);
  Image crop;
  crop.width = cw;
  crop.height = ch;
  crop.pixels.resize(std::size_t(cw) * ch * 4);
  for (int y = 0; y < ch; ++y)
    std::copy_n(texture.pixels.begin() + (std::size_t(y + rect.y0) * texture.width + rect.x0) * 4,
                std::size_t(cw) * 4, crop.pixels.begin() + std::size_t(y) * cw * 4);
  if (w == cw && h == ch) return std::make_shared<Image>(std::move(crop));
  return std::make_shared<Image>(resizeImage(crop, w, h));
}

std::shared_ptr<const Image> prepareNodeTexture(const Image& texture,
                                                std::vector<glm::vec2>& texCoords, double factor) {
  if (texture.empty() || texture.pixels.size() != std::size_t(texture.width) * texture.height * 4)
    return nullptr;
  const TexelRect rect = usedTexels(texture, texCoords);
  remapToRect(texture, rect, texCoords);
  return cropImage(texture, rect, factor);
}

}  // namespace hlod
