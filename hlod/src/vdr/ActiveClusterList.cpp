// The active cluster list (Manocha sec. 5.1, 5.1.1). See hlod/vdr/ActiveClusterList.h.
#include "hlod/vdr/ActiveClusterList.h"

#include <cassert>

namespace hlod::vdr {

namespace {

// Removes the element at slot[x] from list by moving the last one into its place.
void eraseAt(std::vector<std::uint32_t>& list, std::vector<std::uint32_t>& slot, std::uint32_t x) {
  const std::uint32_t at = slot[x];
  assert(at < list.size() && list[at] == x);
  const std::uint32_t moved = list.back();
  list[at] = moved;
  slot[moved] = at;
  list.pop_back();
  slot[x] = kNone;
}

}  // namespace

ActiveClusterList::ActiveClusterList(const ActiveMesh& mesh, const ClusterHierarchy& clusters)
    : mesh_(mesh), clusters_(clusters) {
  const VertexHierarchy& h = mesh.hierarchy();
  const std::size_t k = clusters.clusters.size();
  vertices_.resize(k);
  faces_.resize(k);
  vertexSlot_.assign(h.vertexCount(), kNone);
  owner_.assign(h.faces.size(), kNone);
  faceSlot_.assign(h.faces.size(), kNone);
  activeSlot_.assign(k, kNone);
  version_.assign(k, 0);
  changed_.assign(k, 0);
  for (std::uint32_t v : mesh.activeVertices()) activate(v);
  for (std::uint32_t t : mesh.liveFaces()) {
    const std::uint32_t c = clusters_.clusterOf[mesh.corners(t)[0]];
    owner_[t] = c;
    faceSlot_[t] = std::uint32_t(faces_[c].size());
    faces_[c].push_back(t);
    markChanged(c);
  }
}

void ActiveClusterList::markChanged(std::uint32_t c) {
  ++version_[c];
  if (!changed_[c]) {
    changed_[c] = 1;
    changedList_.push_back(c);
  }
}

void ActiveClusterList::activate(std::uint32_t v) {
  const std::uint32_t c = clusters_.clusterOf[v];
  vertexSlot_[v] = std::uint32_t(vertices_[c].size());
  vertices_[c].push_back(v);
  if (activeSlot_[c] == kNone) {
    activeSlot_[c] = std::uint32_t(active_.size());
    active_.push_back(c);
  }
}

void ActiveClusterList::deactivate(std::uint32_t v) {
  const std::uint32_t c = clusters_.clusterOf[v];
  eraseAt(vertices_[c], vertexSlot_, v);
  // "When the last vertex of a cluster is deactivated, the cluster is removed."
  if (vertices_[c].empty()) eraseAt(active_, activeSlot_, c);
}

void ActiveClusterList::touchFaces() {
  for (std::uint32_t t : mesh_.touchedFaces()) {
    const std::uint32_t old = owner_[t];
    const std::uint32_t now = mesh_.isLive(t) ? clusters_.clusterOf[mesh_.corners(t)[0]] : kNone;
    if (old != now) {
      if (old != kNone) {
        // faceSlot_ is shared by every cluster's list: a face is in one at a time.
        eraseAt(faces_[old], faceSlot_, t);
      }
      if (now != kNone) {
        faceSlot_[t] = std::uint32_t(faces_[now].size());
        faces_[now].push_back(t);
      }
      owner_[t] = now;
    }
    if (old != kNone) markChanged(old);
    if (now != kNone) markChanged(now);
  }
}

void ActiveClusterList::split(std::uint32_t v) {
  const VertexHierarchy& h = mesh_.hierarchy();
  // Children first: a cluster that holds v and a child stays on the list throughout.
  activate(h.kept(v));
  activate(h.removed(v));
  deactivate(v);
  touchFaces();
}

void ActiveClusterList::collapsed(std::uint32_t v) {
  const VertexHierarchy& h = mesh_.hierarchy();
  activate(v);
  deactivate(h.kept(v));
  deactivate(h.removed(v));
  touchFaces();
}

std::vector<std::uint32_t> ActiveClusterList::allActiveVertices() const {
  std::vector<std::uint32_t> out;
  for (std::uint32_t c : active_) out.insert(out.end(), vertices_[c].begin(), vertices_[c].end());
  return out;
}

std::vector<std::uint32_t> ActiveClusterList::takeChanged() {
  for (std::uint32_t c : changedList_) changed_[c] = 0;
  std::vector<std::uint32_t> out = std::move(changedList_);
  changedList_.clear();
  return out;
}

}  // namespace hlod::vdr
