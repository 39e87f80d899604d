#pragma once
// Geometric error of a simplified mesh against its original: the symmetric distance between the
// two surfaces, estimated by sampling (as Metro: Cignoni, Rocchini, Scopigno, "Metro: Measuring
// Error on Simplified Surfaces", Computer Graphics Forum 17(2), 1998).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "hlod/Mesh.h"
#include "hlod/Result.h"

namespace hlod::metrics {

// Distances in the meshes' units.
struct SurfaceDistance {
  double hausdorff = 0;     // the largest distance found, over both directions
  double rms = 0;           // root mean square over all samples of both directions
  double meanAB = 0;        // mean distance from a's samples to b's surface
  double meanBA = 0;        // mean distance from b's samples to a's surface
  std::size_t samples = 0;  // samples taken in all: 2 * samplesPerMesh
};

// Samples samplesPerMesh points on each mesh's surface (area-weighted, uniform within a
// triangle, from a fixed pseudo-random sequence of seed: the same inputs give the same result on
// every platform) and measures each one's distance to the closest point of the other mesh's
// triangles (exact point-triangle distance through a bounding volume hierarchy). Degenerate
// (zero-area) triangles are never sampled and count as their edges for the distance, so they
// give no NaN. An Error for a mesh without triangles, an index out of range, a non-finite
// position, a mesh whose triangles have no area in all, or samplesPerMesh 0.
Result<SurfaceDistance> surfaceDistance(const Mesh& a, const Mesh& b,
                                        std::size_t samplesPerMesh = 100000,
                                        std::uint64_t seed = 1);

// Surface of original that simplified lost: of samples points on original (area-weighted, as
// surfaceDistance), those farther than limit from simplified's triangles, with the triangle of
// original each lies on (its index among original's triangles) and its distance. The same
// checks on both meshes as surfaceDistance.
struct FarSample {
  glm::dvec3 point{0.0};
  std::uint32_t triangle = 0;
  double distance = 0.0;
};
Result<std::vector<FarSample>> farSamples(const Mesh& original, const Mesh& simplified,
                                          std::size_t samples, double limit,
                                          std::uint64_t seed = 1);

// farSamples for many simplifications of one original: its samples are taken once.
class FarSampler {
 public:
  // An Error for the originals farSamples refuses, or samples 0.
  static Result<FarSampler> create(const Mesh& original, std::size_t samples,
                                   std::uint64_t seed = 1);
  // farSamples(original, simplified, samples, limit, seed); with maxDistance, also the largest
  // distance of any sample (however near).
  Result<std::vector<FarSample>> measure(const Mesh& simplified, double limit,
                                         double* maxDistance = nullptr) const;

 private:
  std::vector<glm::dvec3> points_;
  std::vector<std::uint32_t> source_;  // per point, its triangle of the original
  std::vector<std::uint32_t> order_;   // the points by triangle: neighbours measured in a row
};

}  // namespace hlod::metrics
