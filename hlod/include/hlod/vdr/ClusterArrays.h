#pragma once
// The vertex arrays a cluster is drawn from (Manocha sec. 5.1.3): "we use vertex arrays stored
// in the graphics processor unit (GPU) memory ... only a fraction of the vertices for a cluster,
// the active vertices, are used for rendering. This increases the number of bytes per rendered
// vertex that are transferred to the GPU when using vertex arrays stored in GPU memory. To
// obtain maximum throughput, we use a minimum ratio of active vertices to total vertices, and any
// active cluster that does not meet this threshold is rendered in immediate mode."
// Core GL has no immediate mode: a cluster under the ratio is drawn from a compacted array, the
// wedges its faces use now and no others. A cluster at or above it is drawn from its vertex
// array: the wedges at every vertex of the cluster, in a fixed order (what stays in GPU memory
// while only the faces change), followed by the wedges its faces use at vertices of other
// clusters (a face belongs to the cluster of its first corner: its other corners may stand in
// neighbouring clusters).
#include <cstdint>
#include <span>
#include <vector>

#include "hlod/Mesh.h"
#include "hlod/vdr/ActiveMesh.h"
#include "hlod/vdr/VdrObject.h"

namespace hlod::vdr {

enum class ArrayForm { VertexArray, Compacted };

// VertexArray when activeVertices / vertexCount reaches minActiveRatio.
ArrayForm arrayForm(std::uint32_t activeVertices, std::uint32_t vertexCount, double minActiveRatio);

// Per cluster of the object, the wedges at its vertices (each once, ascending): the fixed part of
// its vertex array.
std::vector<std::vector<std::uint32_t>> clusterWedges(const VdrObject& object);

// Working memory for clusterArrays, one per object (one wedge slot each), reused between calls.
struct ArrayScratch {
  std::vector<std::uint32_t> local;  // per wedge: its index in the array being built
  std::vector<std::uint32_t> stamp;  // per wedge: the build that set `local`
  std::uint32_t build = 0;
};

// The cluster's arrays in the given form: vertices relative to the object's centre, the faces
// (the cluster's live faces) at their corners' wedges now, the object's material and texture.
// fixed: the cluster's clusterWedges (used by the VertexArray form only).
LocalMesh clusterArrays(const VdrObject& object, const ActiveMesh& mesh,
                        std::span<const std::uint32_t> faces, ArrayForm form,
                        std::span<const std::uint32_t> fixed, ArrayScratch& scratch);

}  // namespace hlod::vdr
