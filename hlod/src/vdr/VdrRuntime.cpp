// The run-time state of view-dependent rendering (Manocha sec. 5.1). See hlod/vdr/VdrRuntime.h.
#include "hlod/vdr/VdrRuntime.h"

#include <algorithm>
#include <cassert>

#include "hlod/store/NodeStore.h"

namespace hlod::vdr {

VdrRuntime::VdrRuntime(std::vector<std::shared_ptr<const VdrObject>> objects, double cTex)
    : cTex_(cTex) {
  objects_.resize(objects.size());
  for (std::size_t i = 0; i < objects.size(); ++i) {
    Object& o = objects_[i];
    o.object = std::move(objects[i]);
    const VdrObject& obj = *o.object;
    o.bounds = obj.bounds();
    o.firstCluster = std::uint32_t(skeleton_.nodes.size());
    skeleton_.roots.push_back(o.firstCluster);
    for (const Cluster& c : obj.clusters.clusters) {
      NodeInfo n;
      n.parent = c.parent == kNone ? kNoNode : o.firstCluster + c.parent;
      if (c.children[0] != kNone) {
        // The two children of sec. 3.1 are made together: contiguous, as the skeleton needs.
        assert(c.children[1] == kNone || c.children[1] == c.children[0] + 1);
        n.firstChild = o.firstCluster + c.children[0];
        n.childCount = c.children[1] == kNone ? 1 : 2;
      }
      n.level = c.depth;
      n.block = std::uint32_t(i);
      n.centre = obj.centre;
      skeleton_.nodes.push_back(n);
      objectOf_.push_back(std::uint32_t(i));
    }
    o.mesh = std::make_unique<ActiveMesh>(obj.hierarchy);
    o.list = std::make_unique<ActiveClusterList>(*o.mesh, obj.clusters);
    o.list->takeChanged();
    std::vector<std::uint32_t> all(obj.clusters.clusters.size());
    for (std::uint32_t c = 0; c < all.size(); ++c) all[c] = c;
    update(o, all);
  }
  skeleton_.params.cTex = cTex;
}

Result<std::unique_ptr<VdrRuntime>> VdrRuntime::open(const NodeStore& store) {
  const auto& entries = store.vdrEntries();
  if (entries.empty())
    return makeError("the store has no view-dependent section (build it with `hlodr build --vdr`)");
  std::vector<std::shared_ptr<const VdrObject>> objects;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    auto o = store.sharedVdrObject(i);
    if (!o) return o.error();
    objects.push_back(std::move(*o));
  }
  auto runtime = std::make_unique<VdrRuntime>(std::move(objects), store.skeleton().params.cTex);
  runtime->skeleton_.up = store.skeleton().up;
  runtime->skeleton_.crs = store.skeleton().crs;
  return runtime;
}

std::pair<std::size_t, std::uint32_t> VdrRuntime::locate(std::uint32_t cluster) const {
  const std::size_t i = objectOf_[cluster];
  return {i, cluster - objects_[i].firstCluster};
}

void VdrRuntime::update(Object& o, std::span<const std::uint32_t> changed) {
  const VdrObject& obj = *o.object;
  const VertexHierarchy& h = obj.hierarchy;
  const double perTriangle = obj.texture ? cTex_ : 1.0 - cTex_;
  for (std::uint32_t c : changed) {
    NodeInfo& n = skeleton_.nodes[o.firstCluster + c];
    n.bounds = c == 0 ? o.bounds : Aabb{};
    for (std::uint32_t t : o.list->faces(c))
      for (std::uint32_t v : o.mesh->corners(t)) n.bounds.extend(h.position(v));
    n.numTri = std::uint32_t(o.list->faces(c).size());
    n.numTexTri = obj.texture ? n.numTri : 0;
    n.cost = perTriangle * double(n.numTri);
    float e = 0.0f;
    for (std::uint32_t v : o.list->activeVertices(c)) e = std::max(e, h.error[v]);
    n.geometricError = e;
  }
}

RefineCounters VdrRuntime::refine(const ErrorProjection& projection, double bound) {
  RefineCounters all;
  for (Object& o : objects_) {
    const std::vector<std::uint32_t> vertices = o.list->allActiveVertices();
    const RefineCounters n = refineToBound(*o.mesh, vertices, projection, bound, o.list.get());
    all.splits += n.splits;
    all.forcedSplits += n.forcedSplits;
    all.collapses += n.collapses;
    update(o, o.list->takeChanged());
  }
  return all;
}

std::uint32_t VdrRuntime::activeClusterCount() const {
  std::uint32_t n = 0;
  for (const Object& o : objects_) n += std::uint32_t(o.list->activeClusters().size());
  return n;
}

std::vector<std::uint32_t> VdrRuntime::visibleClusters(const Frustum& frustum, double* cost) const {
  std::vector<std::uint32_t> out;
  double sum = 0.0;
  for (const Object& o : objects_) {
    for (std::uint32_t c : o.list->activeClusters()) {
      const NodeInfo& n = skeleton_.nodes[o.firstCluster + c];
      if (n.numTri == 0 || !frustum.intersects(n.bounds)) continue;
      out.push_back(o.firstCluster + c);
      sum += n.cost;
    }
  }
  std::sort(out.begin(), out.end());
  if (cost) *cost = sum;
  return out;
}

LocalMesh VdrRuntime::clusterArrays(std::uint32_t cluster, double minActiveRatio, ArrayForm* form) {
  const auto [i, c] = locate(cluster);
  Object& o = objects_[i];
  if (o.wedges.empty()) o.wedges = clusterWedges(*o.object);
  const ArrayForm f = arrayForm(std::uint32_t(o.list->activeVertices(c).size()),
                                o.object->clusters.clusters[c].vertexCount, minActiveRatio);
  if (form) *form = f;
  return vdr::clusterArrays(*o.object, *o.mesh, o.list->faces(c), f, o.wedges[c], o.scratch);
}

std::uint64_t VdrRuntime::version(std::uint32_t cluster) const {
  const auto [i, c] = locate(cluster);
  return objects_[i].list->version(c);
}

Mesh VdrRuntime::currentMesh(std::size_t object) const {
  return vdr::currentMesh(*objects_[object].mesh);
}

}  // namespace hlod::vdr
