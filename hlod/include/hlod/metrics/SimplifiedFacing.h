#pragma once
// Facing of a simplified surface against its original. Nodes are drawn with back faces culled:
// a simplified triangle that faces away from the surface it stands for vanishes from where that
// surface is seen (a collapse that turned a triangle over becomes a hole), and a triangle that
// stands off the surface (a sliver of vertex clustering joining two walls) shows as a shard.
#include <cstddef>
#include <limits>
#include <memory>
#include <vector>

#include "hlod/Mesh.h"
#include "hlod/Result.h"

namespace hlod::metrics {

struct FacingReport {
  std::size_t triangles = 0;    // simplified triangles with area
  std::size_t flipped = 0;      // of them, facing away from the nearest original surface
  std::size_t standingOff = 0;  // of them, with a checked point farther than offLimit from it
  double area = 0.0;            // of the triangles with area
  double flippedArea = 0.0;     // of the flipped ones
  double maxOff = 0.0;          // the largest distance of a checked point to the original
};

// One simplified triangle, checked against the original surface.
struct TriangleFacing {
  bool hasArea = false;  // false: a needle or a point (it covers no pixel; neither test applies)
  bool flipped = false;  // faces away from the nearest original surface
  double off = 0.0;      // the farthest of its centroid and edge midpoints from the original
};

// Per triangle of simplified, in order (the rules of checkFacing below).
Result<std::vector<TriangleFacing>> triangleFacing(const Mesh& original, const Mesh& simplified);

// The same for many simplifications of one original, which is indexed once.
class FacingChecker {
 public:
  // An Error for the original meshes checkFacing refuses.
  static Result<FacingChecker> create(const Mesh& original);
  // With offLimit, off is measured exactly only where it exceeds offLimit (0 elsewhere): the
  // distance queries stop at the first face within the limit.
  Result<std::vector<TriangleFacing>> check(const Mesh& simplified, double offLimit = 0.0) const;

  FacingChecker(FacingChecker&&) noexcept;
  FacingChecker& operator=(FacingChecker&&) noexcept;
  ~FacingChecker();

 private:
  struct Index;
  explicit FacingChecker(std::unique_ptr<Index> index);
  std::unique_ptr<Index> index_;
};

// Checks every simplified triangle with area (a needle, whose area is below 1e-9 of its longest
// edge squared, has none: its normal is rounding noise). Facing: at its centroid, the original
// triangles nearest to it (within a millionth of the original's bounding diagonal of the closest,
// so that over an edge or a corner every face meeting there counts); the triangle is flipped when
// its normal opposes every one of theirs (dot product below -0.001: a triangle standing at right
// angles to the surface is no flip). Standing off: the centroid and the three edge midpoints are
// measured to the original surface; one farther than offLimit makes the triangle count. An Error
// for meshes without triangles, indices out of range, non-finite positions, or an original
// without area.
Result<FacingReport> checkFacing(const Mesh& original, const Mesh& simplified,
                                 double offLimit = std::numeric_limits<double>::infinity());
// The same against an original indexed once (many simplifications of one original).
Result<FacingReport> checkFacing(const FacingChecker& checker, const Mesh& simplified,
                                 double offLimit = std::numeric_limits<double>::infinity());

}  // namespace hlod::metrics
