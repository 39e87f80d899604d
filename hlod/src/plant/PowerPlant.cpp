// The procedural power plant's layout (hlod/plant/PowerPlant.h). Metres, Y up; x runs along the
// pipe racks (east), z across them (south): unit rows at z = row * kPitchZ, each row's rack
// south of it.
#include "hlod/plant/PowerPlant.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <functional>
#include <glm/gtc/quaternion.hpp>

#include "plant/PartShapes.h"

namespace hlod {

namespace {

using glm::dvec3;
using plant::Ring;
using plant::ShapeBuilder;
using plant::Straight;
using plant::Sweep;

// SplitMix64 (Steele, Lea and Flood 2014): a fixed sequence for a seed on every platform.
class Random {
 public:
  explicit Random(std::uint64_t seed) : s_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (s_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  double uniform(double lo, double hi) { return lo + (hi - lo) * double(next() >> 11) * 0x1p-53; }
  int below(int n) { return int(next() % std::uint64_t(n)); }

 private:
  std::uint64_t s_;
};

// The site's dimensions.
constexpr double kUnitWidth = 56.0, kUnitDepth = 40.0;  // a unit's plot (x, z)
constexpr double kPitchX = 60.0;                        // unit to unit along x
constexpr double kRackWidth = 12.0;                     // the rack corridor (z)
constexpr double kPitchZ = kUnitDepth + kRackWidth;     // row to row along z
constexpr double kCatwalk = 7.0;                        // the catwalks' level (top)
constexpr double kTier[2] = {10.0, 13.0};               // tops of the rack's pipe beams
constexpr double kBranchLevel = 11.6;                   // branches leave the rack here
constexpr double kLevels[3] = {7.0, 14.0, 21.0};        // a unit's walkway levels
constexpr double kFrameTop = 28.0;                      // a unit frame's last beams
constexpr double kShoe = 0.15;                          // a pipe shoe's height
constexpr double kGrating = 0.1;                        // walkway thickness
constexpr double kRailHeight = 1.1;
constexpr int kSlots[2] = {7, 6};                          // long runs per rack tier
constexpr double kRadii[5] = {0.1, 0.15, 0.2, 0.25, 0.3};  // pipe size classes
constexpr int kObjectsPerUnit = 2000;                      // about, with its rack share

enum Part {
  Ground,
  Steam,
  Water,
  Oil,
  Valve,
  Bolt,
  Bracket,
  Frame,
  Walkway,
  Stairs,
  Railing,
  Boiler,
  Tank,
  kParts
};
const GltfMaterial kMaterials[kParts] = {
    {"ground", {0.50f, 0.50f, 0.46f, 1.0f}, 0.0f, 0.95f},
    {"pipe-steam", {0.72f, 0.72f, 0.70f, 1.0f}, 0.6f, 0.45f},
    {"pipe-water", {0.22f, 0.52f, 0.34f, 1.0f}, 0.2f, 0.6f},
    {"pipe-oil", {0.55f, 0.40f, 0.18f, 1.0f}, 0.2f, 0.6f},
    {"valve", {0.78f, 0.12f, 0.10f, 1.0f}, 0.3f, 0.5f},
    {"bolt", {0.22f, 0.22f, 0.24f, 1.0f}, 0.8f, 0.4f},
    {"bracket", {0.85f, 0.58f, 0.10f, 1.0f}, 0.3f, 0.6f},
    {"frame", {0.20f, 0.32f, 0.55f, 1.0f}, 0.4f, 0.6f},
    {"walkway", {0.42f, 0.44f, 0.46f, 1.0f}, 0.5f, 0.7f},
    {"stairs", {0.90f, 0.75f, 0.12f, 1.0f}, 0.3f, 0.6f},
    {"railing", {0.95f, 0.82f, 0.10f, 1.0f}, 0.3f, 0.6f},
    {"boiler", {0.80f, 0.80f, 0.78f, 1.0f}, 0.3f, 0.5f},
    {"tank", {0.93f, 0.93f, 0.90f, 1.0f}, 0.2f, 0.5f},
};

// The rotation that takes +X to ex and +Y to ey (orthonormal).
glm::dquat frame(const dvec3& ex, const dvec3& ey) {
  return glm::normalize(glm::quat_cast(glm::dmat3(ex, ey, glm::cross(ex, ey))));
}

class PlantBuilder {
 public:
  explicit PlantBuilder(const PlantOptions& o) : o_(o), random_(o.seed) {
    for (const GltfMaterial& m : kMaterials) scene_.materials.push_back(m);
    scene_.generator = "hlodr plant";
    seg_ = std::max(8, int(std::lround(64.0 * o.detail)));
    step_ = 0.3 / o.detail;
    bendRings_ = std::max(2, int(std::lround(16.0 * o.detail)));
  }

  Plant build();

 private:
  // ---- scene bookkeeping ----
  std::uint32_t group(const std::string& name) {
    scene_.nodes.push_back({name, -1, dvec3(0.0), glm::dquat(1, 0, 0, 0), dvec3(1.0), {}});
    scene_.roots.push_back(std::uint32_t(scene_.nodes.size() - 1));
    return scene_.roots.back();
  }
  std::uint32_t addMesh(GltfMesh mesh, Part part) {
    mesh.material = std::uint32_t(part);
    scene_.meshes.push_back(std::move(mesh));
    Aabb box;
    for (const glm::vec3& p : scene_.meshes.back().positions) box.extend(dvec3(p));
    meshBoxes_.push_back(box);
    return std::uint32_t(scene_.meshes.size() - 1);
  }
  // An object: a node of the group with the mesh placed.
  void place(std::uint32_t group, const std::string& name, std::uint32_t mesh,
             const dvec3& t = dvec3(0.0), const glm::dquat& r = glm::dquat(1, 0, 0, 0),
             const dvec3& s = dvec3(1.0)) {
    const auto index = std::uint32_t(scene_.nodes.size());
    scene_.nodes.push_back({name + "-" + std::to_string(index), std::int32_t(mesh), t, r, s, {}});
    scene_.nodes[group].children.push_back(index);
    const GltfMesh& m = scene_.meshes[mesh];
    const std::uint64_t tris = m.indices.size() / 3;
    ++summary_.objects;
    summary_.triangles += tris;
    auto& type = summary_.byType[kMaterials[m.material].name];
    ++type.first;
    type.second += tris;
    const Aabb& b = meshBoxes_[mesh];
    for (int k = 0; k < 8; ++k) {
      const dvec3 c((k & 1) ? b.max.x : b.min.x, (k & 2) ? b.max.y : b.min.y,
                    (k & 4) ? b.max.z : b.min.z);
      summary_.bounds.extend(t + r * (s * c));
    }
  }
  // A mesh of its own at its place (pipes, railings, walkways): made by `make`.
  void unique(std::uint32_t group, const std::string& name, Part part,
              const std::function<void(ShapeBuilder&)>& make) {
    GltfMesh mesh;
    mesh.name = name;
    ShapeBuilder b(mesh);
    make(b);
    place(group, name, addMesh(std::move(mesh), part));
  }

  // ---- instanced meshes, made on first use ----
  std::uint32_t shared(const std::string& key, Part part,
                       const std::function<void(ShapeBuilder&)>& make) {
    auto it = shared_.find(key);
    if (it != shared_.end()) return it->second;
    GltfMesh mesh;
    mesh.name = key;
    ShapeBuilder b(mesh);
    make(b);
    return shared_[key] = addMesh(std::move(mesh), part);
  }
  std::uint32_t columnMesh() {
    return shared("column", Frame, [](ShapeBuilder& b) { b.iBeam(0.4, 0.4, 0.03, 0.02); });
  }
  std::uint32_t beamMesh() {
    return shared("beam", Frame, [](ShapeBuilder& b) { b.iBeam(0.4, 0.2, 0.025, 0.015); });
  }
  // A bolt along +X through a flange pair of half-thickness t for pipes of class c.
  std::uint32_t boltMesh(int c) {
    return shared("bolt-" + std::to_string(c), Bolt, [&](ShapeBuilder& b) {
      const double d = 0.016 + 0.04 * kRadii[c], len = 2.0 * flangeHalf(c) + 2.2 * d;
      const int sides = std::max(6, seg_ / 6);
      b.cylinder({-len / 2, 0, 0}, {len / 2 + 0.6 * d, 0, 0}, d / 2, sides);
      b.prism({-len / 2 - 0.7 * d, 0, 0}, {-len / 2, 0, 0}, 0.9 * d, 6);  // head
      b.prism({len / 2 - 0.8 * d, 0, 0}, {len / 2, 0, 0}, 0.9 * d, 6);    // nut
    });
  }
  // A gate valve on a pipe of class c along +X, its bonnet and handwheel up +Y.
  std::uint32_t valveMesh(int c) {
    return shared("valve-" + std::to_string(c), Valve, [&](ShapeBuilder& b) {
      const double r = kRadii[c];
      b.dome({0, 0, 0}, {1, 0, 0}, 1.5 * r, 1.3 * r, seg_ / 2, std::max(3, seg_ / 8));
      b.dome({0, 0, 0}, {-1, 0, 0}, 1.5 * r, 1.3 * r, seg_ / 2, std::max(3, seg_ / 8));
      for (double x : {-1.4 * r, 1.4 * r})
        b.flange({x, 0, 0}, {1, 0, 0}, {0, 1, 0}, r, flangeRadius(c), flangeHalf(c), seg_ / 2);
      b.cylinder({0, 1.2 * r, 0}, {0, 3.0 * r, 0}, 0.55 * r, seg_ / 2);  // bonnet
      b.cylinder({0, 3.0 * r, 0}, {0, 3.8 * r, 0}, 0.08 * r + 0.01, 8);  // stem
      const double wheel = 1.3 * r + 0.05;
      b.torus({0, 3.7 * r, 0}, {0, 1, 0}, wheel, 0.06 * r + 0.008, seg_ / 2, 8);
      for (int k = 0; k < 4; ++k) {
        const double a = M_PI / 4.0 * (2 * k + 1);
        b.cylinder({0, 3.7 * r, 0}, {wheel * std::cos(a), 3.7 * r, wheel * std::sin(a)},
                   0.03 * r + 0.005, 6);
      }
    });
  }
  // A pipe shoe under a pipe of class c (its centre at the origin, along +X), with a U-bolt.
  std::uint32_t shoeMesh(int c) {
    return shared("shoe-" + std::to_string(c), Bracket, [&](ShapeBuilder& b) {
      const double r = kRadii[c], w = 0.6 * r + 0.05;
      b.box({-0.15, -r - kShoe, -w}, {0.15, -r - kShoe + 0.02, w});
      for (double z : {-0.3 * r, 0.3 * r})
        b.box({-0.12, -r - kShoe + 0.02, z - 0.008}, {0.12, -0.5 * r, z + 0.008});
      b.torus({0, 0, 0}, {1, 0, 0}, r + 0.012, 0.008, seg_ / 2, 6);
    });
  }
  // A stair flight along +X from 0 to 9.3, rising 7 m in 28 steps, 1.8 m wide along +Z.
  std::uint32_t flightMesh() {
    return shared("stair-flight", Stairs, [&](ShapeBuilder& b) {
      const int steps = 28;
      const double going = 9.3 / steps, rise = 7.0 / steps;
      const dvec3 slope = glm::normalize(dvec3(9.3, 7.0, 0.0));
      const dvec3 normal = glm::cross(dvec3(0, 0, 1), slope);
      // Stringers: their foot starts far enough up the slope to stand on the floor below.
      for (double z : {0.0, 1.75})
        b.box({0.25 * 9.3 / 7.0, -0.25, z}, {glm::length(dvec3(9.3, 7.0, 0.0)), 0.05, z + 0.05},
              dvec3(0.0), slope, normal, {0, 0, 1});
      for (int k = 0; k < steps; ++k)
        b.box({k * going, (k + 1) * rise - 0.04, 0.05},
              {(k + 1) * going + 0.02, (k + 1) * rise, 1.75});
      for (double z : {0.025, 1.775})
        b.cylinder({0.0, 1.0, z}, {9.3, 8.0, z}, 0.025, std::max(6, seg_ / 8));
    });
  }
  double flangeRadius(int c) const { return 1.5 * kRadii[c] + 0.05; }
  double flangeHalf(int c) const { return 0.02 + 0.05 * kRadii[c]; }
  int boltCount(int c) const { return c < 2 ? 8 : c < 4 ? 12 : 16; }

  // ---- parts ----
  void member(const std::string& name, const dvec3& a, const dvec3& b, bool column);
  void bolts(const dvec3& c, const dvec3& d, const dvec3& u, int cls);
  void valve(const dvec3& c, const dvec3& d, int cls);
  void pipe(const std::string& name, Part service, int cls, const std::vector<dvec3>& points,
            bool capStart, bool capEnd, double flangeEvery, double flangeOffset, double valveEvery,
            bool shoesOnPortals);
  void walkway(const std::string& name, const dvec3& lo, const dvec3& hi);
  void railing(const std::string& name, const dvec3& a, const dvec3& b);
  void unit(int index, const dvec3& origin);
  void rack(int row, double x0, double x1);
  void longRuns();
  void ground();

  const PlantOptions& o_;
  Random random_;
  GltfScene scene_;
  PlantSummary summary_;
  std::vector<Aabb> meshBoxes_;
  std::map<std::string, std::uint32_t> shared_;
  int seg_ = 64, bendRings_ = 16;
  double step_ = 0.3;
  int columns_ = 1, rows_ = 1, units_ = 1;
  std::uint32_t structure_ = 0, equipment_ = 0, piping_ = 0, valves_ = 0, fasteners_ = 0,
                access_ = 0, site_ = 0;
  std::vector<double> portalX_;  // the racks' portal positions along x
};

void PlantBuilder::member(const std::string& name, const dvec3& a, const dvec3& b, bool column) {
  const dvec3 d = b - a;
  const double len = glm::length(d);
  const dvec3 ex = d / len;
  const dvec3 ey = std::abs(ex.y) > 0.9 ? dvec3(-1, 0, 0) : dvec3(0, 1, 0);
  place(structure_, name, column ? columnMesh() : beamMesh(), a, frame(ex, ey), dvec3(len, 1, 1));
}

void PlantBuilder::bolts(const dvec3& c, const dvec3& d, const dvec3& u, int cls) {
  const dvec3 v = glm::cross(d, u);
  const int n = boltCount(cls);
  const double radius = 0.5 * (kRadii[cls] + flangeRadius(cls));
  for (int k = 0; k < n; ++k) {
    const double a = 2.0 * M_PI * (k + 0.5) / n;
    const dvec3 e = u * std::cos(a) + v * std::sin(a);
    place(fasteners_, "bolt", boltMesh(cls), c + e * radius, frame(d, e));
  }
}

void PlantBuilder::valve(const dvec3& c, const dvec3& d, int cls) {
  // Handwheel up on a level pipe; on a riser, turned out of the way along -z.
  const dvec3 up = std::abs(d.y) > 0.9 ? dvec3(0, 0, -1) : dvec3(0, 1, 0);
  place(valves_, "valve", valveMesh(cls), c, frame(d, up));
  const double x = 1.4 * kRadii[cls];
  const dvec3 u = plant::perpendicular(d);
  bolts(c - d * x, d, u, cls);
  bolts(c + d * x, d, u, cls);
}

void PlantBuilder::pipe(const std::string& name, Part service, int cls,
                        const std::vector<dvec3>& points, bool capStart, bool capEnd,
                        double flangeEvery, double flangeOffset, double valveEvery,
                        bool shoesOnPortals) {
  const double r = kRadii[cls];
  const Sweep sweep = plant::sweepPolyline(points, 3.0 * r, step_, bendRings_);
  // Where flanges and valves go along the straights, at least a metre from their ends.
  struct Fitting {
    dvec3 c, d, u;
    bool valve;
  };
  std::vector<Fitting> fittings;
  double walked = flangeOffset;
  for (const Straight& s : sweep.straights) {
    const double len = s.length();
    for (double at = std::fmod(walked, flangeEvery); at < len; at += flangeEvery) {
      if (at < 1.0 || at > len - 1.0) continue;
      const bool isValve = valveEvery > 0.0 && random_.uniform(0.0, 1.0) < flangeEvery / valveEvery;
      fittings.push_back({s.a + s.dir * at, s.dir, s.u, isValve});
    }
    walked = std::fmod(walked + len, flangeEvery);
  }
  // The ends: a blind flange closing the start or end, its bolts with the others.
  const Ring& first = sweep.rings.front();
  const Ring& last = sweep.rings.back();
  if (capStart)
    fittings.push_back({first.centre + first.dir * flangeHalf(cls), first.dir, first.u, false});
  if (capEnd)
    fittings.push_back({last.centre - last.dir * flangeHalf(cls), last.dir, last.u, false});
  unique(piping_, name, service, [&](ShapeBuilder& b) {
    b.tube(sweep.rings, r, seg_, capStart, capEnd);
    for (const Fitting& f : fittings)
      if (!f.valve) b.flange(f.c, f.d, f.u, r, flangeRadius(cls), flangeHalf(cls), seg_);
  });
  for (const Fitting& f : fittings) {
    if (f.valve)
      valve(f.c, f.d, cls);
    else
      bolts(f.c, f.d, f.u, cls);
  }
  if (!shoesOnPortals) return;
  // A shoe on every portal the level straights along x cross.
  for (const Straight& s : sweep.straights) {
    if (std::abs(s.dir.x) < 0.99) continue;
    const double lo = std::min(s.a.x, s.b.x), hi = std::max(s.a.x, s.b.x);
    for (double x : portalX_)
      if (x > lo + 0.3 && x < hi - 0.3)
        place(fasteners_, "shoe", shoeMesh(cls), {x, s.a.y, s.a.z}, frame(s.dir, {0, 1, 0}));
  }
}

void PlantBuilder::walkway(const std::string& name, const dvec3& lo, const dvec3& hi) {
  // Grating: a plate with bearing bars below it every metre across its length.
  unique(access_, name, Walkway, [&](ShapeBuilder& b) {
    b.box(lo, hi);
    const bool alongX = hi.x - lo.x >= hi.z - lo.z;
    const double len = alongX ? hi.x - lo.x : hi.z - lo.z;
    const int bars = std::max(1, int(len));
    for (int k = 0; k <= bars; ++k) {
      const double t = (alongX ? lo.x : lo.z) + len * k / bars;
      const double a = std::clamp(t - 0.025, alongX ? lo.x : lo.z, (alongX ? hi.x : hi.z) - 0.05);
      if (alongX)
        b.box({a, lo.y - 0.06, lo.z}, {a + 0.05, lo.y, hi.z});
      else
        b.box({lo.x, lo.y - 0.06, a}, {hi.x, lo.y, a + 0.05});
    }
  });
}

void PlantBuilder::railing(const std::string& name, const dvec3& a, const dvec3& b) {
  // Posts at most 2 m apart, a top rail and a knee rail, on the walkway's top at a..b.
  unique(access_, name, Railing, [&](ShapeBuilder& s) {
    const dvec3 d = b - a;
    const double len = glm::length(d);
    const int posts = std::max(1, int(std::ceil(len / 2.0)));
    for (int k = 0; k <= posts; ++k) {
      const dvec3 p = a + d * (double(k) / posts);
      s.box({p.x - 0.025, p.y, p.z - 0.025}, {p.x + 0.025, p.y + kRailHeight, p.z + 0.025});
    }
    const int sides = std::max(6, seg_ / 8);
    for (double h : {kRailHeight, 0.55 * kRailHeight})
      s.cylinder(a + dvec3(0, h, 0), b + dvec3(0, h, 0), 0.025, sides);
  });
}

void PlantBuilder::unit(int index, const dvec3& o) {
  const std::string id = "unit" + std::to_string(index);
  // The boiler: a drum with a domed top, a conical bottom on a skirt, stiffening rings.
  const std::uint32_t boilerMesh = shared("boiler", Boiler, [&](ShapeBuilder& b) {
    std::vector<Ring> rings;
    for (double y = 3.0; y <= 27.0 + 1e-9; y += step_ * 2.0)
      rings.push_back({{0, y, 0}, {0, 1, 0}, {1, 0, 0}});
    const int seg = 2 * seg_;
    b.tube(rings, 6.0, seg, false, false);
    b.dome({0, rings.back().centre.y, 0}, {0, 1, 0}, 6.0, 6.0, seg, std::max(4, seg_ / 3));
    b.tube({{{0, 1, 0}, {0, 1, 0}, {1, 0, 0}}, {{0, 3, 0}, {0, 1, 0}, {1, 0, 0}}}, {2.5, 6.0}, seg,
           true, false);
    b.tube({{{0, 0, 0}, {0, 1, 0}, {1, 0, 0}}, {{0, 1, 0}, {0, 1, 0}, {1, 0, 0}}}, 2.5, seg, false,
           false);
    for (double y : {6.0, 12.0, 18.0, 24.0}) b.torus({0, y, 0}, {0, 1, 0}, 6.05, 0.08, seg, 8);
  });
  place(equipment_, id + "-boiler", boilerMesh, o + dvec3(20, 0, 20));
  // The frame: columns on the perimeter of a 4 x 4 grid, beams along it at every level.
  const double grid[4] = {4.0, 12.0, 28.0, 36.0};
  for (double x : grid)
    for (double z : grid) {
      if (x != 4.0 && x != 36.0 && z != 4.0 && z != 36.0) continue;
      member(id + "-column", o + dvec3(x, 0, z), o + dvec3(x, kFrameTop + 0.5, z), true);
    }
  for (double level : {kLevels[0], kLevels[1], kLevels[2], kFrameTop})
    for (int k = 0; k < 3; ++k)
      for (double edge : {4.0, 36.0}) {
        const double y = level - kGrating - 0.2;
        member(id + "-beam", o + dvec3(grid[k] + 0.2, y, edge),
               o + dvec3(grid[k + 1] - 0.2, y, edge), false);
        member(id + "-beam", o + dvec3(edge, y, grid[k] + 0.2),
               o + dvec3(edge, y, grid[k + 1] - 0.2), false);
      }
  // Walkways: a ring 3.6 m wide around the boiler at each level; railings on both edges, open
  // where the stair landings (east) and the bridge to the rack (south, first level) join.
  const double in0 = 4.2, in1 = 7.8, out0 = 32.2, out1 = 35.8;
  const double landing[3][2] = {{16.2, 20.2}, {29.5, 33.5}, {16.2, 20.2}};
  for (int l = 0; l < 3; ++l) {
    const double y = kLevels[l];
    const std::string lv = id + "-level" + std::to_string(l + 1);
    walkway(lv + "-north", o + dvec3(in0, y - kGrating, in0), o + dvec3(out1, y, in1));
    walkway(lv + "-south", o + dvec3(in0, y - kGrating, out0), o + dvec3(out1, y, out1));
    walkway(lv + "-west", o + dvec3(in0, y - kGrating, in1), o + dvec3(in1, y, out0));
    walkway(lv + "-east", o + dvec3(out0, y - kGrating, in1), o + dvec3(out1, y, out0));
    const double e = 0.1;  // railings stand this far inside the edges
    // Inner edges (around the boiler's opening).
    railing(lv + "-rail", o + dvec3(in1 - e, y, in1 - e), o + dvec3(out0 + e, y, in1 - e));
    railing(lv + "-rail", o + dvec3(in1 - e, y, out0 + e), o + dvec3(out0 + e, y, out0 + e));
    railing(lv + "-rail", o + dvec3(in1 - e, y, in1 - e), o + dvec3(in1 - e, y, out0 + e));
    railing(lv + "-rail", o + dvec3(out0 + e, y, in1 - e), o + dvec3(out0 + e, y, out0 + e));
    // Outer edges.
    railing(lv + "-rail", o + dvec3(in0 + e, y, in0 + e), o + dvec3(out1 - e, y, in0 + e));
    railing(lv + "-rail", o + dvec3(in0 + e, y, in0 + e), o + dvec3(in0 + e, y, out1 - e));
    if (l == 0) {
      railing(lv + "-rail", o + dvec3(in0 + e, y, out1 - e), o + dvec3(15.5, y, out1 - e));
      railing(lv + "-rail", o + dvec3(19.5, y, out1 - e), o + dvec3(out1 - e, y, out1 - e));
    } else {
      railing(lv + "-rail", o + dvec3(in0 + e, y, out1 - e), o + dvec3(out1 - e, y, out1 - e));
    }
    railing(lv + "-rail", o + dvec3(out1 - e, y, in0 + e), o + dvec3(out1 - e, y, landing[l][0]));
    railing(lv + "-rail", o + dvec3(out1 - e, y, landing[l][1]), o + dvec3(out1 - e, y, out1 - e));
    // The stair landing east of the frame.
    walkway(lv + "-landing", o + dvec3(out1, y - kGrating, landing[l][0]),
            o + dvec3(40.1, y, landing[l][1]));
    railing(lv + "-rail", o + dvec3(40.0, y, landing[l][0]), o + dvec3(40.0, y, landing[l][1]));
  }
  // The stair tower: three flights in two lanes east of the frame, switching back at the
  // landings: ground -> 7 m going north (lane A), 7 -> 14 going south (lane B), 14 -> 21 north.
  const std::uint32_t flight = flightMesh();
  const glm::dquat north = frame({0, 0, -1}, {0, 1, 0}), south = frame({0, 0, 1}, {0, 1, 0});
  // frame(-z, y) takes the flight's width (+Z) to +x, frame(+z, y) to -x: lane A is x 36.4 ..
  // 38.2, lane B 38.3 .. 40.1.
  place(access_, id + "-stairs", flight, o + dvec3(36.4, 0.0, 29.5), north);
  place(access_, id + "-stairs", flight, o + dvec3(40.1, 7.0, 20.2), south);
  place(access_, id + "-stairs", flight, o + dvec3(36.4, 14.0, 29.5), north);
  // The bridge from the first level to the rack's catwalk.
  walkway(id + "-bridge", o + dvec3(15.5, kCatwalk - kGrating, out1),
          o + dvec3(19.5, kCatwalk, 44.5));
  railing(id + "-rail", o + dvec3(15.6, kCatwalk, out1), o + dvec3(15.6, kCatwalk, 44.5));
  railing(id + "-rail", o + dvec3(19.4, kCatwalk, out1), o + dvec3(19.4, kCatwalk, 44.5));
  // The tank yard: two horizontal tanks on saddles.
  for (int t = 0; t < 2; ++t) {
    const double length = 8.0 + 2.0 * random_.below(3);
    const std::uint32_t tankMesh =
        shared("tank-" + std::to_string(int(length)), Tank, [&](ShapeBuilder& b) {
          std::vector<Ring> rings;
          for (double x = 0.0; x <= length + 1e-9; x += step_ * 2.0)
            rings.push_back({{x, 0, 0}, {1, 0, 0}, {0, 1, 0}});
          b.tube(rings, 2.0, seg_, false, false);
          b.dome({0, 0, 0}, {-1, 0, 0}, 2.0, 0.9, seg_, std::max(4, seg_ / 6));
          b.dome({rings.back().centre.x, 0, 0}, {1, 0, 0}, 2.0, 0.9, seg_, std::max(4, seg_ / 6));
          b.cylinder({length / 2, 1.8, 0}, {length / 2, 2.5, 0}, 0.35, seg_ / 2);  // manway
        });
    const double x = t == 0 ? 45.5 : 51.5, z0 = t == 0 ? 6.0 : 22.0;
    place(equipment_, id + "-tank", tankMesh, o + dvec3(x, 2.6, z0), frame({0, 0, 1}, {0, 1, 0}));
    const std::uint32_t saddle = shared("saddle", Frame, [](ShapeBuilder& b) {
      b.box({-1.6, 0.0, -0.2}, {1.6, 0.05, 0.2});
      b.box({-1.2, 0.05, -0.03}, {1.2, 0.9, 0.03});
    });
    for (double f : {0.2, 0.8})
      place(structure_, id + "-saddle", saddle, o + dvec3(x, 0, z0 + f * length));
    // Its branch: from the rack north, down to the tank's axis, into its south head.
    const int cls = random_.below(3);
    const double end = z0 + length + 0.9;
    pipe(id + "-tankline", t == 0 ? Oil : Water, cls,
         {o + dvec3(x, kTier[0] + kShoe + 0.3, 46.0), o + dvec3(x, kBranchLevel, 46.0),
          o + dvec3(x, kBranchLevel, end + 3.0), o + dvec3(x, 2.6, end + 3.0),
          o + dvec3(x, 2.6, end - 0.2)},
         false, true, 6.0, 3.0, 12.0, false);
  }
  // Two boiler feeds from the rack: north at the branch level, up beside the boiler (inside the
  // walkways' opening) and into its side.
  for (int f = 0; f < 2; ++f) {
    const double x = f == 0 ? 24.0 : 16.0, y = f == 0 ? 17.5 : 24.5;
    const double surface = 20.0 + std::sqrt(36.0 - (x - 20.0) * (x - 20.0));
    pipe(id + "-feed", Steam, 2 + random_.below(3),
         {o + dvec3(x, kTier[0] + kShoe + 0.3, 46.0), o + dvec3(x, kBranchLevel, 46.0),
          o + dvec3(x, kBranchLevel, 29.0), o + dvec3(x, y, 29.0), o + dvec3(x, y, surface - 0.1)},
         false, true, 8.0, 4.0, 16.0, false);
  }
}

void PlantBuilder::rack(int row, double x0, double x1) {
  const double z = row * kPitchZ + kUnitDepth;  // the rack's north edge
  const std::string id = "rack" + std::to_string(row);
  for (double x : portalX_) {
    for (double side : {1.0, 11.0})
      member(id + "-column", {x, 0, z + side}, {x, kTier[1] + 0.5, z + side}, true);
    for (double y : {kCatwalk - kGrating - 0.2, kTier[0] - 0.2, kTier[1] - 0.2})
      member(id + "-beam", {x, y, z + 1.2}, {x, y, z + 10.8}, false);
  }
  for (std::size_t k = 0; k + 1 < portalX_.size(); ++k)
    for (double side : {1.0, 11.0})
      for (double y : {kTier[0] - 0.2, kTier[1] - 0.2})
        member(id + "-beam", {portalX_[k] + 0.2, y, z + side}, {portalX_[k + 1] - 0.2, y, z + side},
               false);
  // The catwalk, a bay at a time, railings on both edges open where the units' bridges join.
  for (std::size_t k = 0; k + 1 < portalX_.size(); ++k) {
    const double a = std::max(x0, portalX_[k]), b = std::min(x1, portalX_[k + 1]);
    if (b <= a) continue;
    walkway(id + "-catwalk", {a, kCatwalk - kGrating, z + 4.5}, {b, kCatwalk, z + 7.5});
    railing(id + "-rail", {a, kCatwalk, z + 7.4}, {b, kCatwalk, z + 7.4});
    // North edge: gaps at the bridges (x 15.5 .. 19.5 of each unit column).
    double from = a;
    for (int c = 0; c < columns_; ++c) {
      const double gap = c * kPitchX + 15.5;
      if (gap + 4.0 <= from || gap >= b) continue;
      if (gap > from) railing(id + "-rail", {from, kCatwalk, z + 4.6}, {gap, kCatwalk, z + 4.6});
      from = gap + 4.0;
    }
    if (from < b) railing(id + "-rail", {from, kCatwalk, z + 4.6}, {b, kCatwalk, z + 4.6});
  }
  // Closed at the east end; stairs and a landing at the west end.
  railing(id + "-rail", {portalX_.back() - 0.1, kCatwalk, z + 4.5},
          {portalX_.back() - 0.1, kCatwalk, z + 7.5});
  place(access_, id + "-stairs", flightMesh(), {x0 - 9.3, 0.0, z + 5.1}, glm::dquat(1, 0, 0, 0));
  walkway(id + "-landing", {x0, kCatwalk - kGrating, z + 4.5},
          {portalX_.front(), kCatwalk, z + 7.5});
}

void PlantBuilder::longRuns() {
  // Each slot of each tier is one run snaking through every rack: along rack 0 east, over to
  // rack 1 at the east end, along it west, and so on. Where runs turn toward the next rack, the
  // one on the southern slot turns last, so that no two cross.
  const double x0 = portalX_.front() - 1.0, x1 = portalX_.back() + 1.0;
  for (int tier = 0; tier < 2; ++tier) {
    const int slots = kSlots[tier];
    for (int i = 0; i < slots; ++i) {
      const int cls = 1 + random_.below(4);
      const Part service = Part(Steam + random_.below(3));
      const double y = kTier[tier] + kShoe + kRadii[cls];
      const double dz = 1.9 + i * (8.2 / (slots - 1));
      const double turnOut = 2.0 + (slots - 1 - i) * 1.5;
      std::vector<dvec3> points{{x0, y, kUnitDepth + dz}};
      for (int r = 0; r < rows_; ++r) {
        const double z = r * kPitchZ + kUnitDepth + dz;
        const bool east = r % 2 == 0;
        if (r + 1 == rows_) {
          points.push_back({east ? x1 : x0, y, z});
          break;
        }
        const double turn = east ? x1 + turnOut : x0 - turnOut;
        points.push_back({turn, y, z});
        points.push_back({turn, y, z + kPitchZ});
      }
      pipe("run-t" + std::to_string(tier + 1) + "-" + std::to_string(i), service, cls, points, true,
           true, 12.0, 2.0 * i, 48.0, true);
      ++summary_.pipeRuns;
    }
  }
  // Supports for the runs between racks at the ends: a portal every 6 m along z.
  for (int r = 0; r + 1 < rows_; ++r) {
    const bool east = r % 2 == 0;
    const double xa = east ? x1 + 1.2 : x0 - 1.2 - 7 * 1.5 - 1.0;
    const double xb = xa + 7 * 1.5 + 1.0;
    const double za = r * kPitchZ + kUnitDepth + 12.0, zb = (r + 1) * kPitchZ + kUnitDepth;
    for (double z = za + 3.0; z < zb - 1.0; z += 6.0) {
      for (double x : {xa, xb}) member("connector-column", {x, 0, z}, {x, kTier[1] + 0.5, z}, true);
      for (double y : {kTier[0] - 0.2, kTier[1] - 0.2})
        member("connector-beam", {xa + 0.2, y, z}, {xb - 0.2, y, z}, false);
    }
  }
}

void PlantBuilder::ground() {
  const Aabb b = summary_.bounds;
  const double x0 = std::floor(b.min.x) - 10.0, x1 = std::ceil(b.max.x) + 10.0;
  const double z0 = std::floor(b.min.z) - 10.0, z1 = std::ceil(b.max.z) + 10.0;
  unique(site_, "ground", Ground, [&](ShapeBuilder& s) {
    const int nx = std::max(1, int((x1 - x0) / 4.0)), nz = std::max(1, int((z1 - z0) / 4.0));
    std::vector<std::uint32_t> v;
    for (int j = 0; j <= nz; ++j)
      for (int i = 0; i <= nx; ++i)
        v.push_back(s.vertex({x0 + (x1 - x0) * i / nx, 0.0, z0 + (z1 - z0) * j / nz}, {0, 1, 0}));
    for (int j = 0; j < nz; ++j)
      for (int i = 0; i < nx; ++i) {
        const std::uint32_t a = v[std::size_t(j * (nx + 1) + i)], c = a + std::uint32_t(nx + 1);
        s.triangle(a, c, c + 1);  // counter-clockwise seen from above (+y)
        s.triangle(a, c + 1, a + 1);
      }
  });
}

Plant PlantBuilder::build() {
  units_ = int(std::max<std::uint64_t>(1, (o_.objects + kObjectsPerUnit / 2) / kObjectsPerUnit));
  columns_ = std::max(1, int(std::ceil(std::sqrt(double(units_)))));
  rows_ = (units_ + columns_ - 1) / columns_;
  summary_.units = std::size_t(units_);
  summary_.racks = std::size_t(rows_);
  // Groups by function, as CAD models are organised.
  site_ = group("site");
  structure_ = group("structure");
  equipment_ = group("equipment");
  piping_ = group("piping");
  valves_ = group("valves");
  fasteners_ = group("fasteners");
  access_ = group("access");
  const double x0 = -4.0, x1 = columns_ * kPitchX - 4.0;
  for (double x = x0 + 1.0; x <= x1 - 1.0 + 1e-9; x += 6.0) portalX_.push_back(x);
  for (int k = 0; k < units_; ++k)
    unit(k, dvec3((k % columns_) * kPitchX, 0.0, (k / columns_) * kPitchZ));
  for (int r = 0; r < rows_; ++r) rack(r, x0, x1);
  longRuns();
  ground();
  Plant p;
  p.scene = std::move(scene_);
  p.summary = summary_;
  return p;
}

}  // namespace

Plant makePowerPlant(const PlantOptions& options) {
  assert(options.detail > 0.0 && options.detail <= 4.0);
  assert(options.objects >= kMinPlantObjects && options.objects <= kMaxPlantObjects);
  return PlantBuilder(options).build();
}

}  // namespace hlod
