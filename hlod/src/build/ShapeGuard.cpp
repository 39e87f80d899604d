// The guard around the simplifiers. Nodes are drawn with back faces culled, so a simplified
// triangle that faces away from the surface it stands for is a hole, one that stands off the
// surface is a shard, and a part of the surface that the simplifier dropped (a courtyard's thin
// paving collapsed onto its kerb, a box against a wall merged into the wall) is a hole the
// simplifier's own error estimate does not report. Each is measured against the original
// triangles, and the vertices where it happened are locked for another reduction; what remains
// after the last round is repaired directly: flipped triangles turned to face the surface,
// shards dropped, and the error raised to the distance measured.
#include "build/ShapeGuard.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "hlod/VertexClustering.h"
#include "hlod/metrics/SimplifiedFacing.h"
#include "hlod/metrics/SurfaceDistance.h"

namespace hlod {

namespace {

// Reductions after the first, each with the vertices of the last one's defects locked.
constexpr int kRepairRounds = 3;
// Vertices locked per round for dropped surface (the farthest first): enough to restore what a
// collapse removed, few enough that the level keeps its triangle budget.
constexpr std::size_t kHoleLocksPerRound = 64;
// A triangle standing off the surface by more than this many times the level's error is a
// shard (a flattened facade stands off its window recesses by about the error).
constexpr double kShardFactor = 2.0;

Mesh asMesh(const Simplifier::Shape& shape, const std::vector<std::uint32_t>& indices) {
  Mesh m;
  m.positions = shape.positions;
  m.indices = indices;
  return m;
}

Simplifier::ReducedShape reduceOnce(const Simplifier::Shape& shape, std::size_t target,
                                    const ReduceFn& reduce, bool mayCluster) {
  Simplifier::ReducedShape r = reduce(shape, target);
  // Edge collapses stop where every remaining collapse is illegal (non-manifold corners where
  // small boxes touch walls, flips); vertex clustering then takes the rest of the way.
  if (mayCluster && r.indices.size() / 3 > target + target / 4) {
    Simplifier::ReducedShape clustered = clusterVertices(shape, r.indices, target);
    clustered.geometricError = std::max(clustered.geometricError, r.geometricError);
    if (clustered.indices.size() < r.indices.size()) r = std::move(clustered);
  }
  return r;
}

// The unlocked vertex of `used` nearest p, or none.
std::uint32_t nearestUnlocked(const Simplifier::Shape& shape,
                              const std::vector<std::uint32_t>& used, const glm::dvec3& p) {
  std::uint32_t best = 0xffffffffu;
  double bestD = std::numeric_limits<double>::max();
  for (std::uint32_t v : used) {
    if (shape.locked[v]) continue;
    const glm::dvec3 d = shape.positions[v] - p;
    if (glm::dot(d, d) < bestD) bestD = glm::dot(d, d), best = v;
  }
  return best;
}

}  // namespace

Simplifier::ReducedShape guardedReduce(const Simplifier::Shape& shape, std::size_t targetTriangles,
                                       const ReduceFn& reduce) {
  const Mesh original = asMesh(shape, shape.indices);
  std::vector<std::uint32_t> used = shape.indices;
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  std::vector<glm::dvec3> usedPositions;
  for (std::uint32_t v : used) usedPositions.push_back(shape.positions[v]);
  const double floor = 1e-4 * glm::length(original.bounds().size());

  Simplifier::Shape work = shape;
  Simplifier::ReducedShape r;
  std::vector<metrics::TriangleFacing> facing;
  std::vector<double> dropped;  // per used vertex: its distance to the reduced surface
  double limit = floor;
  for (int round = 0; round <= kRepairRounds; ++round) {
    // Clustering only in the first round: later rounds may exceed the target (the locks are
    // what the shape needs), and clustering would undo them.
    r = reduceOnce(work, targetTriangles, reduce, round == 0);
    if (r.indices.empty()) return r;
    const Mesh reduced = asMesh(shape, r.indices);
    auto f = metrics::triangleFacing(original, reduced);
    auto d = metrics::pointDistances(reduced, usedPositions);
    if (!f || !d) return r;  // no area to compare with: nothing to guard
    facing = std::move(*f);
    dropped = std::move(*d);
    limit = std::max(r.geometricError, floor);
    if (round == kRepairRounds) break;
    // Lock, for each defect, the original vertex at its place.
    std::size_t locks = 0;
    for (std::size_t t = 0; t < facing.size(); ++t) {
      if (!facing[t].flipped && !(facing[t].off > limit)) continue;
      const glm::dvec3 c =
          (shape.positions[r.indices[3 * t]] + shape.positions[r.indices[3 * t + 1]] +
           shape.positions[r.indices[3 * t + 2]]) /
          3.0;
      const std::uint32_t v = nearestUnlocked(work, used, c);
      if (v != 0xffffffffu) work.locked[v] = 1, ++locks;
    }
    std::vector<std::size_t> far;
    for (std::size_t i = 0; i < used.size(); ++i)
      if (dropped[i] > limit && !work.locked[used[i]]) far.push_back(i);
    std::sort(far.begin(), far.end(),
              [&](std::size_t a, std::size_t b) { return dropped[a] > dropped[b]; });
    if (far.size() > kHoleLocksPerRound) far.resize(kHoleLocksPerRound);
    for (std::size_t i : far) work.locked[used[i]] = 1, ++locks;
    if (locks == 0) break;
  }
  // What the rounds left: a flipped triangle is turned to face the surface it lies on, a shard
  // goes, and the error is what was measured.
  Simplifier::ReducedShape out;
  out.geometricError = r.geometricError;
  for (std::size_t t = 0; t < facing.size(); ++t) {
    const std::uint32_t a = r.indices[3 * t], b = r.indices[3 * t + 1], c = r.indices[3 * t + 2];
    if (facing[t].hasArea && facing[t].off > kShardFactor * limit) continue;
    if (facing[t].flipped)
      out.indices.insert(out.indices.end(), {a, c, b});
    else
      out.indices.insert(out.indices.end(), {a, b, c});
    if (facing[t].hasArea) out.geometricError = std::max(out.geometricError, facing[t].off);
  }
  for (double x : dropped) out.geometricError = std::max(out.geometricError, x);
  return out;
}

}  // namespace hlod
