#pragma once
// The per-frame refinement of the active front (Manocha sec. 5.1): "We traverse its active
// vertex list and use the aforementioned vertex error value to compute which vertices need to be
// split or collapsed. The error value is projected onto the screen and used as a bound on the
// deviation of the surface in screen pixels. Vertex splits are performed recursively on front
// vertices that do not satisfy the bound. For sibling pairs that meet the error bound, we
// recursively check whether their parent vertex also meets the error bound and if so, collapse
// the edge (or virtual edge) between the vertex pair."
// Every operation passes the neighbourhood test (ActiveMesh). A split the test refuses because a
// neighbour is coarser than when the vertex was made splits that neighbour first, recursively
// (Hoppe 1997's force_vsplit): without it a vertex next to a coarse region could never refine.
// Collapses are tried in the order the build made them (parents of lower index first): a pair
// the test refuses then waits only on a finer neighbour that does not meet the bound itself.
// The error is projected over the nearest point of the vertex's sphere (VertexHierarchy::radius),
// so a parent's projected error is never below its child's, and a vertex whose sphere lies
// outside the view frustum projects to 0 (the regions out of view coarsen, as in Hoppe 1997).
#include <cstdint>
#include <optional>
#include <span>

#include "hlod/runtime/Camera.h"
#include "hlod/vdr/ActiveMesh.h"

namespace hlod::vdr {

// A vertex's error in pixels for one view: error * pixelsPerUnit / distance, the distance from
// the eye to the nearest point of its sphere (at least minDistance).
struct ErrorProjection {
  glm::dvec3 eye{0.0};
  // Pixels one world unit covers face-on at distance 1: viewport height / (2 tan(fovY / 2)).
  double pixelsPerUnit = 1.0;
  double minDistance = 1e-3;
  // false: error * pixelsPerUnit wherever the eye is (a bound in world units, for tests).
  bool perspective = true;
  std::optional<Frustum> frustum;

  // For a camera and a viewport height in pixels.
  static ErrorProjection of(const Camera& camera, int viewportHeight);
  double operator()(const VertexHierarchy& h, std::uint32_t v) const;
};

struct RefineCounters {
  std::uint32_t splits = 0;        // all vertex splits, the forced ones included
  std::uint32_t forcedSplits = 0;  // of them, made for a neighbour's split
  std::uint32_t collapses = 0;
};

// Told of each operation as it is made (the mesh's touchedFaces() are its faces).
class RefineObserver {
 public:
  virtual ~RefineObserver() = default;
  virtual void split(std::uint32_t v) = 0;
  virtual void collapsed(std::uint32_t v) = 0;
};

// Refines and coarsens the front around `vertices` (active vertices: those of the clusters to
// refine; stale entries are skipped) until each of them and each vertex made from them meets
// the bound or is a leaf, and no sibling pair among them has a parent that meets it and can be
// collapsed. Collapses first, then splits.
RefineCounters refineToBound(ActiveMesh& mesh, std::span<const std::uint32_t> vertices,
                             const ErrorProjection& projection, double bound,
                             RefineObserver* observer = nullptr);

}  // namespace hlod::vdr
