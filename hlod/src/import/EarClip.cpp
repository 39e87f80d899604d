// Ear clipping with hole bridging, after D. Eberly, "Triangulation by Ear Clipping" (Geometric
// Tools, 2002-2015): sec. 3 (holes: the rightmost hole vertex M, a ray to +x, the visible outer
// vertex), sec. 2 (ears: a convex vertex whose triangle holds no other vertex).
#include "hlod/import/EarClip.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numeric>

namespace hlod {
namespace {

using Ring = std::vector<std::uint32_t>;  // indices into the projected points

double cross(const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

double signedArea(const std::vector<glm::dvec2>& p, const Ring& r) {
  double a = 0.0;
  for (std::size_t i = 0, n = r.size(); i < n; ++i) {
    const glm::dvec2& u = p[r[i]];
    const glm::dvec2& v = p[r[(i + 1) % n]];
    a += u.x * v.y - v.x * u.y;
  }
  return 0.5 * a;
}

// Inclusive of the boundary: a vertex on an ear's edge would make the rest of the ring touch
// itself, so that ear is refused too.
bool inTriangle(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c,
                const glm::dvec2& p) {
  return cross(a, b, p) >= 0.0 && cross(b, c, p) >= 0.0 && cross(c, a, p) >= 0.0;
}

// The ring without consecutive duplicates (the closing repeat of the first point included).
Ring withoutDuplicates(const std::vector<glm::dvec2>& p, Ring r) {
  Ring out;
  for (std::uint32_t i : r)
    if (out.empty() || p[out.back()] != p[i]) out.push_back(i);
  while (out.size() > 1 && p[out.front()] == p[out.back()]) out.pop_back();
  return out;
}

// Whether the direction from ring vertex at position k towards point q starts inside the ring
// (the ring counter-clockwise): a bridge end that appears twice must be the copy facing q.
bool locallyInside(const std::vector<glm::dvec2>& p, const Ring& ring, std::size_t k,
                   const glm::dvec2& q) {
  const std::size_t n = ring.size();
  const glm::dvec2& a = p[ring[k]];
  const glm::dvec2& prev = p[ring[(k + n - 1) % n]];
  const glm::dvec2& next = p[ring[(k + 1) % n]];
  if (cross(prev, a, next) >= 0.0) return cross(a, next, q) >= 0.0 && cross(a, q, prev) >= 0.0;
  return cross(a, next, q) >= 0.0 || cross(a, q, prev) >= 0.0;
}

// Eberly sec. 3: merges the (clockwise) hole into the (counter-clockwise) ring through a bridge
// from the hole's rightmost vertex M to an outer vertex visible from it. False when the ray from
// M meets no edge (the hole lies outside the ring).
bool bridgeHole(const std::vector<glm::dvec2>& p, Ring& ring, const Ring& hole) {
  std::size_t m = 0;
  for (std::size_t i = 1; i < hole.size(); ++i)
    if (p[hole[i]].x > p[hole[m]].x) m = i;
  const glm::dvec2 M = p[hole[m]];
  // The nearest edge the ray M + t(1, 0) crosses; inside a counter-clockwise ring the first edge
  // to the right of a point goes upwards.
  const std::size_t n = ring.size();
  double bestX = std::numeric_limits<double>::infinity();
  std::size_t edge = n;
  for (std::size_t k = 0; k < n; ++k) {
    const glm::dvec2& a = p[ring[k]];
    const glm::dvec2& b = p[ring[(k + 1) % n]];
    if (!(a.y <= M.y && b.y >= M.y && a.y != b.y)) continue;
    const double x = a.x + (M.y - a.y) * (b.x - a.x) / (b.y - a.y);
    if (x >= M.x && x < bestX) {
      bestX = x;
      edge = k;
    }
  }
  if (edge == n) return false;
  const glm::dvec2 I(bestX, M.y);
  const std::size_t ka = edge, kb = (edge + 1) % n;
  // The edge's end with the larger x is the candidate; when the ray meets a vertex, that one.
  std::size_t pick = p[ring[ka]] == I                ? ka
                     : p[ring[kb]] == I              ? kb
                     : p[ring[ka]].x > p[ring[kb]].x ? ka
                                                     : kb;
  if (p[ring[pick]] != I) {
    // Vertices inside the triangle (M, I, P) hide P: the one at the least angle to the ray is
    // visible instead (ties: the nearest).
    const glm::dvec2 P = p[ring[pick]];
    const bool ccw = cross(M, I, P) > 0.0;
    const glm::dvec2 &t1 = ccw ? I : P, &t2 = ccw ? P : I;
    double bestTan = std::numeric_limits<double>::infinity(), bestDist = bestTan;
    for (std::size_t k = 0; k < n; ++k) {
      const glm::dvec2& q = p[ring[k]];
      if (q == P || !(q.x > M.x) || !inTriangle(M, t1, t2, q)) continue;
      const double tan = std::abs(q.y - M.y) / (q.x - M.x);
      const double dist = glm::length(q - M);
      if (tan < bestTan || (tan == bestTan && dist < bestDist)) {
        bestTan = tan;
        bestDist = dist;
        pick = k;
      }
    }
  }
  // A vertex already used by a bridge appears twice: take the copy whose corner opens towards M.
  if (!locallyInside(p, ring, pick, M))
    for (std::size_t k = 0; k < n; ++k)
      if (p[ring[k]] == p[ring[pick]] && locallyInside(p, ring, k, M)) {
        pick = k;
        break;
      }
  Ring merged;
  merged.reserve(n + hole.size() + 2);
  merged.insert(merged.end(), ring.begin(), ring.begin() + std::ptrdiff_t(pick) + 1);
  for (std::size_t i = 0; i <= hole.size(); ++i) merged.push_back(hole[(m + i) % hole.size()]);
  merged.insert(merged.end(), ring.begin() + std::ptrdiff_t(pick), ring.end());
  ring = std::move(merged);
  return true;
}

}  // namespace

glm::dvec3 newellNormal(const std::vector<glm::dvec3>& ring) {
  glm::dvec3 n(0.0);
  if (ring.empty()) return n;
  const glm::dvec3 o = ring[0];  // relative to a ring point: large coordinates keep precision
  for (std::size_t i = 0, k = ring.size(); i < k; ++i) {
    const glm::dvec3 a = ring[i] - o, b = ring[(i + 1) % k] - o;
    n +=
        glm::dvec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
  }
  return n;
}

EarClipResult earClip(const std::vector<std::vector<glm::dvec3>>& rings) {
  EarClipResult result;
  if (rings.empty() || rings[0].size() < 3) {
    result.status = EarClipStatus::Degenerate;
    return result;
  }
  // Projection onto the best-fit plane: u, v and the unit normal form a right-handed frame, so
  // the outer ring is counter-clockwise in (u, v).
  const glm::dvec3 normal = newellNormal(rings[0]);
  const glm::dvec3 o = rings[0][0];
  double extent = 0.0;
  for (const auto& q : rings[0]) extent = std::max(extent, glm::length(q - o));
  const double len = glm::length(normal);
  if (!(len > 1e-14 * extent * extent) || !std::isfinite(len)) {
    result.status = EarClipStatus::Degenerate;
    return result;
  }
  const glm::dvec3 w = normal / len;
  const glm::dvec3 axis = std::abs(w.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 u = glm::normalize(glm::cross(w, axis));
  const glm::dvec3 v = glm::cross(w, u);
  std::vector<glm::dvec2> p;
  std::vector<Ring> projected;
  for (const auto& ring : rings) {
    Ring r;
    for (const auto& q : ring) {
      r.push_back(std::uint32_t(p.size()));
      p.emplace_back(glm::dot(q - o, u), glm::dot(q - o, v));
    }
    projected.push_back(std::move(r));
  }
  const double minArea = 1e-14 * extent * extent;
  Ring outer = withoutDuplicates(p, projected[0]);
  double outerArea = outer.size() >= 3 ? signedArea(p, outer) : 0.0;
  if (outerArea < 0.0) {  // a figure of eight can project the wrong way round
    std::reverse(outer.begin(), outer.end());
    outerArea = -outerArea;
  }
  if (outer.size() < 3 || !(outerArea > minArea)) {
    result.status = EarClipStatus::Degenerate;
    return result;
  }
  // Holes clockwise, taken rightmost first (Eberly sec. 3: then each bridge sees only the outer
  // ring and the holes merged before it).
  std::vector<Ring> holes;
  for (std::size_t h = 1; h < projected.size(); ++h) {
    Ring r = withoutDuplicates(p, projected[h]);
    const double a = r.size() >= 3 ? signedArea(p, r) : 0.0;
    if (!(std::abs(a) > minArea)) {
      ++result.droppedHoles;
      continue;
    }
    if (a > 0.0) std::reverse(r.begin(), r.end());
    holes.push_back(std::move(r));
  }
  auto maxX = [&](const Ring& r) {
    double x = -std::numeric_limits<double>::infinity();
    for (auto i : r) x = std::max(x, p[i].x);
    return x;
  };
  std::sort(holes.begin(), holes.end(),
            [&](const Ring& a, const Ring& b) { return maxX(a) > maxX(b); });
  for (const Ring& hole : holes)
    if (!bridgeHole(p, outer, hole)) ++result.droppedHoles;

  // Ear clipping over a doubly linked list of the merged ring's positions.
  const std::size_t n = outer.size();
  std::vector<std::size_t> prev(n), next(n);
  for (std::size_t i = 0; i < n; ++i) {
    prev[i] = (i + n - 1) % n;
    next[i] = (i + 1) % n;
  }
  auto pt = [&](std::size_t k) -> const glm::dvec2& { return p[outer[k]]; };
  auto isEar = [&](std::size_t i) {
    const glm::dvec2 &a = pt(prev[i]), &b = pt(i), &c = pt(next[i]);
    if (!(cross(a, b, c) > 0.0)) return false;
    for (std::size_t k = next[next[i]]; k != prev[i]; k = next[k]) {
      const glm::dvec2& q = pt(k);
      // Bridge copies of the ear's corners are not inside it.
      if (q == a || q == b || q == c) continue;
      if (inTriangle(a, b, c, q)) return false;
    }
    return true;
  };
  auto emit = [&](std::size_t i) {
    result.triangles.push_back({outer[prev[i]], outer[i], outer[next[i]]});
  };
  auto unlink = [&](std::size_t i) {
    next[prev[i]] = next[i];
    prev[next[i]] = prev[i];
  };
  std::size_t remaining = n, i = 0, tried = 0;
  while (remaining > 3) {
    if (isEar(i)) {
      emit(i);
      unlink(i);
      --remaining;
      tried = 0;
      i = prev[i];  // the neighbours' corners changed: look at them first
      continue;
    }
    i = next[i];
    if (++tried < remaining) continue;
    // A whole round without an ear. First drop a corner without area (a spike, or a collinear
    // point the clipping left between two others), which costs no triangle.
    std::size_t k = i, stuck = n;
    do {
      if (cross(pt(prev[k]), pt(k), pt(next[k])) == 0.0) {
        stuck = k;
        break;
      }
      k = next[k];
    } while (k != i);
    if (stuck == n) {
      // Rounding or a self-intersecting ring: clip a convex corner anyway, and say so.
      result.status = EarClipStatus::Partial;
      do {
        if (cross(pt(prev[k]), pt(k), pt(next[k])) > 0.0) {
          stuck = k;
          break;
        }
        k = next[k];
      } while (k != i);
      if (stuck == n) return result;
      emit(stuck);
    }
    unlink(stuck);
    --remaining;
    i = next[stuck];
    tried = 0;
  }
  if (cross(pt(prev[i]), pt(i), pt(next[i])) > 0.0) emit(i);
  return result;
}

}  // namespace hlod
