// Geometry of one city block from its plan: facades with window recesses, reveals, sills, hoods,
// mullions, ledges and cornices, displacement noise on the wall panels, closed building boxes
// with parapets and rooftop units, and the block's sidewalk and half of its street.
// Dense on purpose: the HLOD builder (Lakhia III-A) needs real detail to simplify.
#include <algorithm>
#include <cmath>

#include "city/CityPlan.h"

namespace hlod::city {

namespace {

// Largest wall panel edge (metres): sets the facade triangle density.
constexpr double kCell = 0.5;
constexpr double kPi = 3.14159265358979323846;

enum Face : unsigned { kNegX = 1, kPosX = 2, kNegY = 4, kPosY = 8, kNegZ = 16, kPosZ = 32 };

class Builder {
 public:
  Mesh mesh;

  std::uint32_t vertex(const glm::dvec3& p, const glm::dvec3& n, glm::vec2 uv) {
    mesh.positions.push_back(p);
    mesh.normals.push_back(glm::vec3(n));
    mesh.texCoords.push_back(uv);
    return static_cast<std::uint32_t>(mesh.positions.size() - 1);
  }

  // Emits a triangle wound counter-clockwise as seen from the side `facing` points to.
  void tri(std::uint32_t a, std::uint32_t b, std::uint32_t c, const glm::dvec3& facing) {
    const auto& p = mesh.positions;
    if (glm::dot(glm::cross(p[b] - p[a], p[c] - p[a]), facing) < 0.0) std::swap(b, c);
    mesh.indices.insert(mesh.indices.end(), {a, b, c});
  }

  // A quad p0 p1 p2 p3 (in order around its boundary) with one normal.
  void quad(const glm::dvec3 (&p)[4], const glm::dvec3& n, const glm::vec2 (&uv)[4]) {
    const std::uint32_t a = vertex(p[0], n, uv[0]), b = vertex(p[1], n, uv[1]);
    const std::uint32_t c = vertex(p[2], n, uv[2]), d = vertex(p[3], n, uv[3]);
    tri(a, b, c, n);
    tri(a, c, d, n);
  }

  // Axis-aligned box faces; uvOf maps a corner to its texture coordinate.
  template <class UvOf>
  void box(const glm::dvec3& lo, const glm::dvec3& hi, unsigned faces, const UvOf& uvOf) {
    auto face = [&](int axis, bool positive) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      glm::dvec3 n(0.0);
      n[axis] = positive ? 1.0 : -1.0;
      glm::dvec3 p[4];
      const double uu[4] = {lo[u], hi[u], hi[u], lo[u]}, vv[4] = {lo[v], lo[v], hi[v], hi[v]};
      for (int i = 0; i < 4; ++i) {
        p[i][axis] = positive ? hi[axis] : lo[axis];
        p[i][u] = uu[i];
        p[i][v] = vv[i];
      }
      quad(p, n, {uvOf(p[0]), uvOf(p[1]), uvOf(p[2]), uvOf(p[3])});
    };
    for (int axis = 0; axis < 3; ++axis) {
      if (faces & (1u << (2 * axis))) face(axis, false);
      if (faces & (1u << (2 * axis + 1))) face(axis, true);
    }
  }
};

// Sorted cut positions covering [lo, hi]: the keys inside, then every interval split into
// pieces no longer than kCell (or `cell`).
std::vector<double> cuts(std::vector<double> keys, double lo, double hi, double cell) {
  keys.push_back(lo);
  keys.push_back(hi);
  std::sort(keys.begin(), keys.end());
  std::vector<double> out;
  for (double k : keys) {
    if (k < lo || k > hi) continue;
    if (!out.empty() && k - out.back() < 0.01) continue;
    if (!out.empty()) {
      const double a = out.back();
      const int n = static_cast<int>(std::ceil((k - a) / cell - 1e-9));
      for (int i = 1; i < n; ++i) out.push_back(a + (k - a) * i / n);
    }
    out.push_back(k);
  }
  if (out.back() < hi) out.back() = hi;  // a last key closer than 1 cm to hi
  return out;
}

class BuildingGeometry {
 public:
  BuildingGeometry(Builder& out, const BuildingPlan& plan, const AtlasMap& atlas)
      : B(out), b(plan), A(atlas) {}

  void build() {
    // Ground floor: shop windows and maybe a door; upper floors: the window grid. The seam at
    // groundHeight is where the displacement is zero and the belt course sits.
    std::vector<glm::dvec4> shops;
    for (int u = 0; u < b.shopBays; ++u) shops.push_back(b.shopWindow(u));
    facadeBand(0.0, b.groundHeight, shops, {});
    std::vector<glm::dvec4> windows;
    std::vector<double> zKeys;
    for (int f = 1; f < b.floors; ++f) {
      zKeys.push_back(b.floorZ(f));
      for (int bay = 0; bay < b.bays; ++bay) windows.push_back(b.window(f, bay));
    }
    zKeys.push_back(b.roofZ);
    facadeBand(b.groundHeight, b.topZ, windows, zKeys);

    for (const auto& r : shops) pane(r, r.z <= 0.0 ? 0 : 1, r.z <= 0.0);
    for (const auto& r : windows) {
      pane(r, b.mullions, false);
      if (b.sills)
        facadeBox(r.x - 0.1, r.y + 0.1, r.z - 0.12, r.z, 0.1, kNegX | kPosX | kNegZ | kPosZ);
      if (b.hoods)
        facadeBox(r.x - 0.12, r.y + 0.12, r.w, r.w + 0.2, 0.15, kNegX | kPosX | kNegZ | kPosZ);
    }
    ledges();
    walls();
    roof();
  }

 private:
  Builder& B;
  const BuildingPlan& b;
  const AtlasMap& A;

  glm::vec2 facadeUv(const glm::dvec3& p) const { return A.facade(b, p.x, p.z); }

  // The displaced facade point at (s, z) and its normal (from the displacement's gradient).
  glm::dvec3 facadePoint(double s, double z) const {
    return {s, b.setback - b.displacement(s, z), z};
  }
  glm::dvec3 facadeNormal(double s, double z) const {
    constexpr double e = 0.01;
    const double ds = (b.displacement(s + e, z) - b.displacement(s - e, z)) / (2 * e);
    const double dz = (b.displacement(s, z + e) - b.displacement(s, z - e)) / (2 * e);
    // Surface y = setback - D(s, z); the outward (street-side) normal is (dD/ds, -1, dD/dz).
    return glm::normalize(glm::dvec3(ds, -1.0, dz));
  }

  // A structured grid of wall panels over [s0, s1] x [z0, z1] with holes for `openings`,
  // vertices shared inside the grid; a reveal quad on every grid edge between wall and opening.
  void facadeBand(double z0, double z1, const std::vector<glm::dvec4>& openings,
                  std::vector<double> zKeys) {
    std::vector<double> sKeys;
    for (const auto& r : openings) {
      sKeys.push_back(r.x);
      sKeys.push_back(r.y);
      zKeys.push_back(r.z);
      zKeys.push_back(r.w);
    }
    const std::vector<double> S = cuts(sKeys, b.s0, b.s1(), kCell);
    const std::vector<double> Z = cuts(zKeys, z0, z1, kCell);
    const std::size_t ns = S.size(), nz = Z.size();
    const std::size_t cs = ns - 1, cz = nz - 1;
    std::vector<char> hole(cs * cz, 0);
    for (std::size_t j = 0; j < cz; ++j)
      for (std::size_t i = 0; i < cs; ++i) {
        const double ms = (S[i] + S[i + 1]) / 2, mz = (Z[j] + Z[j + 1]) / 2;
        for (const auto& r : openings)
          if (ms > r.x && ms < r.y && mz > r.z && mz < r.w) hole[j * cs + i] = 1;
      }

    std::vector<std::uint32_t> vid(ns * nz, UINT32_MAX);
    auto v = [&](std::size_t i, std::size_t j) {
      std::uint32_t& id = vid[j * ns + i];
      if (id == UINT32_MAX)
        id = B.vertex(facadePoint(S[i], Z[j]), facadeNormal(S[i], Z[j]), A.facade(b, S[i], Z[j]));
      return id;
    };
    const glm::dvec3 out(0, -1, 0);
    for (std::size_t j = 0; j < cz; ++j)
      for (std::size_t i = 0; i < cs; ++i) {
        if (hole[j * cs + i]) continue;
        const auto a = v(i, j), c = v(i + 1, j), d = v(i + 1, j + 1), e = v(i, j + 1);
        B.tri(a, c, d, out);
        B.tri(a, d, e, out);
      }

    // Reveals: the recess sides, from the displaced facade edge back to the inset plane.
    const double back = b.setback + b.reveal;
    auto reveal = [&](std::size_t i0, std::size_t j0, std::size_t i1, std::size_t j1,
                      glm::dvec3 towardWall) {
      const glm::dvec3 f0 = facadePoint(S[i0], Z[j0]), f1 = facadePoint(S[i1], Z[j1]);
      const glm::dvec3 k0(S[i0], back, Z[j0]), k1(S[i1], back, Z[j1]);
      // Texture: the wall just outside the opening, as deep as the reveal.
      const glm::dvec3 o = towardWall * b.reveal;
      B.quad({f0, f1, k1, k0}, -towardWall,
             {A.facade(b, f0.x, f0.z), A.facade(b, f1.x, f1.z), A.facade(b, k1.x + o.x, k1.z + o.z),
              A.facade(b, k0.x + o.x, k0.z + o.z)});
    };
    auto isWall = [&](long i, long j) {
      if (i < 0 || j < 0 || i >= static_cast<long>(cs) || j >= static_cast<long>(cz)) return true;
      return !hole[static_cast<std::size_t>(j) * cs + static_cast<std::size_t>(i)];
    };
    for (std::size_t j = 0; j < cz; ++j)
      for (std::size_t i = 0; i < cs; ++i) {
        if (!hole[j * cs + i]) continue;
        const long li = static_cast<long>(i), lj = static_cast<long>(j);
        if (isWall(li - 1, lj)) reveal(i, j, i, j + 1, {-1, 0, 0});
        if (isWall(li + 1, lj)) reveal(i + 1, j, i + 1, j + 1, {1, 0, 0});
        if (isWall(li, lj - 1)) reveal(i, j, i + 1, j, {0, 0, -1});
        if (isWall(li, lj + 1)) reveal(i, j + 1, i + 1, j + 1, {0, 0, 1});
      }
  }

  // The glass (or door) at the back of an opening, with mullion/transom bars in front of it.
  void pane(const glm::dvec4& r, int mullions, bool door) {
    const double y = b.setback + b.reveal;
    const glm::dvec3 p[4] = {{r.x, y, r.z}, {r.y, y, r.z}, {r.y, y, r.w}, {r.x, y, r.w}};
    B.quad(p, {0, -1, 0}, {facadeUv(p[0]), facadeUv(p[1]), facadeUv(p[2]), facadeUv(p[3])});
    if (door) return;
    const auto uv = [this](const glm::dvec3& q) { return facadeUv(q); };
    const double cs = (r.x + r.y) / 2, cz = r.z + (r.w - r.z) * 0.62;
    if (mullions >= 1)
      B.box({cs - 0.04, y - 0.06, r.z}, {cs + 0.04, y, r.w}, kNegX | kPosX | kNegY, uv);
    if (mullions >= 2)
      B.box({r.x, y - 0.05, cz - 0.04}, {r.y, y, cz + 0.04}, kNegY | kNegZ | kPosZ, uv);
  }

  // A box on the facade: s and z ranges, protruding `out` towards the street; its back is
  // sunk 5 cm into the wall so that the displaced wall never shows a gap behind it.
  void facadeBox(double s0, double s1, double z0, double z1, double out, unsigned faces) {
    const auto uv = [this](const glm::dvec3& q) { return facadeUv(q); };
    B.box({s0, b.setback - out, z0}, {s1, b.setback + 0.05, z1}, faces | kNegY, uv);
  }

  void ledges() {
    const unsigned sides = kNegX | kPosX | kNegZ | kPosZ;
    facadeBox(b.s0, b.s1(), b.groundHeight - 0.15, b.groundHeight + 0.2, 0.18, sides);
    if (b.floorLedges)
      for (int f = 2; f < b.floors; ++f)
        facadeBox(b.s0, b.s1(), b.floorZ(f) - 0.06, b.floorZ(f) + 0.1, 0.08, sides);
    const double h = b.topZ - b.roofZ, top = b.topZ + 0.02;
    switch (b.cornice) {
      case 0:
        facadeBox(b.s0, b.s1(), b.topZ - 0.12, top, 0.05, sides);
        break;
      case 1:
        for (int k = 0; k < 3; ++k)
          facadeBox(b.s0, b.s1(), b.roofZ + k * h / 3, k == 2 ? top : b.roofZ + (k + 1) * h / 3,
                    0.1 * (k + 1), sides);
        break;
      default:
        facadeBox(b.s0, b.s1(), b.topZ - 0.25, top, 0.6, sides);
        for (int k = 0; k <= b.bays; ++k) {
          const double c = b.s0 + b.margin + k * b.bayWidth();
          facadeBox(c - 0.1, c + 0.1, b.topZ - 0.7, b.topZ - 0.25, 0.45, sides);
        }
        break;
    }
  }

  // Plain walls: the two sides and the back, one row per floor.
  void walls() {
    std::vector<double> zKeys;
    for (int f = 1; f <= b.floors; ++f) zKeys.push_back(b.floorZ(f));
    zKeys.push_back(b.roofZ);
    const std::vector<double> Z = cuts(zKeys, 0.0, b.topZ, 4.0);
    const std::vector<double> Y = cuts({}, b.setback, b.setback + b.depth, 3.0);
    const std::vector<double> S = cuts({}, b.s0, b.s1(), 3.0);
    const double yb = b.setback + b.depth;
    for (std::size_t j = 0; j + 1 < Z.size(); ++j) {
      const double z0 = Z[j], z1 = Z[j + 1];
      for (std::size_t i = 0; i + 1 < Y.size(); ++i) {
        const double y0 = Y[i], y1 = Y[i + 1];
        for (int side = 0; side < 2; ++side) {
          const double s = side ? b.s1() : b.s0;
          const glm::dvec3 p[4] = {{s, y0, z0}, {s, y1, z0}, {s, y1, z1}, {s, y0, z1}};
          glm::vec2 uv[4];
          for (int k = 0; k < 4; ++k) uv[k] = A.side(b, p[k].y - b.setback, b.depth, p[k].z);
          B.quad(p, {side ? 1.0 : -1.0, 0, 0}, uv);
        }
      }
      for (std::size_t i = 0; i + 1 < S.size(); ++i) {
        const glm::dvec3 p[4] = {
            {S[i], yb, z0}, {S[i + 1], yb, z0}, {S[i + 1], yb, z1}, {S[i], yb, z1}};
        glm::vec2 uv[4];
        for (int k = 0; k < 4; ++k) uv[k] = A.side(b, p[k].x - b.s0, b.width, p[k].z);
        B.quad(p, {0, 1, 0}, uv);
      }
    }
  }

  // Roof plane inside a parapet, the parapet's inner faces and top, and rooftop units.
  void roof() {
    constexpr double t = 0.3;
    const auto uv = [this](const glm::dvec3& q) { return A.roof(b, q.x, q.y); };
    const double sa = b.s0, sb = b.s1(), ya = b.setback, yb = b.setback + b.depth;
    const double si = sa + t, so = sb - t, yi = ya + t, yo = yb - t;
    const std::vector<double> S = cuts({}, si, so, 4.0), Y = cuts({}, yi, yo, 4.0);
    for (std::size_t j = 0; j + 1 < Y.size(); ++j)
      for (std::size_t i = 0; i + 1 < S.size(); ++i) {
        const glm::dvec3 p[4] = {{S[i], Y[j], b.roofZ},
                                 {S[i + 1], Y[j], b.roofZ},
                                 {S[i + 1], Y[j + 1], b.roofZ},
                                 {S[i], Y[j + 1], b.roofZ}};
        B.quad(p, {0, 0, 1}, {uv(p[0]), uv(p[1]), uv(p[2]), uv(p[3])});
      }
    // Parapet: a ring of four top strips and four inner faces.
    const double z0 = b.roofZ, z1 = b.topZ;
    auto q = [&](glm::dvec3 a, glm::dvec3 c, glm::dvec3 d, glm::dvec3 e, glm::dvec3 n) {
      const glm::dvec3 p[4] = {a, c, d, e};
      B.quad(p, n, {uv(a), uv(c), uv(d), uv(e)});
    };
    q({sa, ya, z1}, {sb, ya, z1}, {sb, yi, z1}, {sa, yi, z1}, {0, 0, 1});
    q({sa, yo, z1}, {sb, yo, z1}, {sb, yb, z1}, {sa, yb, z1}, {0, 0, 1});
    q({sa, yi, z1}, {si, yi, z1}, {si, yo, z1}, {sa, yo, z1}, {0, 0, 1});
    q({so, yi, z1}, {sb, yi, z1}, {sb, yo, z1}, {so, yo, z1}, {0, 0, 1});
    q({si, yi, z0}, {so, yi, z0}, {so, yi, z1}, {si, yi, z1}, {0, 1, 0});
    q({si, yo, z0}, {so, yo, z0}, {so, yo, z1}, {si, yo, z1}, {0, -1, 0});
    q({si, yi, z0}, {si, yo, z0}, {si, yo, z1}, {si, yi, z1}, {1, 0, 0});
    q({so, yi, z0}, {so, yo, z0}, {so, yo, z1}, {so, yi, z1}, {-1, 0, 0});

    for (const auto& u : b.roofUnits) {
      if (u.tank)
        tank(u, uv);
      else
        B.box(u.lo, u.hi, kNegX | kPosX | kNegY | kPosY | kPosZ, uv);
    }
  }

  // A water tank: four legs, a 12-sided barrel and a conical lid.
  template <class Uv>
  void tank(const RoofUnit& u, const Uv& uv) {
    constexpr int kSides = 12;
    const glm::dvec3 c = (u.lo + u.hi) * 0.5;
    const double r = (u.hi.x - u.lo.x) / 2, h = u.hi.z - u.lo.z;
    const double zLeg = u.lo.z + 0.35 * h, zTop = u.lo.z + 0.85 * h;
    for (int k = 0; k < 4; ++k) {
      const double a = kPi / 4 + k * kPi / 2;
      const glm::dvec3 l(c.x + 0.7 * r * std::cos(a), c.y + 0.7 * r * std::sin(a), u.lo.z);
      B.box({l.x - 0.08, l.y - 0.08, l.z}, {l.x + 0.08, l.y + 0.08, zLeg},
            kNegX | kPosX | kNegY | kPosY, uv);
    }
    auto ring = [&](int k, double z, double rr) {
      const double a = 2 * kPi * k / kSides;
      return glm::dvec3(c.x + rr * std::cos(a), c.y + rr * std::sin(a), z);
    };
    const glm::dvec3 apex(c.x, c.y, u.hi.z);
    for (int k = 0; k < kSides; ++k) {
      const glm::dvec3 a0 = ring(k, zLeg, r), a1 = ring(k + 1, zLeg, r);
      const glm::dvec3 b0 = ring(k, zTop, r), b1 = ring(k + 1, zTop, r);
      // Barrel side with smooth radial normals.
      const glm::dvec3 n0 = glm::normalize(glm::dvec3(a0.x - c.x, a0.y - c.y, 0));
      const glm::dvec3 n1 = glm::normalize(glm::dvec3(a1.x - c.x, a1.y - c.y, 0));
      const auto i0 = B.vertex(a0, n0, uv(a0)), i1 = B.vertex(a1, n1, uv(a1));
      const auto i2 = B.vertex(b1, n1, uv(b1)), i3 = B.vertex(b0, n0, uv(b0));
      const glm::dvec3 mid = glm::normalize(n0 + n1);
      B.tri(i0, i1, i2, mid);
      B.tri(i0, i2, i3, mid);
      // Bottom and lid, flat per facet.
      const glm::dvec3 down(0, 0, -1);
      const glm::dvec3 cb(c.x, c.y, zLeg);
      B.tri(B.vertex(cb, down, uv(cb)), B.vertex(a0, down, uv(a0)), B.vertex(a1, down, uv(a1)),
            down);
      const glm::dvec3 ln = glm::normalize(glm::cross(b1 - b0, apex - b0));
      const glm::dvec3 lid = ln.z < 0 ? -ln : ln;
      B.tri(B.vertex(b0, lid, uv(b0)), B.vertex(b1, lid, uv(b1)), B.vertex(apex, lid, uv(apex)),
            lid);
    }
  }
};

// The block's ground: a raised sidewalk in front of (and under) the buildings, its curb, and the
// asphalt out to the middle of the street (and of the side streets at the corners it owns).
void ground(Builder& B, const BlockPlan& plan, const AtlasMap& A) {
  const BlockFrame& f = plan.frame;
  const auto uv = [&](const glm::dvec3& q) { return A.ground(f, plan.groundTile, q.x, q.y); };
  const double sa = -f.endSidewalkLo, sb = f.length + f.endSidewalkHi;
  const double h = kCurbHeight, D = f.depth, sw = f.sidewalk;
  const std::vector<double> S = cuts({}, sa, sb, 10.0);
  for (std::size_t i = 0; i + 1 < S.size(); ++i) {
    B.box({S[i], -sw, 0.0}, {S[i + 1], D, h}, kNegY | kPosY | kPosZ, uv);
  }
  if (f.endSidewalkLo > 0) B.box({sa, -sw, 0.0}, {sa, D, h}, kNegX, uv);
  if (f.endSidewalkHi > 0) B.box({sb, -sw, 0.0}, {sb, D, h}, kPosX, uv);
  const double s0 = -f.endLo, s1 = f.length + f.endHi;
  const std::vector<double> SA = cuts({}, s0, s1, 10.0);
  for (std::size_t i = 0; i + 1 < SA.size(); ++i)
    B.box({SA[i], -f.streetHalf, 0.0}, {SA[i + 1], -sw, 0.0}, kPosZ, uv);
  if (sa > s0) B.box({s0, -sw, 0.0}, {sa, D, 0.0}, kPosZ, uv);
  if (s1 > sb) B.box({sb, -sw, 0.0}, {s1, D, 0.0}, kPosZ, uv);
  if (f.courtyardY1 > D && f.courtyardS1 > f.courtyardS0) {
    // Paved like the sidewalk: its texture row at the building line, stretched.
    const auto paved = [&](const glm::dvec3& q) { return uv({q.x, D, q.z}); };
    B.box({f.courtyardS0, D, 0.0}, {f.courtyardS1, f.courtyardY1, h}, kPosZ, paved);
  }
}

}  // namespace

Mesh buildBlockGeometry(const BlockPlan& plan) {
  Builder B;
  const AtlasMap atlas{plan.textureWidth, plan.textureHeight};
  for (const auto& building : plan.buildings) BuildingGeometry(B, building, atlas).build();
  ground(B, plan, atlas);

  // Block-local (s, y, z) to city coordinates: a rotation about Z and a translation, so
  // windings and unit normals carry over.
  Mesh& m = B.mesh;
  for (auto& p : m.positions) p = plan.frame.toCity(p);
  for (auto& n : m.normals) n = glm::vec3(glm::normalize(plan.frame.dirToCity(glm::dvec3(n))));
  return std::move(B.mesh);
}

}  // namespace hlod::city
