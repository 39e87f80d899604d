// The view-dependent section of a node store (hlod/store/VdrStore.h): a record, both as vdr.bin
// stores it and as it is decoded (the input inflated for a decoded size named by its first 4
// bytes, at most 1 MiB, and the input itself decoded raw), and the section's index (the input
// taken as an index found 1 MiB into its file, in a store of 64 nodes). A decoded object must be
// what decodeVdrObject promises, and the run time must survive it: its front refined to every
// vertex and coarsened back.
#include <cstdlib>
#include <cstring>

#include "FuzzSupport.h"
#include "hlod/store/NodeStore.h"
#include "hlod/store/VdrStore.h"
#include "hlod/vdr/ActiveClusterList.h"
#include "hlod/vdr/ActiveMesh.h"
#include "hlod/vdr/ClusterArrays.h"
#include "hlod/vdr/ViewRefinement.h"

namespace {

using namespace hlod::vdr;

void decodeAndRun(std::span<const std::byte> bytes) {
  auto o = hlod::decodeVdrObject(bytes);
  fuzz::report("decodeVdrObject", o);
  if (!o.ok()) return;
  const VertexHierarchy& h = o->hierarchy;
  if (h.parent.size() != h.vertexCount() || h.leafOf.size() != h.vertexCount() ||
      o->clusters.clusterOf.size() != h.vertexCount() || o->faceWedges.size() != h.faces.size())
    std::abort();
  for (std::uint32_t v = h.leafCount; v < h.vertexCount(); ++v)
    if (h.kept(v) >= v || h.removed(v) >= v) std::abort();
  ActiveMesh mesh(h);
  ActiveClusterList list(mesh, o->clusters);
  ErrorProjection all;
  all.perspective = false;
  refineToBound(mesh, list.allActiveVertices(), all, -1.0, &list);
  refineToBound(mesh, list.allActiveVertices(), all, 1e30, &list);
  ArrayScratch scratch;
  const auto wedges = clusterWedges(*o);
  for (std::uint32_t c : list.activeClusters()) {
    const hlod::LocalMesh m =
        clusterArrays(*o, mesh, list.faces(c), ArrayForm::VertexArray, wedges[c], scratch);
    for (std::uint32_t i : m.indices)
      if (i >= m.positions.size()) std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::byte> input(reinterpret_cast<const std::byte*>(data), size);
  decodeAndRun(input);
  if (size >= 4) {
    std::uint32_t rawBytes = 0;
    std::memcpy(&rawBytes, data, 4);
    rawBytes &= (1u << 20) - 1;
    auto raw = hlod::inflatePayload(input.subspan(4), rawBytes);
    fuzz::report("inflatePayload", raw);
    if (raw.ok()) decodeAndRun(*raw);
  }
  auto index = hlod::decodeVdrIndex(input, 1u << 20, 64);
  fuzz::report("decodeVdrIndex", index);
  if (index.ok())
    for (const hlod::VdrEntry& e : *index)
      if (e.rootNode >= 64 || e.offset + e.storedSize > (1u << 20)) std::abort();
  return 0;
}
