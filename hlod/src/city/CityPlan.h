#pragma once
// The plan of one city block: every random choice (street grid, buildings, windows, colours) made
// once, so that the geometry (BlockGeometry.cpp) and the texture (BlockTexture.cpp) agree on where
// each window is. Private to the city generator.
//
// Block-local coordinates (s, y, z) in metres: s along the street line (0..length), y from the
// street line into the block (facades face -y, the street), z up. BlockFrame maps them to city
// coordinates by a rotation about Z plus a translation.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "hlod/Mesh.h"

namespace hlod::city {

// splitmix64 (Steele, Lea, Flood 2014): tiny, fast, and the same numbers on every platform.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  double range(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Uniform integer in [lo, hi].
  int intRange(int lo, int hi) {
    return lo + static_cast<int>(next() % static_cast<std::uint64_t>(hi - lo + 1));
  }
  bool chance(double p) { return uniform() < p; }

 private:
  std::uint64_t state_;
};

// Hash of several values into one seed (splitmix64 finaliser over a running combination).
std::uint64_t hashSeed(std::uint64_t a, std::uint64_t b, std::uint64_t c = 0);

// Smooth value noise in [-1, 1] on a unit lattice.
double valueNoise(std::uint64_t seed, double x, double y);

struct BlockFrame {
  glm::dvec3 origin{0.0};  // (s, y, z) = (0, 0, 0) in city coordinates
  glm::dvec3 along{1, 0, 0};
  glm::dvec3 inward{0, 1, 0};
  double length = 0.0;         // street line length: buildings occupy s in [0, length]
  double depth = 0.0;          // buildings occupy y in [0, depth]
  double streetHalf = 0.0;     // the block's ground reaches y = -streetHalf (street centre)
  double sidewalk = 0.0;       // sidewalk y in [-sidewalk, depth], raised kCurbHeight
  double endLo = 0.0;          // ground s in [-endLo, length + endHi] (corner owners reach
  double endHi = 0.0;          // the middle of the side streets)
  double endSidewalkLo = 0.0;  // corner owners: the sidewalk reaches s in
  double endSidewalkHi = 0.0;  // [-endSidewalkLo, length + endSidewalkHi]
  // The east and west blocks also pave their half of the cell's courtyard, s in
  // [courtyardS0, courtyardS1] and y in [depth, courtyardY1], so that from above the sky does
  // not show through a cell; block boxes still only touch, never overlap.
  double courtyardS0 = 0.0, courtyardS1 = 0.0, courtyardY1 = 0.0;

  glm::dvec3 toCity(const glm::dvec3& local) const {
    return origin + local.x * along + local.y * inward + glm::dvec3(0, 0, local.z);
  }
  glm::dvec3 dirToCity(const glm::dvec3& local) const {
    return local.x * along + local.y * inward + glm::dvec3(0, 0, local.z);
  }
};

inline constexpr double kCurbHeight = 0.15;

// A pixel rectangle of the block texture.
struct Tile {
  int x = 0, y = 0, w = 0, h = 0;
};

struct RoofUnit {
  bool tank = false;  // water tank (cylinder on legs) or a box (stair house, AC unit)
  glm::dvec3 lo{0.0}, hi{0.0};
};

// Window layout classes for the texture painter.
enum class FacadePart { Wall, Glass, Frame, Ledge, Sign, Door };

struct BuildingPlan {
  double s0 = 0.0, width = 0.0;       // along the street
  double setback = 0.0, depth = 0.0;  // facade plane at y = setback, back at setback + depth
  int floors = 1;                     // ground floor + upper floors
  double groundHeight = 4.0, floorHeight = 3.2;
  double roofZ = 0.0;   // roof plane
  double topZ = 0.0;    // top of parapet/cornice: walls reach it
  int bays = 1;         // window columns on upper floors
  double margin = 1.0;  // plain wall at each end of the facade
  double windowWidth = 1.2, windowHeight = 1.6, sillZ = 0.9;  // sillZ: above the floor line
  int shopBays = 1;                                           // ground-floor shop windows
  double shopWidth = 3.0, shopBottom = 0.5, shopTop = 3.0;
  int doorBay = -1;  // ground-floor unit that is a door instead of a shop window
  bool sills = true, hoods = false, floorLedges = true;
  int mullions = 0;     // 0 none, 1 vertical, 2 cross
  int cornice = 0;      // 0 plain parapet, 1 stepped cornice, 2 overhanging slab
  double reveal = 0.2;  // window inset depth
  double noiseAmp = 0.02;
  std::uint64_t noiseSeed = 0;
  glm::vec3 wallColor{0.8f}, trimColor{0.9f}, glassColor{0.2f}, frameColor{0.9f},
      signColor{0.8f, 0.1f, 0.1f}, roofColor{0.3f};
  bool brick = false;
  std::vector<RoofUnit> roofUnits;
  Tile tile;

  double s1() const { return s0 + width; }
  double bayWidth() const { return (width - 2.0 * margin) / bays; }
  double shopBayWidth() const { return (width - 2.0 * margin) / shopBays; }
  double floorZ(int floor) const {  // floor 0 = ground floor
    return floor == 0 ? 0.0 : groundHeight + (floor - 1) * floorHeight;
  }
  // Window of bay b on upper floor f (f >= 1): s range and z range.
  glm::dvec4 window(int floor, int bay) const;
  // Shop window / door of ground-floor unit u.
  glm::dvec4 shopWindow(int unit) const;
  // What the facade shows at (s, z); used by the texture painter.
  FacadePart partAt(double s, double z) const;
  // Facade displacement noise (metres, towards the street) and its gradient.
  double displacement(double s, double z) const;
};

struct BlockPlan {
  std::uint64_t seed = 0;
  int index = 0;
  BlockFrame frame;
  std::vector<BuildingPlan> buildings;
  int textureWidth = 0, textureHeight = 0;
  Tile groundTile;
};

BlockFrame blockFrame(std::uint64_t seed, int index);
BlockPlan planBlock(std::uint64_t seed, int index, int textureSize);

// Texture coordinate mapping shared by geometry and painter (1 px inset against bleeding).
// Facade: left 3/4 of the building's tile; side walls: bottom of the right 1/4; roof: its top.
struct AtlasMap {
  int texW = 1, texH = 1;
  glm::vec2 facade(const BuildingPlan& b, double s, double z) const;
  glm::vec2 side(const BuildingPlan& b, double a, double aMax, double z) const;
  glm::vec2 roof(const BuildingPlan& b, double s, double y) const;
  glm::vec2 ground(const BlockFrame& f, const Tile& t, double s, double y) const;
  static Tile facadeRect(const Tile& t) { return {t.x, t.y, t.w * 3 / 4, t.h}; }
  static Tile sideRect(const Tile& t) {
    return {t.x + t.w * 3 / 4, t.y + t.h / 2, t.w - t.w * 3 / 4, t.h - t.h / 2};
  }
  static Tile roofRect(const Tile& t) {
    return {t.x + t.w * 3 / 4, t.y, t.w - t.w * 3 / 4, t.h / 2};
  }
  glm::vec2 inRect(const Tile& r, double fx, double fy) const;  // fx, fy in [0, 1]
};

Mesh buildBlockGeometry(const BlockPlan& plan);
Image paintBlockTexture(const BlockPlan& plan);

}  // namespace hlod::city
