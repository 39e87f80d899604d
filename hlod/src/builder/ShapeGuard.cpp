// The guard around the simplifiers. Nodes are drawn with back faces culled, so a simplified
// triangle that faces away from the surface it stands for is a hole, one that stands off the
// surface is a shard, and a part of the surface that the simplifier dropped (a courtyard's thin
// paving collapsed onto its kerb, a box against a wall merged into the wall) is a hole the
// simplifier's own error estimate does not report. Each is measured against the original
// triangles; where surface was dropped or a shard stands, the vertices of every defect are locked
// for another reduction; what remains after the last round is repaired directly: flipped
// triangles turned to face the surface, shards dropped, and the error raised to the distance
// measured.
#include "builder/ShapeGuard.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "hlod/builder/VertexClustering.h"
#include "hlod/metrics/SimplifiedFacing.h"
#include "hlod/metrics/SurfaceDistance.h"

namespace hlod {

namespace {

// Reductions after the first, each with the vertices of the last one's defects locked.
constexpr int kRepairRounds = 1;
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
                                    double errorLimit, const ReduceFn& reduce, bool mayCluster) {
  Simplifier::ReducedShape r = reduce(shape, target, errorLimit);
  // Edge collapses stop where every remaining collapse is illegal (non-manifold corners where
  // small boxes touch walls, flips); vertex clustering then takes the rest of the way.
  if (mayCluster && r.indices.size() / 3 > target + target / 4) {
    Simplifier::ReducedShape clustered = clusterVertices(shape, r.indices, target);
    clustered.geometricError = std::max(clustered.geometricError, r.geometricError);
    // Not past the error limit: there the edge collapses' larger result keeps the shape.
    if (clustered.indices.size() < r.indices.size() && clustered.geometricError <= errorLimit)
      r = std::move(clustered);
  }
  return r;
}

// The unlocked vertex of `used` nearest p, or none.
std::uint32_t nearestUnlocked(const Simplifier::Shape& shape,
                              const std::vector<std::uint32_t>& used, const glm::dvec3& p) {
  std::uint32_t best = 0xffffffffu;
  double bestD = std::numeric_limits<double>::max();
  for (std::uint32_t v : used) {
    if (shape.locked[v] == kVertexLocked) continue;
    const glm::dvec3 d = shape.positions[v] - p;
    if (glm::dot(d, d) < bestD) bestD = glm::dot(d, d), best = v;
  }
  return best;
}

}  // namespace

Simplifier::ReducedShape guardedReduce(const Simplifier::Shape& shape, std::size_t targetTriangles,
                                       double errorLimit, const ReduceFn& reduce,
                                       bool clusterEveryRound) {
  const Mesh original = asMesh(shape, shape.indices);
  // The vertices the triangles use, ascending.
  std::vector<std::uint32_t> used;
  {
    std::vector<std::uint8_t> isUsed(shape.positions.size(), 0);
    for (std::uint32_t v : shape.indices) isUsed[v] = 1;
    for (std::uint32_t v = 0; v < isUsed.size(); ++v)
      if (isUsed[v]) used.push_back(v);
  }
  const double floor = 1e-4 * glm::length(original.bounds().size());
  // The spacing of targetTriangles triangles spread evenly over the surface: a simplification
  // to that many triangles need not deviate by more, whatever error the simplifier allowed
  // itself (edge collapses on a block's cut pieces reported 11 m on pieces 9 m wide).
  double area = 0.0;
  for (std::size_t i = 0; i + 2 < shape.indices.size(); i += 3) {
    const glm::dvec3& a = shape.positions[shape.indices[i]];
    area += 0.5 * glm::length(glm::cross(shape.positions[shape.indices[i + 1]] - a,
                                         shape.positions[shape.indices[i + 2]] - a));
  }
  const double spacing = std::sqrt(area / double(std::max<std::size_t>(1, targetTriangles)));
  // Enough samples that a courtyard's two paving triangles (under 1% of a block's area) get
  // a dozen.
  const std::size_t samples = std::clamp<std::size_t>(8 * targetTriangles, 2000, 20000);

  auto checker = metrics::FacingChecker::create(original);
  if (!checker)
    return reduceOnce(shape, targetTriangles, errorLimit, reduce, true);  // no area to guard
  // The same samples in every round (and the same as one farSamples call each would take).
  auto sampler = metrics::FarSampler::create(original, samples);

  Simplifier::Shape work = shape;
  Simplifier::ReducedShape r;
  std::vector<metrics::TriangleFacing> facing;
  std::vector<metrics::FarSample> lost;
  double farthest = 0.0;  // of all samples, from the last round's reduction
  double limit = floor;
  for (int round = 0; round <= kRepairRounds; ++round) {
    // Clustering only in the first round: later rounds may exceed the target (the locks are
    // what the shape needs), and clustering would undo them.
    r = reduceOnce(work, targetTriangles, errorLimit, reduce, round == 0 || clusterEveryRound);
    if (r.indices.empty()) return r;
    const Mesh reduced = asMesh(shape, r.indices);
    // The simplifier's own estimate plays no part: edge collapses underestimate what they drop
    // (OpenMesh reported 0 for a wall losing 8 m), and where they overestimate they went astray.
    limit = std::max(std::min(spacing, errorLimit), floor);
    auto f = checker->check(reduced, limit);
    auto l = sampler ? sampler->measure(reduced, limit, &farthest) : sampler.error();
    if (!f || !l) return r;  // no area to compare with: nothing to guard
    facing = std::move(*f);
    lost = std::move(*l);
    if (round == kRepairRounds) break;
    // Another round only for dropped surface or shards, which the locks restore. Flipped
    // triangles alone do not pay for one: with their vertices locked the collapses flip about as
    // many others instead, and the repair below turns them either way.
    const bool shards =
        std::any_of(facing.begin(), facing.end(), [&](const auto& tf) { return tf.off > limit; });
    if (lost.empty() && !shards) break;
    // Lock, for each defect, the original vertex at its place.
    std::size_t locks = 0;
    for (std::size_t t = 0; t < facing.size(); ++t) {
      if (!facing[t].flipped && !(facing[t].off > limit)) continue;
      const glm::dvec3 c =
          (shape.positions[r.indices[3 * t]] + shape.positions[r.indices[3 * t + 1]] +
           shape.positions[r.indices[3 * t + 2]]) /
          3.0;
      const std::uint32_t v = nearestUnlocked(work, used, c);
      if (v != 0xffffffffu) work.locked[v] = kVertexLocked, ++locks;
    }
    // Lost surface, the farthest first: the corner of the sample's triangle nearest to it.
    std::sort(lost.begin(), lost.end(),
              [](const metrics::FarSample& a, const metrics::FarSample& b) {
                return a.distance > b.distance;
              });
    std::size_t holeLocks = 0;
    for (const metrics::FarSample& x : lost) {
      if (holeLocks == kHoleLocksPerRound) break;
      std::uint32_t best = 0xffffffffu;
      double bestD = std::numeric_limits<double>::max();
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = shape.indices[3 * std::size_t(x.triangle) + k];
        const double d = glm::length(shape.positions[v] - x.point);
        if (work.locked[v] != kVertexLocked && d < bestD) bestD = d, best = v;
      }
      if (best != 0xffffffffu) work.locked[best] = kVertexLocked, ++holeLocks;
    }
    locks += holeLocks;
    if (locks == 0) break;
  }
  // What the rounds left: a flipped triangle is turned to face the surface it lies on, a shard
  // goes, and the error is what was measured.
  Simplifier::ReducedShape out;
  out.geometricError = r.geometricError;
  for (std::size_t t = 0; t < facing.size(); ++t) {
    const std::uint32_t a = r.indices[3 * t], b = r.indices[3 * t + 1], c = r.indices[3 * t + 2];
    // (Never one with a cut vertex: its neighbour node keeps that vertex on the seam.)
    const bool cut = shape.locked[a] || shape.locked[b] || shape.locked[c];
    if (!cut && facing[t].hasArea && facing[t].off > kShardFactor * limit) continue;
    if (facing[t].flipped)
      out.indices.insert(out.indices.end(), {a, c, b});
    else
      out.indices.insert(out.indices.end(), {a, b, c});
    if (facing[t].hasArea) out.geometricError = std::max(out.geometricError, facing[t].off);
  }
  // The error is what was measured: the lost surface beyond the simplifier's own estimate. The
  // last round measured every sample already, unless shards went since.
  if (out.indices.size() == r.indices.size()) {
    out.geometricError = std::max(out.geometricError, farthest);
  } else if (!out.indices.empty()) {
    auto beyond = sampler->measure(asMesh(shape, out.indices), out.geometricError);
    if (beyond)
      for (const metrics::FarSample& x : *beyond)
        out.geometricError = std::max(out.geometricError, x.distance);
  }
  return out;
}

}  // namespace hlod
