#pragma once
// The HLOD skeleton: the tree with per-node pre-processed values (Lakhia III-B), loaded whole.
// Payloads (vertices, indices, texture) live elsewhere in the node store and are read on demand.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "hlod/Mesh.h"
#include "hlod/UpAxis.h"
#include "hlod/city/BlockQuadtree.h"

namespace hlod {

constexpr std::uint32_t kNoNode = 0xffffffffu;
// NodeInfo::block of a cell node: it belongs to no one block.
constexpr std::uint32_t kCellBlock = 0xffffffffu;

// A node is a block's (its hlod_0 node, the block's root, and the nodes below it) or a cell node:
// the HLOD of a quadtree cell above the blocks (Manocha sec. 2.2: "the HLODs of intermediate
// nodes are computed by combining the LODs of the nodes with the HLODs of the node's children"),
// whose children are cell nodes and hlod_0 nodes (CellNodes.h says when a store has them).
struct NodeInfo {
  std::uint32_t parent = kNoNode;  // kNoNode for a root: an hlod_0 node, or a top cell node
  std::uint32_t firstChild = 0;    // children are contiguous: [firstChild, firstChild+childCount)
  std::uint32_t childCount = 0;
  std::uint32_t level = 0;  // d of hlod_d: 0 for block roots and for cell nodes
  std::uint32_t block = 0;  // index of the block the node belongs to; kCellBlock for a cell node
  Aabb bounds;              // world space, double
  glm::dvec3 centre{0.0};   // payload vertices are float, relative to this
  std::uint32_t numTri = 0;
  std::uint32_t numTexTri = 0;
  // Parry (sec. 5): the fewest triangles the node's progression draws it with (0: no
  // progression, drawn whole only), and how many splats it has (0: never drawn as splats).
  std::uint32_t minTri = 0;
  std::uint32_t splatCount = 0;
  bool progressive() const { return minTri > 0 && minTri < numTri; }
  double cost = 0.0;                      // eq. 1
  double staticBenefit = 0.0;             // eq. 2
  glm::vec3 avgNormal{0.0f, 0.0f, 1.0f};  // eq. 3 (fallback +Z when the node has no area)
  double geometricError = 0.0;  // world units; 0 at the leaves (for screen-space-error selection)
  // The mesh section at payloadOffset, payloadSize - textureSize stored bytes; then the texture
  // section, textureSize bytes at textureOffset: right after the mesh section, or the section
  // of another node of its block and level that shares the texture (stored once).
  std::uint64_t payloadOffset = 0;
  std::uint64_t payloadSize = 0;      // bytes stored in payload.bin (compressed): what a load reads
  std::uint32_t payloadChecksum = 0;  // CRC-32 of the mesh section
  std::uint64_t memoryBytes = 0;      // the decoded payload: what a resident node holds
  // The texture's section (0: none): a scene without textures reads payloadSize - textureSize
  // and holds memoryBytes - textureBytes.
  std::uint64_t textureOffset = 0;
  std::uint64_t textureSize = 0;
  std::uint32_t textureChecksum = 0;  // CRC-32 of the texture section's stored bytes
  std::uint64_t textureBytes = 0;     // its decoded RGBA8 pixels
  std::uint64_t meshSize() const { return payloadSize - textureSize; }
  bool isCell() const { return block == kCellBlock; }
};

// BuildParams::simplifier of a store imported from a tileset hlodr did not write: its levels
// and errors are the tileset author's.
inline constexpr const char* kTilesetSimplifier = "3d-tiles";

struct BuildParams {
  double levelFactor = 3.0;      // C_levelFactor
  std::uint32_t desiredTri = 0;  // C_desiredTri
  double cTex = 0.0;             // c_tex of eq. 1
  std::string simplifier;        // "meshopt" or "openmesh", or kTilesetSimplifier
};

struct Skeleton {
  std::vector<NodeInfo> nodes;
  // The parentless nodes, ascending: the hlod_0 nodes (one per block), or with cell nodes the
  // top cell node(s).
  std::vector<std::uint32_t> roots;
  BuildParams params;
  // What the input declared about its world: the axis it stands on (camera paths and default
  // views circle it) and its coordinate reference system (for `hlodr info`; never consulted by
  // the runtime). Z up by default: a city folder's blocks are metres with Z up.
  UpAxis up = UpAxis::Z;
  ModelCrs crs;
  // The blocks' hlod_0 nodes by their latitude/longitude anchors (Parry sec. 3): a culling
  // structure on top of them, and what cell nodes are built from. Empty for a skeleton made
  // without one (every root is then visited); a built store always has one, holding every
  // block's hlod_0 node once. With cell nodes the culling walk is theirs (QuadtreeCulling).
  BlockQuadtree quadtree;

  bool isLeaf(std::uint32_t n) const { return nodes[n].childCount == 0; }
  bool hasCells() const {
    return !roots.empty() && roots.size() <= nodes.size() && nodes[roots.front()].isCell();
  }
  // The blocks' hlod_0 nodes, ascending: roots, or below the cell nodes.
  std::vector<std::uint32_t> blockRoots() const;
};

}  // namespace hlod
