#include "hlod/metrics/SurfaceDistance.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "hlod/metrics/TriangleBvh.h"

namespace hlod::metrics {

namespace {

// The mesh's triangles as corner triples, or the Error that makes it unusable.
Result<std::vector<Triangle>> triangles(const Mesh& mesh, const char* role) {
  const std::string what = std::string("surface distance: mesh ") + role;
  if (mesh.indices.empty()) return makeError(what + " has no triangles");
  if (mesh.indices.size() % 3 != 0) {
    return makeError(what + " has " + std::to_string(mesh.indices.size()) +
                     " indices, not a multiple of 3");
  }
  for (const glm::dvec3& p : mesh.positions) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      return makeError(what + " has a non-finite position");
    }
  }
  std::vector<Triangle> out(mesh.indices.size() / 3);
  for (std::size_t i = 0; i < mesh.indices.size(); ++i) {
    if (mesh.indices[i] >= mesh.positions.size()) {
      return makeError(what + ": index " + std::to_string(mesh.indices[i]) + " out of range (" +
                       std::to_string(mesh.positions.size()) + " positions)");
    }
    out[i / 3][i % 3] = mesh.positions[mesh.indices[i]];
  }
  return out;
}

double area(const Triangle& t) {
  return 0.5 * glm::length(glm::cross(t[1] - t[0], t[2] - t[0]));
}

// A double in [0, 1) from the top 53 bits: std::mt19937_64's output is fixed by the standard,
// unlike std::uniform_real_distribution's, so the samples are the same on every platform.
double unitRandom(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

// Area-weighted points on the triangles: a triangle by its share of the area (inverse of the
// cumulative areas), then a uniform point in it (the square root warps two uniform numbers onto
// the triangle without bunching at a corner).
Result<std::vector<glm::dvec3>> samplePoints(const std::vector<Triangle>& tris, std::size_t count,
                                             std::mt19937_64& rng, const char* role,
                                             std::vector<std::uint32_t>* source = nullptr) {
  std::vector<double> cumulative(tris.size());
  double total = 0.0;
  for (std::size_t i = 0; i < tris.size(); ++i) {
    total += area(tris[i]);
    cumulative[i] = total;
  }
  if (!(total > 0.0) || !std::isfinite(total)) {
    return makeError(std::string("surface distance: mesh ") + role + " has no surface area");
  }
  std::vector<glm::dvec3> points(count);
  if (source) source->resize(count);
  for (std::size_t k = 0; k < count; ++k) {
    glm::dvec3& p = points[k];
    const double r = unitRandom(rng) * total;
    const std::size_t i = std::min<std::size_t>(
        std::upper_bound(cumulative.begin(), cumulative.end(), r) - cumulative.begin(),
        tris.size() - 1);
    const double s = std::sqrt(unitRandom(rng));
    const double v = unitRandom(rng);
    const Triangle& t = tris[i];
    p = (1.0 - s) * t[0] + s * (1.0 - v) * t[1] + s * v * t[2];
    if (source) (*source)[k] = std::uint32_t(i);
  }
  return points;
}

}  // namespace

Result<SurfaceDistance> surfaceDistance(const Mesh& a, const Mesh& b, std::size_t samplesPerMesh,
                                        std::uint64_t seed) {
  if (samplesPerMesh == 0) return makeError("surface distance: samplesPerMesh must be > 0");
  Result<std::vector<Triangle>> trisA = triangles(a, "a");
  if (!trisA) return trisA.error();
  Result<std::vector<Triangle>> trisB = triangles(b, "b");
  if (!trisB) return trisB.error();
  std::mt19937_64 rng(seed);
  Result<std::vector<glm::dvec3>> onA = samplePoints(*trisA, samplesPerMesh, rng, "a");
  if (!onA) return onA.error();
  Result<std::vector<glm::dvec3>> onB = samplePoints(*trisB, samplesPerMesh, rng, "b");
  if (!onB) return onB.error();

  SurfaceDistance d;
  double sumSquares = 0.0;
  const auto measure = [&](const std::vector<glm::dvec3>& points, const TriangleBvh& other) {
    double sum = 0.0;
    for (const glm::dvec3& p : points) {
      const double distance = other.distance(p);
      sum += distance;
      sumSquares += distance * distance;
      d.hausdorff = std::max(d.hausdorff, distance);
    }
    return sum / static_cast<double>(points.size());
  };
  d.meanAB = measure(*onA, TriangleBvh(std::move(*trisB)));
  d.meanBA = measure(*onB, TriangleBvh(std::move(*trisA)));
  d.samples = 2 * samplesPerMesh;
  d.rms = std::sqrt(sumSquares / static_cast<double>(d.samples));
  return d;
}

Result<std::vector<FarSample>> farSamples(const Mesh& original, const Mesh& simplified,
                                          std::size_t samples, double limit, std::uint64_t seed) {
  Result<FarSampler> sampler = FarSampler::create(original, samples, seed);
  if (!sampler) return sampler.error();
  return sampler->measure(simplified, limit);
}

Result<FarSampler> FarSampler::create(const Mesh& original, std::size_t samples,
                                      std::uint64_t seed) {
  if (samples == 0) return makeError("far samples: samples must be > 0");
  Result<std::vector<Triangle>> tris = triangles(original, "a");
  if (!tris) return tris.error();
  std::mt19937_64 rng(seed);
  FarSampler s;
  Result<std::vector<glm::dvec3>> points = samplePoints(*tris, samples, rng, "a", &s.source_);
  if (!points) return points.error();
  s.points_ = std::move(*points);
  s.order_.resize(s.points_.size());
  std::iota(s.order_.begin(), s.order_.end(), 0u);
  std::stable_sort(s.order_.begin(), s.order_.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return s.source_[a] < s.source_[b]; });
  return s;
}

Result<std::vector<FarSample>> FarSampler::measure(const Mesh& simplified, double limit,
                                                   double* maxDistance) const {
  Result<std::vector<Triangle>> tris = triangles(simplified, "b");
  if (!tris) return tris.error();
  const TriangleBvh bvh(std::move(*tris));
  const double limit2 = limit * limit;
  // The largest squared distance so far: a point within it (or within the limit, once the
  // largest is past it) changes nothing, and that takes only the first triangle found.
  double max2 = maxDistance ? 0.0 : limit2;
  std::uint32_t hint = TriangleBvh::kNoHint;
  std::vector<std::pair<std::uint32_t, FarSample>> far;
  for (std::uint32_t k : order_) {
    const glm::dvec3& p = points_[k];
    if (bvh.within2(p, std::min(max2, limit2), hint)) continue;
    const double d2 = bvh.distance2(p);
    max2 = std::max(max2, d2);
    if (!(d2 <= limit2)) far.emplace_back(k, FarSample{p, source_[k], std::sqrt(d2)});
  }
  if (maxDistance) *maxDistance = std::sqrt(max2);
  // In the order of the samples, as farSamples gives them.
  std::sort(far.begin(), far.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<FarSample> out;
  out.reserve(far.size());
  for (const auto& [k, x] : far) out.push_back(x);
  return out;
}

}  // namespace hlod::metrics
