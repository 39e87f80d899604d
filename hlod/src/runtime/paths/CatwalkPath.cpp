// The catwalk walk of a CAD scene (hlod/runtime/CatwalkPath.h).
#include "hlod/runtime/CatwalkPath.h"

#include "runtime/paths/PathGenerators.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <deque>
#include <limits>
#include <vector>

namespace hlod {

namespace {

// Floors closer than this in one cell are one floor.
constexpr double kSameFloor = 0.05;
// The highest step between neighbouring cells a walker takes (a stair's rise is 0.25 m).
constexpr double kStep = 0.3;
// A triangle is a floor when its normal is this close to up (cos 18 degrees).
constexpr double kFloorCos = 0.95;
// The grid is coarsened past this many cells.
constexpr double kMaxCells = 3.0e7;
constexpr std::uint32_t kNone = 0xffffffffu;

// The grid over the model's horizontal axes (a, b) with `up` vertical.
struct Grid {
  int u = 2, a = 0, b = 1;
  double cell = 0.25;
  glm::dvec2 origin{0.0};
  int na = 0, nb = 0;
  // Floors per cell (CSR): heights ascending, and per floor whether something stands above it,
  // whether it is walkable, and its network.
  std::vector<std::uint32_t> start;  // na * nb + 1
  std::vector<double> height;
  std::vector<std::uint8_t> blocked, walkable;
  std::vector<std::uint32_t> network;

  std::size_t cellOf(int i, int j) const {
    return std::size_t(j) * std::size_t(na) + std::size_t(i);
  }
  bool inside(int i, int j) const { return i >= 0 && j >= 0 && i < na && j < nb; }
  glm::dvec2 centre(int i, int j) const {
    return origin + glm::dvec2((i + 0.5) * cell, (j + 0.5) * cell);
  }
  glm::dvec2 flat(const glm::dvec3& p) const { return {p[a], p[b]}; }
  // The floor of cell (i, j) nearest to h within tol in network n (any with kNone), or kNone.
  std::uint32_t floorNear(int i, int j, double h, double tol, std::uint32_t n) const {
    if (!inside(i, j)) return kNone;
    std::uint32_t best = kNone;
    const std::size_t c = cellOf(i, j);
    for (std::uint32_t f = start[c]; f < start[c + 1]; ++f)
      if (walkable[f] && (n == kNone || network[f] == n) && std::abs(height[f] - h) <= tol &&
          (best == kNone || std::abs(height[f] - h) < std::abs(height[best] - h)))
        best = f;
    return best;
  }
};

// 2D: whether triangle (p, q, r) and the square [lo, hi] overlap (separating axes: the square's
// two and the triangle's three edge normals).
bool overlaps(const glm::dvec2 t[3], const glm::dvec2& lo, const glm::dvec2& hi) {
  for (int k = 0; k < 3; ++k) {
    const glm::dvec2 e = t[(k + 1) % 3] - t[k];
    const glm::dvec2 n(-e.y, e.x);
    double tmin = std::numeric_limits<double>::max(), tmax = std::numeric_limits<double>::lowest();
    for (int v = 0; v < 3; ++v) {
      tmin = std::min(tmin, glm::dot(n, t[v]));
      tmax = std::max(tmax, glm::dot(n, t[v]));
    }
    double smin = std::numeric_limits<double>::max(), smax = std::numeric_limits<double>::lowest();
    for (const glm::dvec2& c : {lo, hi, glm::dvec2(lo.x, hi.y), glm::dvec2(hi.x, lo.y)}) {
      smin = std::min(smin, glm::dot(n, c));
      smax = std::max(smax, glm::dot(n, c));
    }
    if (smax < tmin || smin > tmax) return false;
  }
  return true;
}

// Whether point p lies in triangle t (2D, either winding).
bool contains(const glm::dvec2 t[3], const glm::dvec2& p) {
  const auto side = [&](int k) {
    const glm::dvec2 e = t[(k + 1) % 3] - t[k], d = p - t[k];
    return e.x * d.y - e.y * d.x;
  };
  const double s0 = side(0), s1 = side(1), s2 = side(2);
  return (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0);
}

Result<Grid> floorsOf(const TriangleSource& triangles, const Aabb& bounds, UpAxis up,
                      const CatwalkOptions& o) {
  Grid g;
  g.u = int(up);
  g.a = (g.u + 1) % 3;
  g.b = (g.u + 2) % 3;
  g.cell = o.cell;
  const glm::dvec2 size(bounds.size()[g.a], bounds.size()[g.b]);
  while (std::ceil(size.x / g.cell) * std::ceil(size.y / g.cell) > kMaxCells) g.cell *= 2.0;
  g.origin = glm::dvec2(bounds.min[g.a], bounds.min[g.b]);
  g.na = std::max(1, int(std::ceil(size.x / g.cell)));
  g.nb = std::max(1, int(std::ceil(size.y / g.cell)));
  const double bottom = bounds.min[g.u] + o.minElevation;
  // The cells a triangle's 2D box covers (clamped to the grid).
  const auto cellRange = [&](const glm::dvec2 t[3], int& i0, int& i1, int& j0, int& j1) {
    const glm::dvec2 lo = glm::min(t[0], glm::min(t[1], t[2])) - g.origin,
                     hi = glm::max(t[0], glm::max(t[1], t[2])) - g.origin;
    i0 = std::clamp(int(std::floor(lo.x / g.cell)), 0, g.na - 1);
    i1 = std::clamp(int(std::floor(hi.x / g.cell)), 0, g.na - 1);
    j0 = std::clamp(int(std::floor(lo.y / g.cell)), 0, g.nb - 1);
    j1 = std::clamp(int(std::floor(hi.y / g.cell)), 0, g.nb - 1);
  };
  // Pass 1: floors, as (cell, height) pairs.
  std::vector<std::pair<std::uint64_t, double>> floors;
  auto status = triangles([&](const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& r) {
    const glm::dvec3 n = glm::cross(q - p, r - p);
    const double len = glm::length(n);
    if (!(len > 0.0) || n[g.u] < kFloorCos * len) return;
    if (std::max({p[g.u], q[g.u], r[g.u]}) < bottom) return;
    const glm::dvec2 t[3] = {g.flat(p), g.flat(q), g.flat(r)};
    int i0, i1, j0, j1;
    cellRange(t, i0, i1, j0, j1);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const glm::dvec2 c = g.centre(i, j);
        if (!contains(t, c)) continue;
        // The plane's height at the centre.
        const double h = p[g.u] - (n[g.a] * (c.x - p[g.a]) + n[g.b] * (c.y - p[g.b])) / n[g.u];
        if (h >= bottom) floors.emplace_back(g.cellOf(i, j), h);
      }
  });
  if (!status) return status.error();
  std::sort(floors.begin(), floors.end());
  g.start.assign(std::size_t(g.na) * std::size_t(g.nb) + 1, 0);
  for (std::size_t k = 0; k < floors.size(); ++k) {
    if (k > 0 && floors[k].first == floors[k - 1].first &&
        floors[k].second - g.height.back() <= kSameFloor)
      continue;
    g.height.push_back(floors[k].second);
    ++g.start[floors[k].first + 1];
  }
  for (std::size_t c = 1; c < g.start.size(); ++c) g.start[c] += g.start[c - 1];
  floors = {};
  g.blocked.assign(g.height.size(), 0);
  // Pass 2: what reaches into the headroom of a floor, over its cell.
  status = triangles([&](const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& r) {
    const double hmin = std::min({p[g.u], q[g.u], r[g.u]}),
                 hmax = std::max({p[g.u], q[g.u], r[g.u]});
    const glm::dvec2 t[3] = {g.flat(p), g.flat(q), g.flat(r)};
    int i0, i1, j0, j1;
    cellRange(t, i0, i1, j0, j1);
    const glm::dvec3 n = glm::cross(q - p, r - p);
    const bool sloped = std::abs(n[g.u]) > 0.05 * glm::length(n);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const std::size_t c = g.cellOf(i, j);
        if (g.start[c] == g.start[c + 1]) continue;
        const glm::dvec2 lo = g.origin + glm::dvec2(i * g.cell, j * g.cell),
                         hi = lo + glm::dvec2(g.cell);
        if (!overlaps(t, lo, hi)) continue;
        // The triangle's heights over the cell: its plane's at the corners, within its own range
        // (an upright triangle: all of its range).
        double lowest = hmin, highest = hmax;
        if (sloped) {
          lowest = std::numeric_limits<double>::max();
          highest = std::numeric_limits<double>::lowest();
          for (const glm::dvec2& k : {lo, hi, glm::dvec2(lo.x, hi.y), glm::dvec2(hi.x, lo.y)}) {
            const double h = p[g.u] - (n[g.a] * (k.x - p[g.a]) + n[g.b] * (k.y - p[g.b])) / n[g.u];
            lowest = std::min(lowest, h);
            highest = std::max(highest, h);
          }
          lowest = std::max(lowest, hmin);
          highest = std::min(highest, hmax);
        }
        for (std::uint32_t f = g.start[c]; f < g.start[c + 1]; ++f)
          if (highest > g.height[f] + kSameFloor && lowest < g.height[f] + o.headroom)
            g.blocked[f] = 1;
      }
  });
  if (!status) return status.error();
  return g;
}

// Walkable floors: free, with free floor a step away all around within the clearance.
void markWalkable(Grid& g, const CatwalkOptions& o) {
  const int reach = int(std::ceil(o.clearance / g.cell));
  std::vector<std::pair<int, int>> disc;
  for (int dj = -reach; dj <= reach; ++dj)
    for (int di = -reach; di <= reach; ++di)
      if ((di * di + dj * dj) * g.cell * g.cell <= o.clearance * o.clearance)
        disc.emplace_back(di, dj);
  g.walkable.assign(g.height.size(), 0);
  for (int j = 0; j < g.nb; ++j)
    for (int i = 0; i < g.na; ++i) {
      const std::size_t c = g.cellOf(i, j);
      for (std::uint32_t f = g.start[c]; f < g.start[c + 1]; ++f) {
        if (g.blocked[f]) continue;
        bool ok = true;
        for (const auto& [di, dj] : disc) {
          if (!g.inside(i + di, j + dj)) {
            ok = false;
            break;
          }
          const std::size_t d = g.cellOf(i + di, j + dj);
          bool found = false;
          for (std::uint32_t k = g.start[d]; k < g.start[d + 1] && !found; ++k)
            found = !g.blocked[k] && std::abs(g.height[k] - g.height[f]) <= kStep;
          if (!found) {
            ok = false;
            break;
          }
        }
        g.walkable[f] = ok;
      }
    }
}

struct Node {
  int i, j;
  std::uint32_t floor;
};

// Breadth-first over the walkable floors from `from`: the distances (steps) and parents.
void sweep(const Grid& g, std::uint32_t from, const std::vector<Node>& where,
           std::vector<std::uint32_t>& dist, std::vector<std::uint32_t>& parent,
           std::uint32_t networkId, std::vector<std::uint32_t>* network) {
  dist.assign(g.height.size(), kNone);
  parent.assign(g.height.size(), kNone);
  std::deque<std::uint32_t> queue{from};
  dist[from] = 0;
  while (!queue.empty()) {
    const std::uint32_t f = queue.front();
    queue.pop_front();
    if (network) (*network)[f] = networkId;
    const Node n = where[f];
    for (const auto& [di, dj] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
      if (!g.inside(n.i + di, n.j + dj)) continue;
      const std::size_t c = g.cellOf(n.i + di, n.j + dj);
      for (std::uint32_t k = g.start[c]; k < g.start[c + 1]; ++k)
        if (g.walkable[k] && dist[k] == kNone && std::abs(g.height[k] - g.height[f]) <= kStep) {
          dist[k] = dist[f] + 1;
          parent[k] = f;
          queue.push_back(k);
        }
    }
  }
}

}  // namespace

Result<CameraPath> makeCatwalkPath(const TriangleSource& triangles, const Aabb& bounds, UpAxis up,
                                   const CatwalkOptions& o) {
  if (bounds.empty()) return makeError("catwalk: the model is empty");
  auto grid = floorsOf(triangles, bounds, up, o);
  if (!grid) return grid.error();
  Grid& g = *grid;
  markWalkable(g, o);
  std::vector<Node> where(g.height.size());
  for (int j = 0; j < g.nb; ++j)
    for (int i = 0; i < g.na; ++i) {
      const std::size_t c = g.cellOf(i, j);
      for (std::uint32_t f = g.start[c]; f < g.start[c + 1]; ++f) where[f] = {i, j, f};
    }
  // Networks of walkable floors; the largest is the catwalks.
  g.network.assign(g.height.size(), kNone);
  std::vector<std::uint32_t> dist, parent;
  std::uint32_t best = kNone, bestSize = 0, networks = 0;
  for (std::uint32_t f = 0; f < g.height.size(); ++f) {
    if (!g.walkable[f] || g.network[f] != kNone) continue;
    sweep(g, f, where, dist, parent, networks, &g.network);
    std::uint32_t size = 0;
    for (std::uint32_t d : dist) size += d != kNone;
    if (size > bestSize) best = f, bestSize = size;
    ++networks;
  }
  if (best == kNone || bestSize < 16)
    return makeError("catwalk: no walkable floor " + std::to_string(o.minElevation) +
                     " m above the ground with " + std::to_string(o.headroom) +
                     " m of head room and " + std::to_string(2.0 * o.clearance) +
                     " m of width (try --kind fly-around or orbit)");
  const std::uint32_t net = g.network[best];
  // Two sweeps: the farthest floor from any floor is an end of a longest shortest path.
  sweep(g, best, where, dist, parent, 0, nullptr);
  std::uint32_t end = best;
  for (std::uint32_t f = 0; f < dist.size(); ++f)
    if (dist[f] != kNone && dist[f] > dist[end]) end = f;
  sweep(g, end, where, dist, parent, 0, nullptr);
  std::uint32_t far = end;
  for (std::uint32_t f = 0; f < dist.size(); ++f)
    if (dist[f] != kNone && dist[f] > dist[far]) far = f;
  std::vector<std::uint32_t> route;  // from `end` to `far`
  for (std::uint32_t f = far; f != kNone; f = parent[f]) route.push_back(f);
  std::reverse(route.begin(), route.end());
  // Each route floor's point at floor height.
  const auto point = [&](std::uint32_t f) {
    const glm::dvec2 c = g.centre(where[f].i, where[f].j);
    glm::dvec3 p(0.0);
    p[g.a] = c.x;
    p[g.b] = c.y;
    p[g.u] = g.height[f];
    return p;
  };
  // Whether the straight line from route[x] to route[y] stays on the network's floors.
  const auto straight = [&](std::size_t x, std::size_t y) {
    const glm::dvec3 p = point(route[x]), q = point(route[y]);
    const double len = glm::length(g.flat(q) - g.flat(p));
    const int samples = std::max(1, int(std::ceil(len / (0.5 * g.cell))));
    for (int s = 0; s <= samples; ++s) {
      const glm::dvec3 m = p + (q - p) * (double(s) / samples);
      const glm::dvec2 f = (g.flat(m) - g.origin) / g.cell;
      if (g.floorNear(int(std::floor(f.x)), int(std::floor(f.y)), m[g.u], kStep, net) == kNone)
        return false;
    }
    return true;
  };
  // Keyframe route indices: straightened greedily, at most `duration * speed` long.
  const double length = o.speed * o.duration;
  std::vector<std::size_t> keys{0};
  double walked = 0.0;
  while (keys.back() + 1 < route.size() && walked < length) {
    const std::size_t from = keys.back();
    std::size_t to = from + 1;
    // The farthest straight reach, tried at doubling steps then bisected.
    std::size_t ok = to, step = 1;
    while (ok + step < route.size() && straight(from, ok + step)) ok += step, step *= 2;
    for (; step > 0; step /= 2)
      if (ok + step < route.size() && straight(from, ok + step)) ok += step;
    // The last stretch ends where the walk has its length.
    to = from + 1;
    while (to < ok && glm::length(point(route[to]) - point(route[from])) < length - walked) ++to;
    walked += glm::length(point(route[to]) - point(route[from]));
    keys.push_back(to);
  }
  // Build the path; where the interpolated curve leaves the network's floors (a turn's curve
  // cutting a corner), the route between two keyframes gains its middle floor as a keyframe.
  glm::dvec3 upVec(0.0);
  upVec[g.u] = 1.0;
  for (int round = 0;; ++round) {
    std::vector<CameraKeyframe> frames;
    double t = 0.0;
    for (std::size_t k = 0; k < keys.size(); ++k) {
      const glm::dvec3 p = point(route[keys[k]]);
      if (k > 0) t += glm::length(p - point(route[keys[k - 1]])) / o.speed;
      // Look along the way ahead (the last keyframe: the way it came), level.
      const std::size_t a = k + 1 < keys.size() ? k : k - 1, b = a + 1;
      glm::dvec3 dir = point(route[keys[b]]) - point(route[keys[a]]);
      dir[g.u] *= 0.5;
      dir = glm::length(dir) > 0.0 ? glm::normalize(dir) : glm::dvec3(upVec.y, upVec.z, upVec.x);
      CameraKeyframe key;
      key.time = t;
      key.position = p + upVec * o.eyeHeight;
      key.target = key.position + dir * 10.0;
      key.up = upVec;
      key.fovY = 70.0;
      frames.push_back(key);
    }
    if (frames.size() < 2) return makeError("catwalk: the catwalks are too short to walk");
    auto path = CameraPath::fromKeyframes(frames);
    if (!path) return path.error();
    // Samples every few centimetres of the walk, each over a floor of the network.
    std::vector<std::size_t> bad;
    for (std::size_t k = 0; k + 1 < keys.size(); ++k) {
      const double t0 = frames[k].time, t1 = frames[k + 1].time;
      const int samples = std::max(2, int(std::ceil((t1 - t0) * o.speed / 0.05)));
      for (int s = 1; s < samples; ++s) {
        const glm::dvec3 p = path->sample(t0 + (t1 - t0) * s / samples).camera.position;
        const glm::dvec2 f = (g.flat(p) - g.origin) / g.cell;
        if (g.floorNear(int(std::floor(f.x)), int(std::floor(f.y)), p[g.u] - o.eyeHeight, kStep,
                        net) == kNone) {
          bad.push_back(k);
          break;
        }
      }
    }
    if (bad.empty()) return path;
    if (round == 64) return makeError("catwalk: the walk could not be kept on the catwalks");
    for (std::size_t k = bad.size(); k-- > 0;) {
      const std::size_t a = keys[bad[k]], b = keys[bad[k] + 1];
      if (b - a < 2) return makeError("catwalk: the walk could not be kept on the catwalks");
      keys.insert(keys.begin() + std::ptrdiff_t(bad[k]) + 1, (a + b) / 2);
    }
  }
}

TriangleSource leafTriangles(const NodeSource& source) {
  return [&source](const TriangleVisitor& visit) -> Status {
    const Skeleton& s = source.skeleton();
    std::vector<std::byte> bytes;
    for (std::uint32_t n = 0; n < s.nodes.size(); ++n) {
      const NodeInfo& info = s.nodes[n];
      if (!s.isLeaf(n)) continue;
      bytes.resize(info.meshSize());
      if (auto st = source.readPayloadChunk(n, 0, bytes); !st) return st;
      auto mesh = source.decodePayload(n, bytes);
      if (!mesh) return mesh.error();
      for (std::size_t i = 0; i + 2 < mesh->indices.size(); i += 3) {
        const auto at = [&](std::size_t k) {
          return mesh->centre + glm::dvec3(mesh->positions[mesh->indices[i + k]]);
        };
        visit(at(0), at(1), at(2));
      }
    }
    return Ok{};
  };
}

Result<CameraPath> makeCatwalkPath(const NodeSource& store) {
  return makeCatwalkPath(leafTriangles(store), rootBounds(store.skeleton()), store.skeleton().up);
}

}  // namespace hlod
