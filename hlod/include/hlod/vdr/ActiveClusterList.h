#pragma once
// The active cluster list of Manocha sec. 5.1 and 5.1.1, for one object: "the active vertex
// front or list and active face list are divided among the clusters so that each cluster
// maintains its own portion of the active lists. Only clusters that contain vertices on the
// active front need to be considered during refining and rendering. These clusters are stored as
// an active cluster list." and "A vertex that is split may have children that belong to a
// different cluster. The children vertices are activated in their containing clusters and these
// clusters are added to the active cluster list if they were not previously active. Similarly,
// during an edge collapse operation, the parent vertex is activated in its containing cluster
// and that cluster is added to the active cluster list. When the last vertex of a cluster is
// deactivated, the cluster is removed from the active cluster list."
// A live face belongs to the cluster of the vertex at its first corner (always an active
// cluster). A cluster whose faces or their corners changed is marked changed, so that only
// those are rebuilt for drawing.
#include <cstdint>
#include <span>
#include <vector>

#include "hlod/vdr/ActiveMesh.h"
#include "hlod/vdr/ClusterHierarchy.h"
#include "hlod/vdr/ViewRefinement.h"

namespace hlod::vdr {

class ActiveClusterList final : public RefineObserver {
 public:
  // The lists of mesh's present state; then kept up to date through split() and collapsed(),
  // which the refinement calls after each operation on mesh.
  ActiveClusterList(const ActiveMesh& mesh, const ClusterHierarchy& clusters);

  void split(std::uint32_t v) override;
  void collapsed(std::uint32_t v) override;

  // The active clusters, in no particular order.
  std::span<const std::uint32_t> activeClusters() const { return active_; }
  bool isActive(std::uint32_t cluster) const { return activeSlot_[cluster] != kNone; }
  std::span<const std::uint32_t> activeVertices(std::uint32_t cluster) const {
    return vertices_[cluster];
  }
  std::span<const std::uint32_t> faces(std::uint32_t cluster) const { return faces_[cluster]; }
  // Every active vertex of every active cluster.
  std::vector<std::uint32_t> allActiveVertices() const;

  // Clusters whose faces changed since the last takeChanged(), each once; clears the marks.
  std::vector<std::uint32_t> takeChanged();
  // Increases whenever the cluster's faces change.
  std::uint32_t version(std::uint32_t cluster) const { return version_[cluster]; }

 private:
  void activate(std::uint32_t v);
  void deactivate(std::uint32_t v);
  void touchFaces();
  void markChanged(std::uint32_t cluster);

  const ActiveMesh& mesh_;
  const ClusterHierarchy& clusters_;
  std::vector<std::vector<std::uint32_t>> vertices_;  // per cluster: its active vertices
  std::vector<std::uint32_t> vertexSlot_;             // per vertex: its place there, or kNone
  std::vector<std::vector<std::uint32_t>> faces_;     // per cluster: its live faces
  std::vector<std::uint32_t> owner_;                  // per face: its cluster, or kNone
  std::vector<std::uint32_t> faceSlot_;               // per face: its place there
  std::vector<std::uint32_t> active_;                 // the active cluster list
  std::vector<std::uint32_t> activeSlot_;             // per cluster: its place there, or kNone
  std::vector<std::uint32_t> version_;
  std::vector<std::uint8_t> changed_;
  std::vector<std::uint32_t> changedList_;
};

}  // namespace hlod::vdr
