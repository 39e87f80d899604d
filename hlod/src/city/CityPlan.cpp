#include "city/CityPlan.h"

#include <algorithm>
#include <cmath>

namespace hlod::city {

namespace {

// Salts that keep the random streams of layout, cells and blocks independent.
constexpr std::uint64_t kSaltColumn = 0xC01u, kSaltRow = 0x50Du, kSaltCell = 0xCE11u,
                        kSaltBlock = 0xB10Cu;

// Street grid: grid line c (x = X(c)) has its own street width; column c its own pitch.
double columnPitch(std::uint64_t seed, int c) {
  return 150.0 + 90.0 * Rng(hashSeed(seed, kSaltColumn, static_cast<std::uint64_t>(c))).uniform();
}
double rowPitch(std::uint64_t seed, int r) {
  return 110.0 + 80.0 * Rng(hashSeed(seed, kSaltRow, static_cast<std::uint64_t>(r))).uniform();
}
double streetWidth(std::uint64_t seed, std::uint64_t salt, int line) {
  static constexpr double kWidths[] = {18.0, 22.0, 26.0, 32.0};
  Rng rng(hashSeed(seed, salt + 1, static_cast<std::uint64_t>(line)));
  return kWidths[rng.next() % 4];
}
double sidewalkWidth(double street) {
  return std::clamp(street * 0.17, 3.0, 5.0);
}

// Grid cell k in square shells: cells 0..m*m-1 fill an m x m square, so N*N cells make a square.
glm::ivec2 cellOf(int k) {
  int m = static_cast<int>(std::sqrt(static_cast<double>(k)));
  while (m * m > k) --m;
  while ((m + 1) * (m + 1) <= k) ++m;
  const int j = k - m * m;
  return j <= m ? glm::ivec2(m, j) : glm::ivec2(j - m - 1, m);
}

glm::vec3 jitter(Rng& rng, glm::vec3 c, float amount) {
  for (int i = 0; i < 3; ++i)
    c[i] = std::clamp(c[i] + static_cast<float>(rng.range(-amount, amount)), 0.0f, 1.0f);
  return c;
}

glm::vec3 pick(Rng& rng, std::initializer_list<glm::vec3> palette) {
  return *(palette.begin() + rng.next() % palette.size());
}

BuildingPlan planBuilding(Rng& rng, double s0, double width, double blockDepth) {
  BuildingPlan b;
  b.s0 = s0;
  b.width = width;
  b.setback = rng.chance(0.7) ? 0.0 : rng.range(0.3, 2.5);
  const double maxDepth = blockDepth - b.setback;
  b.depth = rng.range(std::min(10.0, maxDepth), maxDepth);

  const double kind = rng.uniform();
  b.floors = kind < 0.55  ? rng.intRange(2, 6)
             : kind < 0.9 ? rng.intRange(5, 10)
                          : rng.intRange(10, 22);
  b.groundHeight = rng.range(3.6, 5.2);
  b.floorHeight = rng.range(2.9, 3.8);
  b.roofZ = b.floorZ(b.floors) + rng.range(0.3, 1.2);
  b.topZ = b.roofZ + rng.range(0.5, 1.3);

  b.margin = std::min(rng.range(0.6, 1.8), width * 0.15);
  const double usable = width - 2.0 * b.margin;
  b.bays = std::max(1, static_cast<int>(std::lround(usable / rng.range(2.4, 4.2))));
  b.windowWidth = b.bayWidth() * rng.range(0.4, 0.7);
  b.windowHeight = b.floorHeight * rng.range(0.42, 0.62);
  b.sillZ = std::min(rng.range(0.7, 1.0), b.floorHeight - 0.35 - b.windowHeight);

  b.shopBays = std::max(1, static_cast<int>(std::lround(usable / rng.range(3.5, 7.0))));
  b.shopWidth = b.shopBayWidth() * rng.range(0.6, 0.85);
  b.shopBottom = rng.range(0.3, 0.7);
  b.shopTop = b.groundHeight - rng.range(0.8, 1.3);
  b.doorBay = rng.chance(0.5) ? rng.intRange(0, b.shopBays - 1) : -1;

  b.sills = rng.chance(0.6);
  b.hoods = rng.chance(0.3);
  b.floorLedges = rng.chance(0.5);
  b.mullions = rng.intRange(0, 2);
  b.cornice = rng.intRange(0, 2);
  b.reveal = rng.range(0.12, 0.35);
  b.noiseAmp = rng.range(0.01, 0.035);
  b.noiseSeed = rng.next();

  b.brick = rng.chance(0.35);
  b.wallColor = b.brick ? jitter(rng,
                                 pick(rng, {{0.56f, 0.27f, 0.19f},
                                            {0.46f, 0.30f, 0.22f},
                                            {0.62f, 0.38f, 0.28f},
                                            {0.52f, 0.22f, 0.18f}}),
                                 0.05f)
                        : jitter(rng,
                                 pick(rng, {{0.82f, 0.76f, 0.62f},
                                            {0.90f, 0.87f, 0.78f},
                                            {0.60f, 0.60f, 0.58f},
                                            {0.87f, 0.87f, 0.85f},
                                            {0.78f, 0.60f, 0.36f},
                                            {0.62f, 0.70f, 0.60f},
                                            {0.52f, 0.57f, 0.63f},
                                            {0.85f, 0.69f, 0.66f}}),
                                 0.06f);
  b.trimColor =
      jitter(rng, rng.chance(0.6) ? glm::vec3(0.92f, 0.90f, 0.85f) : b.wallColor * 0.75f, 0.04f);
  b.glassColor = jitter(rng,
                        pick(rng, {{0.16f, 0.22f, 0.30f},
                                   {0.22f, 0.28f, 0.34f},
                                   {0.12f, 0.16f, 0.20f},
                                   {0.25f, 0.33f, 0.42f}}),
                        0.03f);
  b.frameColor =
      rng.chance(0.5) ? glm::vec3(0.93f, 0.93f, 0.9f) : jitter(rng, {0.2f, 0.2f, 0.2f}, 0.05f);
  b.signColor = jitter(rng,
                       pick(rng, {{0.75f, 0.12f, 0.10f},
                                  {0.10f, 0.35f, 0.60f},
                                  {0.12f, 0.50f, 0.22f},
                                  {0.90f, 0.70f, 0.10f},
                                  {0.15f, 0.15f, 0.15f}}),
                       0.05f);
  b.roofColor = jitter(rng, {0.32f, 0.31f, 0.30f}, 0.05f);

  // Rooftop units stay inside the parapet (0.3 m) and on the roof plane.
  const int units = rng.intRange(0, 3);
  for (int i = 0; i < units; ++i) {
    RoofUnit u;
    u.tank = width > 10.0 && b.depth > 8.0 && rng.chance(0.25);
    const double sx = u.tank ? rng.range(2.4, 3.6) : rng.range(1.0, std::min(6.0, width * 0.4));
    const double sy = u.tank ? sx : rng.range(1.0, std::min(5.0, b.depth * 0.4));
    const double h = u.tank ? rng.range(3.5, 5.0) : rng.range(0.8, 3.0);
    if (sx + 1.0 > width || sy + 1.0 > b.depth) continue;
    const double x = rng.range(s0 + 0.5, s0 + width - 0.5 - sx);
    const double y = rng.range(b.setback + 0.5, b.setback + b.depth - 0.5 - sy);
    u.lo = {x, y, b.roofZ};
    u.hi = {x + sx, y + sy, b.roofZ + h};
    b.roofUnits.push_back(u);
  }
  return b;
}

bool inside(const glm::dvec4& r, double s, double z) {
  return s >= r.x && s <= r.y && z >= r.z && z <= r.w;
}

}  // namespace

std::uint64_t hashSeed(std::uint64_t a, std::uint64_t b, std::uint64_t c) {
  Rng r(a ^ 0x6A09E667F3BCC909ull);
  std::uint64_t h = r.next();
  h = Rng(h ^ b).next();
  return Rng(h ^ (c * 0x9E3779B97F4A7C15ull + 0x3C6EF372FE94F82Bull)).next();
}

double valueNoise(std::uint64_t seed, double x, double y) {
  const double fx = std::floor(x), fy = std::floor(y);
  const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy);
  auto lattice = [&](std::int64_t i, std::int64_t j) {
    // One multiply-xorshift round: plenty for noise, and this is the texture painter's hot spot.
    std::uint64_t h = seed ^ (static_cast<std::uint64_t>(i) * 0x9E3779B97F4A7C15ull) ^
                      (static_cast<std::uint64_t>(j) * 0xC2B2AE3D27D4EB4Full);
    h = (h ^ (h >> 29)) * 0xBF58476D1CE4E5B9ull;
    h ^= h >> 32;
    return static_cast<double>(h & 0xFFFFFF) / 8388607.5 - 1.0;
  };
  const double tx = x - fx, ty = y - fy;
  const double sx = tx * tx * (3.0 - 2.0 * tx), sy = ty * ty * (3.0 - 2.0 * ty);
  const double a = lattice(ix, iy) + (lattice(ix + 1, iy) - lattice(ix, iy)) * sx;
  const double b = lattice(ix, iy + 1) + (lattice(ix + 1, iy + 1) - lattice(ix, iy + 1)) * sx;
  return a + (b - a) * sy;
}

BlockFrame blockFrame(std::uint64_t seed, int index) {
  const int k = index / 4, side = index % 4;
  const glm::ivec2 cell = cellOf(k);
  double X0 = 0.0, Y0 = 0.0;
  for (int c = 0; c < cell.x; ++c) X0 += columnPitch(seed, c);
  for (int r = 0; r < cell.y; ++r) Y0 += rowPitch(seed, r);
  const double X1 = X0 + columnPitch(seed, cell.x), Y1 = Y0 + rowPitch(seed, cell.y);
  const double stW = streetWidth(seed, kSaltColumn, cell.x);
  const double stE = streetWidth(seed, kSaltColumn, cell.x + 1);
  const double stS = streetWidth(seed, kSaltRow, cell.y);
  const double stN = streetWidth(seed, kSaltRow, cell.y + 1);
  // The cell interior (the block of buildings) between the street centre lines' half widths.
  const double x0 = X0 + stW / 2, x1 = X1 - stE / 2, y0 = Y0 + stS / 2, y1 = Y1 - stN / 2;

  Rng rng(hashSeed(seed, kSaltCell, static_cast<std::uint64_t>(k)));
  const double dS = rng.range(14.0, 26.0), dE = rng.range(14.0, 26.0);
  const double dN = rng.range(14.0, 26.0), dW = rng.range(14.0, 26.0);

  // South and north own the whole width (and the street corners); east and west fit between.
  BlockFrame f;
  switch (side) {
    case 0:  // south: faces -Y
      f.origin = {x0, y0, 0};
      f.along = {1, 0, 0};
      f.inward = {0, 1, 0};
      f.length = x1 - x0;
      f.depth = dS;
      f.streetHalf = stS / 2;
      f.sidewalk = sidewalkWidth(stS);
      f.endLo = stW / 2;
      f.endHi = stE / 2;
      f.endSidewalkLo = sidewalkWidth(stW);
      f.endSidewalkHi = sidewalkWidth(stE);
      break;
    case 1:  // east: faces +X
      f.origin = {x1, y0 + dS, 0};
      f.along = {0, 1, 0};
      f.inward = {-1, 0, 0};
      f.length = (y1 - dN) - (y0 + dS);
      f.depth = dE;
      f.streetHalf = stE / 2;
      f.sidewalk = sidewalkWidth(stE);
      f.courtyardS1 = f.length;
      f.courtyardY1 = dE + 0.5 * ((x1 - x0) - dE - dW);
      break;
    case 2:  // north: faces +Y
      f.origin = {x1, y1, 0};
      f.along = {-1, 0, 0};
      f.inward = {0, -1, 0};
      f.length = x1 - x0;
      f.depth = dN;
      f.streetHalf = stN / 2;
      f.sidewalk = sidewalkWidth(stN);
      f.endLo = stE / 2;
      f.endHi = stW / 2;
      f.endSidewalkLo = sidewalkWidth(stE);
      f.endSidewalkHi = sidewalkWidth(stW);
      break;
    default:  // west: faces -X
      f.origin = {x0, y1 - dN, 0};
      f.along = {0, -1, 0};
      f.inward = {1, 0, 0};
      f.length = (y1 - dN) - (y0 + dS);
      f.depth = dW;
      f.streetHalf = stW / 2;
      f.sidewalk = sidewalkWidth(stW);
      f.courtyardS1 = f.length;
      f.courtyardY1 = dW + 0.5 * ((x1 - x0) - dE - dW);
      break;
  }
  return f;
}

BlockPlan planBlock(std::uint64_t seed, int index, int textureSize) {
  BlockPlan plan;
  plan.seed = seed;
  plan.index = index;
  plan.frame = blockFrame(seed, index);
  Rng rng(hashSeed(seed, kSaltBlock, static_cast<std::uint64_t>(index)));

  // A row of buildings along the street line, now and then an alley between two of them.
  const double L = plan.frame.length;
  double s = 0.0;
  while (L - s > 0.5) {
    double w = rng.chance(0.15) ? rng.range(30.0, 45.0) : rng.range(8.0, 30.0);
    if (L - s < w + 8.0) w = L - s;
    plan.buildings.push_back(planBuilding(rng, s, w, plan.frame.depth));
    s += w;
    if (L - s > 20.0 && rng.chance(0.08)) s += rng.range(2.0, 5.0);
  }

  // Texture atlas: one tile per building plus one for the ground.
  const int n = static_cast<int>(plan.buildings.size()) + 1;
  int cols = 1;
  while (cols * cols < n) ++cols;
  const int rows = (n + cols - 1) / cols;
  const int size = std::clamp(textureSize, 64, 4096);
  plan.textureWidth = plan.textureHeight = size;
  const int tw = size / cols, th = size / rows;
  for (int i = 0; i < n; ++i) {
    const Tile t{(i % cols) * tw, (i / cols) * th, tw, th};
    if (i + 1 < n)
      plan.buildings[static_cast<std::size_t>(i)].tile = t;
    else
      plan.groundTile = t;
  }
  return plan;
}

glm::dvec4 BuildingPlan::window(int floor, int bay) const {
  const double c = s0 + margin + (bay + 0.5) * bayWidth();
  const double z = floorZ(floor) + sillZ;
  return {c - windowWidth / 2, c + windowWidth / 2, z, z + windowHeight};
}

glm::dvec4 BuildingPlan::shopWindow(int unit) const {
  const double c = s0 + margin + (unit + 0.5) * shopBayWidth();
  if (unit == doorBay) {
    const double w = std::min(shopWidth, 1.6);
    return {c - w / 2, c + w / 2, 0.0, std::min(shopTop, 2.4)};
  }
  return {c - shopWidth / 2, c + shopWidth / 2, shopBottom, shopTop};
}

FacadePart BuildingPlan::partAt(double s, double z) const {
  constexpr double kFrame = 0.08;
  auto windowPart = [&](const glm::dvec4& r, int mull, bool door) {
    if (s - r.x < kFrame || r.y - s < kFrame || r.w - z < kFrame || (!door && z - r.z < kFrame))
      return FacadePart::Frame;
    const double cs = (r.x + r.y) / 2, cz = r.z + (r.w - r.z) * 0.62;
    if (mull >= 1 && std::abs(s - cs) < kFrame / 2) return FacadePart::Frame;
    if (mull >= 2 && std::abs(z - cz) < kFrame / 2) return FacadePart::Frame;
    return door ? FacadePart::Door : FacadePart::Glass;
  };

  if (z < groundHeight) {
    const double bw = shopBayWidth();
    const int u = std::clamp(static_cast<int>(std::floor((s - s0 - margin) / bw)), 0, shopBays - 1);
    const glm::dvec4 r = shopWindow(u);
    if (inside(r, s, z)) return windowPart(r, u == doorBay ? 0 : 1, u == doorBay);
  }
  // Belt course over the shop fronts, ledges at floor lines, cornice above the roof line.
  if (z >= groundHeight - 0.15 && z <= groundHeight + 0.2) return FacadePart::Ledge;
  if (z > roofZ) return cornice == 0 && z < topZ - 0.12 ? FacadePart::Wall : FacadePart::Ledge;
  if (z < groundHeight) {
    if (z > shopTop + 0.15 && z < groundHeight - 0.25 && s > s0 + margin && s < s1() - margin)
      return FacadePart::Sign;
    return FacadePart::Wall;
  }
  const int f = 1 + static_cast<int>(std::floor((z - groundHeight) / floorHeight));
  if (floorLedges && f >= 2 && z - floorZ(f) < 0.1) return FacadePart::Ledge;
  if (floorLedges && f + 1 < floors && floorZ(f + 1) - z < 0.06) return FacadePart::Ledge;
  if (f < floors) {
    const int bay =
        std::clamp(static_cast<int>(std::floor((s - s0 - margin) / bayWidth())), 0, bays - 1);
    const glm::dvec4 r = window(f, bay);
    if (inside(r, s, z)) return windowPart(r, mullions, false);
    if (sills && z < r.z && z > r.z - 0.12 && s > r.x - 0.1 && s < r.y + 0.1)
      return FacadePart::Ledge;
    if (hoods && z > r.w && z < r.w + 0.2 && s > r.x - 0.12 && s < r.y + 0.12)
      return FacadePart::Ledge;
  }
  return FacadePart::Wall;
}

double BuildingPlan::displacement(double s, double z) const {
  // Tapers to zero at the facade's edges and at the band seam, so that it meets the side walls,
  // the parapet top and the ground floor without cracks.
  const double edge = std::min({s - s0, s1() - s, z, topZ - z, std::abs(z - groundHeight)}) / 0.3;
  const double taper = std::clamp(edge, 0.0, 1.0);
  if (taper <= 0.0) return 0.0;
  const double n = valueNoise(noiseSeed, s / 1.3, z / 1.3) +
                   0.5 * valueNoise(noiseSeed ^ 0x5555u, s / 0.45, z / 0.45);
  return noiseAmp * taper * n;
}

glm::vec2 AtlasMap::inRect(const Tile& r, double fx, double fy) const {
  fx = std::clamp(fx, 0.0, 1.0);
  fy = std::clamp(fy, 0.0, 1.0);
  const double px = r.x + 1.0 + fx * (r.w - 2.0), py = r.y + 1.0 + fy * (r.h - 2.0);
  return {static_cast<float>(px / texW), static_cast<float>(py / texH)};
}

glm::vec2 AtlasMap::facade(const BuildingPlan& b, double s, double z) const {
  return inRect(facadeRect(b.tile), (s - b.s0) / b.width, (b.topZ - z) / b.topZ);
}

glm::vec2 AtlasMap::side(const BuildingPlan& b, double a, double aMax, double z) const {
  return inRect(sideRect(b.tile), a / aMax, (b.topZ - z) / b.topZ);
}

glm::vec2 AtlasMap::roof(const BuildingPlan& b, double s, double y) const {
  return inRect(roofRect(b.tile), (s - b.s0) / b.width, (y - b.setback) / b.depth);
}

glm::vec2 AtlasMap::ground(const BlockFrame& f, const Tile& t, double s, double y) const {
  return inRect(t, (s + f.endLo) / (f.length + f.endLo + f.endHi),
                (y + f.streetHalf) / (f.streetHalf + f.depth));
}

}  // namespace hlod::city
