#pragma once
// The run-time state of view-dependent rendering for a set of objects (a store's blocks): each
// object's active front (ActiveMesh) and active cluster list, refined per frame to an error bound
// (Manocha sec. 5.1), and the clusters seen as nodes of a skeleton of their own, so that they are
// drawn, sorted, culled and queried as nodes are (Fig. 4: clusters are the units of occlusion
// culling; a cluster's box is that of its live faces now).
//
// The cluster skeleton: one node per cluster of every object, numbered object by object; a
// cluster's children (C_l, C_r of sec. 3.1) follow it; the roots are each object's first
// cluster; level = the cluster's depth; block = the object. Its boxes, triangle counts, cost
// (Lakhia eq. 1: triangles times c_tex for textured objects, 1 - c_tex otherwise) and
// geometricError (the largest error of the cluster's active vertices) follow the front after
// each refine(). A cluster without active vertices or faces has an empty box and no triangles;
// an object's first cluster's box always holds the whole object, so that the roots' boxes hold
// the model (what clip planes and default views are fitted to).
#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "hlod/Mesh.h"
#include "hlod/Result.h"
#include "hlod/runtime/Camera.h"
#include "hlod/store/Skeleton.h"
#include "hlod/vdr/ActiveClusterList.h"
#include "hlod/vdr/ActiveMesh.h"
#include "hlod/vdr/ClusterArrays.h"
#include "hlod/vdr/VdrObject.h"
#include "hlod/vdr/ViewRefinement.h"

namespace hlod {
class NodeStore;
}

namespace hlod::vdr {

class VdrRuntime {
 public:
  // Every object starts at its coarsest (its roots active). cTex: eq. 1's c_tex.
  VdrRuntime(std::vector<std::shared_ptr<const VdrObject>> objects, double cTex);
  // All the objects of a store's view-dependent section; an Error when it has none (a store
  // built without --vdr) or one does not decode.
  static Result<std::unique_ptr<VdrRuntime>> open(const NodeStore& store);

  const Skeleton& skeleton() const { return skeleton_; }
  std::size_t objectCount() const { return objects_.size(); }
  const VdrObject& object(std::size_t i) const { return *objects_[i].object; }

  // Refines every object's active clusters to `bound` pixels for the view (refineToBound over
  // each active cluster list), then brings the changed clusters' skeleton nodes up to date.
  RefineCounters refine(const ErrorProjection& projection, double bound);
  // The clusters on the active cluster lists, of all objects.
  std::uint32_t activeClusterCount() const;
  // The active clusters with faces whose box meets the frustum, ascending, and their summed cost.
  std::vector<std::uint32_t> visibleClusters(const Frustum& frustum, double* cost = nullptr) const;

  // The arrays to draw a cluster with now (ClusterArrays.h: its vertex array when at least
  // minActiveRatio of its vertices are active, else a compacted one), and whether that was the
  // vertex array.
  LocalMesh clusterArrays(std::uint32_t cluster, double minActiveRatio, ArrayForm* form = nullptr);
  // Changes whenever the cluster's faces change: a drawn copy of another version is stale.
  std::uint64_t version(std::uint32_t cluster) const;

  // The CPU time of this frame's refinement, recorded by the selector and taken (once) by the
  // renderer, which counts it in the frame.
  void addRefineMs(double ms) { refineMs_ += ms; }
  double takeRefineMs() { return std::exchange(refineMs_, 0.0); }

  // Each object's front as a mesh (ActiveMesh's currentMesh), for tests and tools.
  Mesh currentMesh(std::size_t object) const;
  const ActiveMesh& mesh(std::size_t object) const { return *objects_[object].mesh; }

 private:
  struct Object {
    std::shared_ptr<const VdrObject> object;
    std::unique_ptr<ActiveMesh> mesh;
    std::unique_ptr<ActiveClusterList> list;
    std::uint32_t firstCluster = 0;                  // its first cluster's node in skeleton_
    Aabb bounds;                                     // the object's
    std::vector<std::vector<std::uint32_t>> wedges;  // clusterWedges, made on first use
    ArrayScratch scratch;
  };
  void update(Object& o, std::span<const std::uint32_t> changed);
  std::pair<std::size_t, std::uint32_t> locate(std::uint32_t cluster) const;

  std::vector<Object> objects_;
  std::vector<std::uint32_t> objectOf_;  // per cluster node
  double cTex_;
  Skeleton skeleton_;
  double refineMs_ = 0.0;
};

}  // namespace hlod::vdr
