// mergeMaterials: a tile's meshes as one node mesh, materials in one atlas
// (hlod/tiles/MergeMaterials.h).
#include "hlod/tiles/MergeMaterials.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace hlod::tiles {

namespace {

// Texels repeated around each block: linear filtering and the first mipmap levels stay inside.
constexpr int kGutter = 4;
// The side of an untextured colour's block.
constexpr int kSwatch = 4;

struct Material {
  const Image* texture;  // null: a flat colour
  glm::vec4 colour;
  bool operator<(const Material& o) const {
    return std::tie(texture, colour.r, colour.g, colour.b, colour.a) <
           std::tie(o.texture, o.colour.r, o.colour.g, o.colour.b, o.colour.a);
  }
};

bool textured(const Mesh& m) {
  return m.texture && !m.texture->empty() && m.texCoords.size() == m.positions.size();
}

void append(Mesh& dst, const Mesh& src, const std::vector<glm::vec3>& normals,
            const std::vector<glm::vec2>* uv) {
  const auto base = std::uint32_t(dst.positions.size());
  dst.positions.insert(dst.positions.end(), src.positions.begin(), src.positions.end());
  dst.normals.insert(dst.normals.end(), normals.begin(), normals.end());
  if (uv) dst.texCoords.insert(dst.texCoords.end(), uv->begin(), uv->end());
  for (std::uint32_t i : src.indices) dst.indices.push_back(base + i);
}

const std::vector<glm::vec3>& normalsOf(const Mesh& m, std::vector<glm::vec3>& scratch) {
  if (m.normals.size() == m.positions.size()) return m.normals;
  scratch = computeVertexNormals(m.positions, m.indices);
  return scratch;
}

}  // namespace

MergedMesh mergeMaterials(std::span<const Mesh> meshes) {
  MergedMesh out;
  if (meshes.empty()) return out;
  Mesh& merged = out.mesh;
  merged.name = meshes.front().name;
  merged.oneSided =
      std::all_of(meshes.begin(), meshes.end(), [](const Mesh& m) { return m.oneSided; });
  std::map<Material, std::size_t> materials;
  for (const Mesh& m : meshes)
    materials.try_emplace({textured(m) ? m.texture.get() : nullptr, m.baseColor}, materials.size());
  std::vector<glm::vec3> scratch;

  if (materials.size() == 1) {
    // One material: joined as they are (texture coordinates kept only when all have them).
    merged.baseColor = meshes.front().baseColor;
    const bool uv = std::all_of(meshes.begin(), meshes.end(), [](const Mesh& m) {
      return m.texCoords.size() == m.positions.size();
    });
    if (textured(meshes.front())) merged.texture = meshes.front().texture;
    for (const Mesh& m : meshes)
      append(merged, m, normalsOf(m, scratch), uv ? &m.texCoords : nullptr);
    return out;
  }

  // Blocks: each material's image (its texture times its colour, or a swatch of the colour),
  // placed on shelves of a square-ish atlas.
  struct Block {
    Image image;
    int x = 0, y = 0;  // where its texels start (inside the gutter)
  };
  std::vector<Block> blocks(materials.size());
  double area = 0.0;
  int widest = 0;
  for (const auto& [material, k] : materials) {
    Image& img = blocks[k].image;
    if (material.texture) {
      img = *material.texture;
      for (std::size_t i = 0; i < img.pixels.size(); ++i)
        img.pixels[i] = std::uint8_t(
            std::lround(img.pixels[i] * std::clamp(material.colour[int(i % 4)], 0.0f, 1.0f)));
    } else {
      img.width = img.height = kSwatch;
      img.pixels.resize(std::size_t(kSwatch) * kSwatch * 4);
      for (std::size_t i = 0; i < img.pixels.size(); ++i)
        img.pixels[i] =
            std::uint8_t(std::lround(255.0f * std::clamp(material.colour[int(i % 4)], 0.0f, 1.0f)));
    }
    area += double(img.width + 2 * kGutter) * double(img.height + 2 * kGutter);
    widest = std::max(widest, img.width + 2 * kGutter);
  }
  const int width = std::max(widest, int(std::ceil(std::sqrt(area))));
  std::vector<std::size_t> order(blocks.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return blocks[a].image.height > blocks[b].image.height;
  });
  int x = 0, y = 0, shelf = 0;
  for (std::size_t k : order) {
    const int w = blocks[k].image.width + 2 * kGutter, h = blocks[k].image.height + 2 * kGutter;
    if (x + w > width) {
      x = 0;
      y += shelf;
      shelf = 0;
    }
    blocks[k].x = x + kGutter;
    blocks[k].y = y + kGutter;
    x += w;
    shelf = std::max(shelf, h);
  }
  auto atlas = std::make_shared<Image>();
  atlas->width = width;
  atlas->height = y + shelf;
  atlas->pixels.assign(std::size_t(atlas->width) * std::size_t(atlas->height) * 4, 0);
  for (const Block& b : blocks)
    for (int ty = -kGutter; ty < b.image.height + kGutter; ++ty)
      for (int tx = -kGutter; tx < b.image.width + kGutter; ++tx) {
        const int sx = std::clamp(tx, 0, b.image.width - 1),
                  sy = std::clamp(ty, 0, b.image.height - 1);
        const std::uint8_t* s = &b.image.pixels[(std::size_t(sy) * b.image.width + sx) * 4];
        std::uint8_t* d = &atlas->pixels[(std::size_t(b.y + ty) * atlas->width + (b.x + tx)) * 4];
        std::copy(s, s + 4, d);
      }

  merged.texture = atlas;
  merged.baseColor = glm::vec4(1.0f);
  out.atlasBlocks = blocks.size();
  for (const Mesh& m : meshes) {
    const std::size_t k = materials.at({textured(m) ? m.texture.get() : nullptr, m.baseColor});
    const Block& b = blocks[k];
    std::vector<glm::vec2> uv(m.positions.size());
    bool wrapped = false;
    for (std::size_t v = 0; v < uv.size(); ++v) {
      // Texel centres of the block: (0,0) and (1,1) of the source map to its outer texels' edges.
      glm::vec2 t = textured(m) ? m.texCoords[v] : glm::vec2(0.5f);
      if (t.x < 0.0f || t.x > 1.0f || t.y < 0.0f || t.y > 1.0f) {
        wrapped = true;
        t -= glm::floor(t);
      }
      uv[v] = glm::vec2((float(b.x) + t.x * float(b.image.width)) / float(atlas->width),
                        (float(b.y) + t.y * float(b.image.height)) / float(atlas->height));
    }
    out.wrappedMeshes += wrapped && textured(m);
    append(merged, m, normalsOf(m, scratch), &uv);
  }
  return out;
}

}  // namespace hlod::tiles
