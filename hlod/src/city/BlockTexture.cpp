// The block's texture atlas: one tile per building (facade, side wall, roof) and one for the
// ground. The facade is painted from the same plan, through the same mapping, as the geometry,
// so that painted window panes land on the recessed panes and ledges on the ledge boxes.
#include <algorithm>
#include <cmath>

#include "city/CityPlan.h"

namespace hlod::city {

namespace {

// A hash of an integer cell in [-1, 1].
float cellHash(std::uint64_t seed, int x, int y) {
  std::uint64_t h = seed ^ (static_cast<std::uint64_t>(x) * 0x9E3779B97F4A7C15ull) ^
                    (static_cast<std::uint64_t>(y) * 0xC2B2AE3D27D4EB4Full);
  h = (h ^ (h >> 31)) * 0xBF58476D1CE4E5B9ull;
  h ^= h >> 29;
  return static_cast<float>(h & 0xFFFF) / 32767.5f - 1.0f;
}

class Painter {
 public:
  explicit Painter(const BlockPlan& plan)
      : plan_(plan), seed_(hashSeed(plan.seed, 0x7E7, plan.index)) {
    img_.width = plan.textureWidth;
    img_.height = plan.textureHeight;
    img_.pixels.assign(static_cast<std::size_t>(img_.width) * img_.height * 4, 0);
    // Unused atlas space: neutral grey, never sampled.
    for (std::size_t i = 0; i < img_.pixels.size(); i += 4) {
      img_.pixels[i] = img_.pixels[i + 1] = img_.pixels[i + 2] = 128;
      img_.pixels[i + 3] = 255;
    }
  }

  Image paint() {
    for (const auto& b : plan_.buildings) {
      facade(b);
      side(b);
      roof(b);
    }
    ground();
    return std::move(img_);
  }

 private:
  const BlockPlan& plan_;
  std::uint64_t seed_;
  Image img_;

  void put(int x, int y, glm::vec3 c) {
    std::uint8_t* p = &img_.pixels[(static_cast<std::size_t>(y) * img_.width + x) * 4];
    for (int i = 0; i < 3; ++i)
      p[i] = static_cast<std::uint8_t>(std::clamp(c[i], 0.0f, 1.0f) * 255.0f + 0.5f);
    p[3] = 255;
  }

  // Calls fn(x, y, fx, fy) for every pixel of rect r with (fx, fy) the inverse of
  // AtlasMap::inRect at the pixel centre.
  template <class Fn>
  void forRect(const Tile& r, const Fn& fn) {
    for (int y = r.y; y < r.y + r.h; ++y)
      for (int x = r.x; x < r.x + r.w; ++x) {
        const double fx = (x + 0.5 - r.x - 1.0) / (r.w - 2.0);
        const double fy = (y + 0.5 - r.y - 1.0) / (r.h - 2.0);
        fn(x, y, std::clamp(fx, 0.0, 1.0), std::clamp(fy, 0.0, 1.0));
      }
  }

  // Fine variation in metres (0.4 m lattice), not per pixel: per-pixel noise does not compress,
  // so it makes the PNGs larger and their encoding slower, and cannot be seen at 10-20 texels a
  // metre anyway.
  float grain(double a, double b) const {
    return static_cast<float>(valueNoise(seed_, a * 2.5, b * 2.5));
  }

  glm::vec3 wall(const BuildingPlan& b, double s, double z, float g) const {
    float shade = 1.0f +
                  0.07f * static_cast<float>(valueNoise(b.noiseSeed ^ 0xA11, s / 2.5, z / 2.5)) +
                  0.04f * g;
    if (b.brick) {
      // Bands of brick courses (0.3 m), each its own tone: bricks themselves are below a texel.
      shade += 0.05f * cellHash(b.noiseSeed, static_cast<int>(std::floor(z / 0.3)), 3);
    }
    if (z < 1.0) shade *= static_cast<float>(0.85 + 0.15 * z);  // street grime
    return b.wallColor * shade;
  }

  // The look of one opening: dark, lit (warm) or curtained. Cached: consecutive pixels of a
  // row mostly fall in the same opening, and the hash is the costly part.
  struct Look {
    const BuildingPlan* building = nullptr;
    int id = -1;
    double z0 = 0.0, z1 = 1.0, look = 0.0, curtain = 1.0;
  };
  Look look_;

  glm::vec3 glass(const BuildingPlan& b, double s, double z, float g) {
    int id;
    glm::dvec4 r;
    if (z < b.groundHeight) {
      id = std::clamp(static_cast<int>(std::floor((s - b.s0 - b.margin) / b.shopBayWidth())), 0,
                      b.shopBays - 1);
      r = b.shopWindow(id);
    } else {
      const int f = 1 + static_cast<int>(std::floor((z - b.groundHeight) / b.floorHeight));
      const int bay = std::clamp(static_cast<int>(std::floor((s - b.s0 - b.margin) / b.bayWidth())),
                                 0, b.bays - 1);
      id = f * 1000 + bay;
      r = b.window(f, bay);
    }
    if (look_.building != &b || look_.id != id) {
      Rng rng(hashSeed(b.noiseSeed, 0x6A55, static_cast<std::uint64_t>(id)));
      look_ = {&b, id, r.z, r.w, rng.uniform(), 0.8 + 0.2 * rng.uniform()};
    }
    // A sky reflection brightening towards the top of the pane.
    const float t = static_cast<float>(
        std::clamp((z - look_.z0) / std::max(look_.z1 - look_.z0, 0.1), 0.0, 1.0));
    glm::vec3 c = b.glassColor + glm::vec3(0.10f, 0.13f, 0.16f) * t;
    if (look_.look < 0.08)
      c = glm::vec3(0.85f, 0.75f, 0.45f) * (0.85f + 0.15f * t);
    else if (look_.look < 0.3 && t > 0.55f)
      c = glm::vec3(0.78f, 0.74f, 0.66f) * static_cast<float>(look_.curtain);
    return c * (1.0f + 0.03f * g);
  }

  void facade(const BuildingPlan& b) {
    forRect(AtlasMap::facadeRect(b.tile), [&](int x, int y, double fx, double fy) {
      const double s = b.s0 + fx * b.width, z = b.topZ - fy * b.topZ;
      const float g = grain(s, z), n = 0.03f * g;
      glm::vec3 c;
      switch (b.partAt(s, z)) {
        case FacadePart::Wall:
          c = wall(b, s, z, g);
          break;
        case FacadePart::Glass:
          c = glass(b, s, z, g);
          break;
        case FacadePart::Frame:
          c = b.frameColor * (1.0f + n);
          break;
        case FacadePart::Ledge:
          c = b.trimColor * (0.97f + n);
          break;
        case FacadePart::Door:
          c = glm::vec3(0.30f, 0.20f, 0.12f) * (1.0f + 2 * n);
          break;
        case FacadePart::Sign: {
          // Letters: light blocks in the middle of the sign band.
          const double zm = b.shopTop + 0.15 + (b.groundHeight - 0.25 - b.shopTop - 0.15) * 0.5;
          const bool letter =
              std::abs(z - zm) < 0.18 &&
              cellHash(b.noiseSeed, static_cast<int>(std::floor(s / 0.3)), 7) > 0.1f;
          c = letter ? glm::vec3(0.95f, 0.93f, 0.85f) : b.signColor * (1.0f + n);
          break;
        }
      }
      put(x, y, c);
    });
  }

  void side(const BuildingPlan& b) {
    forRect(AtlasMap::sideRect(b.tile), [&](int x, int y, double fx, double fy) {
      const double s = b.s0 + fx * b.width, z = b.topZ - fy * b.topZ;
      put(x, y, wall(b, s, z, grain(s, z)) * 0.92f);
    });
  }

  void roof(const BuildingPlan& b) {
    forRect(AtlasMap::roofRect(b.tile), [&](int x, int y, double fx, double fy) {
      const double s = b.s0 + fx * b.width, yy = b.setback + fy * b.depth;
      const float g = grain(s, yy);
      glm::vec3 c = b.roofColor * (1.0f + 0.12f * g);
      for (const auto& u : b.roofUnits)
        if (s >= u.lo.x && s <= u.hi.x && yy >= u.lo.y && yy <= u.hi.y)
          c = (u.tank ? glm::vec3(0.45f, 0.33f, 0.24f) : glm::vec3(0.62f, 0.62f, 0.60f)) *
              (1.0f + 0.05f * g);
      put(x, y, c);
    });
  }

  void ground() {
    const BlockFrame& f = plan_.frame;
    const double sa = -f.endSidewalkLo, sb = f.length + f.endSidewalkHi;
    forRect(plan_.groundTile, [&](int x, int y, double fx, double fy) {
      const double s = -f.endLo + fx * (f.length + f.endLo + f.endHi);
      const double yy = -f.streetHalf + fy * (f.streetHalf + f.depth);
      const float n = grain(s, yy);
      glm::vec3 c;
      if (yy >= -f.sidewalk && s >= sa && s <= sb) {
        // Concrete slabs with joints every 1.5 m; a lighter curb stone at the edge.
        const bool joint = std::fmod(s + 1000.0, 1.5) < 0.06 || std::fmod(yy + 1000.0, 1.5) < 0.06;
        c = yy < -f.sidewalk + 0.25 ? glm::vec3(0.72f, 0.71f, 0.68f)
                                    : glm::vec3(0.62f, 0.60f, 0.57f) * (joint ? 0.8f : 1.0f);
        c *= 1.0f + 0.05f * n;
      } else {
        c = glm::vec3(0.23f, 0.23f, 0.24f) * (1.0f + 0.15f * n);
        // Dashed centre line of the street (the block owns the half up to it).
        if (yy < -f.streetHalf + 0.15 && std::fmod(s + 1000.0, 9.0) < 3.0)
          c = glm::vec3(0.85f, 0.8f, 0.55f);
      }
      put(x, y, c);
    });
  }
};

}  // namespace

Image paintBlockTexture(const BlockPlan& plan) {
  return Painter(plan).paint();
}

}  // namespace hlod::city
