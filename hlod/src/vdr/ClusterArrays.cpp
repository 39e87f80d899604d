// A cluster's vertex arrays (Manocha sec. 5.1.3). See hlod/vdr/ClusterArrays.h.
#include "hlod/vdr/ClusterArrays.h"

#include <algorithm>

namespace hlod::vdr {

ArrayForm arrayForm(std::uint32_t activeVertices, std::uint32_t vertexCount,
                    double minActiveRatio) {
  return vertexCount > 0 && double(activeVertices) >= minActiveRatio * double(vertexCount)
             ? ArrayForm::VertexArray
             : ArrayForm::Compacted;
}

std::vector<std::vector<std::uint32_t>> clusterWedges(const VdrObject& o) {
  std::vector<std::vector<std::uint32_t>> out(o.clusters.clusters.size());
  const VertexHierarchy& h = o.hierarchy;
  for (std::uint32_t v = 0; v < h.vertexCount(); ++v) {
    const std::uint32_t leaf = h.leafOf[v];
    auto& list = out[o.clusters.clusterOf[v]];
    for (std::uint32_t w = o.leafWedgeStart[leaf]; w < o.leafWedgeStart[leaf + 1]; ++w)
      list.push_back(w);
  }
  for (auto& list : out) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  return out;
}

LocalMesh clusterArrays(const VdrObject& o, const ActiveMesh& mesh,
                        std::span<const std::uint32_t> faces, ArrayForm form,
                        std::span<const std::uint32_t> fixed, ArrayScratch& scratch) {
  LocalMesh m;
  m.centre = o.centre;
  m.baseColor = o.baseColor;
  m.oneSided = o.oneSided;
  m.texture = o.texture;
  const std::size_t wedges = o.wedgeLeaf.size();
  if (scratch.local.size() != wedges) {
    scratch.local.assign(wedges, 0);
    scratch.stamp.assign(wedges, 0);
    scratch.build = 0;
  }
  if (++scratch.build == 0) {  // wrapped: forget every stamp
    std::fill(scratch.stamp.begin(), scratch.stamp.end(), 0);
    scratch.build = 1;
  }
  const bool uv = o.wedgeTexCoord.size() == wedges;
  const auto add = [&](std::uint32_t w) {
    if (scratch.stamp[w] == scratch.build) return scratch.local[w];
    scratch.stamp[w] = scratch.build;
    scratch.local[w] = std::uint32_t(m.positions.size());
    m.positions.push_back(glm::vec3(o.hierarchy.leafPosition[o.wedgeLeaf[w]] - o.centre));
    m.normals.push_back(o.wedgeNormal[w]);
    if (uv) m.texCoords.push_back(o.wedgeTexCoord[w]);
    return scratch.local[w];
  };
  if (form == ArrayForm::VertexArray)
    for (std::uint32_t w : fixed) add(w);
  m.indices.reserve(faces.size() * 3);
  for (std::uint32_t t : faces) {
    const auto corners = mesh.corners(t);
    for (int i = 0; i < 3; ++i) m.indices.push_back(add(o.cornerWedge(t, i, corners[i])));
  }
  return m;
}

}  // namespace hlod::vdr
