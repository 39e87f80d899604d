#pragma once
// The HLOD builder (Lakhia III-A and III-B): blocks in, a node store on disk out.
//
// Per block b: hlod_0 is the block simplified to desiredTri triangles (simplification factor
// s_0 = numTri_b / desiredTri); a node with factor s > 1 whose piece holds at least
// levelFactor * minLeafTri triangles is divided by levelFactor - 1 planes perpendicular to the
// longest dimension of its piece (equal widths) into levelFactor children, each simplified from
// the original triangles of its piece with factor s / levelFactor; a slab of fewer than
// minLeafTri triangles joins its neighbour (so a node may have fewer children). Every other node
// is a leaf and holds its piece's original triangles. A triangle goes whole to the child its
// centroid lies in (SlabPartition.h says why), so the leaves hold exactly the input's triangles,
// and the vertices a piece shares with the rest of the model are locked while simplifying:
// neighbouring nodes meet on the same chain of input edges at every level. Textures are cropped to
// the node's texture-coordinate range and down-sampled by the same factor (side / sqrt(s), at least
// kMinTextureSide pixels: builder/TextureCrop.h); where the crops of one level's nodes overlap,
// they share one texture, stored once (kSharedTextureOverlap).
//
// Out of core: blocks are added one at a time; a block's payloads go straight to payload.bin and
// only the NodeInfo records stay in memory, so memory is bounded by the largest block.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "hlod/builder/CityBlocks.h"
#include "hlod/builder/ObjectHierarchy.h"
#include "hlod/builder/Simplifier.h"
#include "hlod/geodesy/Geodesy.h"
#include "hlod/store/NodeStore.h"
#include "hlod/store/VdrStore.h"
#include "hlod/vdr/VdrObject.h"

namespace hlod {

// A mesh file is cut into blocks of at most this many triangles before the HLOD is built.
constexpr std::size_t kDefaultMaxBlockTriangles = 200000;
// 800: a street-level frame of the visible hlod_0 nodes (the coarsest the selector can draw)
// must leave a 33 ms budget on llvmpipe at 1280x720 room to refine near the camera; with 2000
// it did not, and the budget could not be held (docs/results.md, the builder).
constexpr std::uint32_t kDefaultDesiredTri = 800;
// A piece is divided only when its children would hold this many triangles on average, and each
// child holds at least this many, so that hierarchies do not end in crumbs: with leaves of ~400
// triangles (as when a node's factor alone decided), a GPU pays a draw call per few hundred
// triangles and the leaves are mostly border.
constexpr std::uint32_t kDefaultMinLeafTri = 2000;
// c_tex used when neither --c-tex nor a calibration file gives one.
constexpr double kDefaultCTex = 0.6;

enum class CellMode { Auto, On, Off };
// Above this many hlod_0 triangles in all, Auto builds cell nodes: about what a 33 ms frame
// draws on llvmpipe, so a view of every block at hlod_0 no longer fits the budget. Below it
// cells would only add a selection level (the default city's hlod_0 is under it).
constexpr std::uint64_t kCellTriangles = 200000;

// An axis-aligned plane p[axis] == value: where a block's ground meets its neighbour's, or where
// a node's piece was divided.
struct CutPlane {
  int axis = 0;
  double value = 0.0;
  bool contains(const glm::dvec3& p) const { return p[axis] == value; }
};

struct BuildOptions {
  int levelFactor = 3;                            // C_levelFactor, >= 2
  std::uint32_t desiredTri = kDefaultDesiredTri;  // C_desiredTri, >= 1
  std::uint32_t minLeafTri = kDefaultMinLeafTri;  // see kDefaultMinLeafTri, >= 1
  std::string simplifier = "meshopt";             // "meshopt" or "openmesh"
  double cTex = kDefaultCTex;                     // c_tex of eq. 1
  std::size_t maxBlockTriangles = kDefaultMaxBlockTriangles;
  // The store's up axis whatever the input's convention (upAxisOf; a city folder: Z).
  std::optional<UpAxis> up;
  // Blocks prepared at once (0: one per core). The store is the same for any count.
  unsigned threads = 0;
  // The side of the grid that groups a CityJSON model's buildings into blocks (CityBlocks.h),
  // in the model's units (metres).
  double blockSize = kDefaultBlockSize;
  // Cell nodes above the blocks (builder/CellNodes.h): Auto builds them when the blocks' hlod_0
  // nodes hold more than kCellTriangles in all.
  CellMode cells = CellMode::Auto;
  // A model's hierarchy: plane cuts (the blocks above), or the object hierarchy of Manocha sec.
  // 2.2 (builder/ObjectHierarchy.h; resolveHierarchy says what Auto picks). City folders and
  // geo-referenced regions are always cut by planes.
  HierarchyMode hierarchy = HierarchyMode::Planes;
  // The view-dependent section (`--vdr`, hlod/store/VdrStore.h): per block, its welded mesh's
  // vertex and cluster hierarchies (hlod/vdr/VdrObject.h), with the block's seam and outline
  // locked as its nodes lock them, and its texture at full resolution cropped to what it uses.
  bool vdr = false;
  vdr::VdrBuildOptions vdrOptions;
};

// The object hierarchy's options from the build's: fan-out levelFactor, redefined objects of at
// most levelFactor * minLeafTri triangles (as the plane cuts' leaves).
ObjectHierarchyOptions objectHierarchyOptions(const BuildOptions& options);

// One node of a block's hierarchy, as built in memory (world coordinates, double).
// info.parent and info.firstChild are indices into the block's node list; payload fields unset.
struct BlockNode {
  NodeInfo info;
  Mesh mesh;
  double simplification = 0.0;    // the node's simplification factor (1 at the leaves)
  int cutAxis = -1;               // the axis its children were divided along (-1 for a leaf)
  std::vector<double> cutPlanes;  // positions of those planes
};

// A block to build: its triangles, the positions it shares with other blocks cut from the same
// mesh (locked at every level, so that blocks meet as nodes of one block do), and its sides:
// planes where its ground meets a neighbouring block's (a city block's street middles). The
// outline there is kept at every level, or coarse levels open cracks between the blocks.
struct Block {
  Mesh mesh;
  std::vector<glm::dvec3> seam;
  std::vector<CutPlane> sides;
};

// Builds the hierarchy of one block in memory (nodes in breadth-first order, the block root first;
// children contiguous). The block is welded first (weldVertices). An empty block gives no nodes.
// The vertices of a piece that the rest of the block, or `seam`, also has are locked while
// simplifying, and the open border on the block's sides keeps its corners (straight runs between
// them may lose vertices, as kVertexOnOutline says). The leaves' triangles are the welded block's.
std::vector<BlockNode> buildBlockHierarchy(const Mesh& block, const BuildOptions& options,
                                           const Simplifier& simplifier,
                                           std::span<const glm::dvec3> seam = {},
                                           std::span<const CutPlane> blockSides = {});

// Cuts a model into blocks: meshes are grouped by material (texture and base colour, so every
// block has one texture), each group is welded and halved along the longest axis of its bounding
// box (each triangle whole to the half its centroid lies in) until each block has at most
// maxTriangles triangles. Block::seam lists the positions each block shares with the others.
std::vector<Block> cutIntoBlocks(const Model& model, std::size_t maxTriangles);

// The hierarchy the plane cuts make of a model (cutIntoBlocks, then buildBlockHierarchy's
// division of each block, each block a root), without simplifying and without welding: for
// comparing it with the object hierarchy (HierarchyCriteria.h). The triangles keep their objects.
HierarchyShape planeCutShape(const Model& model, const BuildOptions& options);

// The nodes of one block, level and resolution share one texture when their own crops would add
// up to more than this many times the area of their union (an atlas each node uses all over).
constexpr double kSharedTextureOverlap = 1.5;

struct BuildProgress {
  std::size_t blocksDone = 0;
  std::size_t blockCount = 0;
  std::uint64_t trianglesDone = 0;  // input triangles of the finished blocks
  double seconds = 0.0;
  // After the blocks, the cell nodes' pass (BuildOptions::cells): quadtree cells done of all.
  std::size_t cellsDone = 0;
  std::size_t cellCount = 0;
  // The object hierarchy (BuildOptions::hierarchy): its nodes done of all.
  std::size_t nodesDone = 0;
  std::size_t nodeCount = 0;
};
using BuildProgressFn = std::function<void(const BuildProgress&)>;

// A block's nodes ready for the store: what addBlock computes before it writes anything.
struct PreparedBlock {
  std::vector<NodeInfo> nodes;  // parent and firstChild index the block's own nodes
  std::vector<StoredPayload> payloads;
  // Per node: the earlier node of the block whose texture section it shares (kNoNode: its own).
  std::vector<std::uint32_t> textureOwner;
  std::uint64_t inputTriangles = 0;
  // The block's geographic anchor (Parry sec. 3), when its input has one: where the quadtree
  // places it.
  std::optional<LatLon> anchor;
  // The block's sides and seam (as addBlock's): what its cell node locks.
  std::vector<CutPlane> sides;
  std::vector<glm::dvec3> seam;
  // BuildOptions::vdr: the block's view-dependent object, stored; or why it could not be built.
  std::optional<StoredVdr> vdr;
  std::string vdrError;
};

// Streams blocks into a node store at `dir` (written under a temporary name, renamed in finish).
class HlodBuilder {
 public:
  static Result<std::unique_ptr<HlodBuilder>> create(const std::filesystem::path& dir,
                                                     const BuildOptions& options);
  // The model's up axis (options.up wins over it) and CRS, stored in the skeleton; without a
  // call the store is Z up (or options.up) with no CRS, as a city folder is.
  void setModelFrame(UpAxis up, const ModelCrs& crs);
  // Builds the block's subtree and appends its payloads; the block can be freed afterwards.
  // seam and sides: as Block's.
  Status addBlock(const Mesh& block, std::span<const glm::dvec3> seam = {},
                  std::span<const CutPlane> sides = {});
  // addBlock in two steps: prepare (thread-safe: any number at once) and commit (one at a time;
  // blocks enter the store in the order of their commits).
  PreparedBlock prepareBlock(const Mesh& block, std::span<const glm::dvec3> seam = {},
                             std::span<const CutPlane> sides = {}) const;
  Status commitBlock(PreparedBlock&& block);
  // The object hierarchy of a model as one block (builder/ObjectHlods.cpp; Manocha sec. 2.2.1):
  // a leaf holds its redefined object's triangles, in one material or, for several, in flat
  // colours (a palette texture); an inner node's HLOD is made bottom up from its children's
  // payloads, read back from the store, so that only a node and its children are in memory:
  // merged in flat colours, simplified to their triangles over levelFactor (at least desiredTri)
  // by Simplifier::simplifyUnion, whose vertex clustering joins disjoint objects and whose shape
  // guard keeps the result free of flips and shards, as a cell node is; its geometric error is
  // its children's largest plus its own. progress: nodes done of all.
  Status addObjectHierarchy(const Model& model, const ObjectHierarchy& hierarchy,
                            const std::function<void(std::size_t, std::size_t)>& progress = {});
  // Writes the skeleton, with the quadtree of the blocks (quadtreeOfRoots) and cell nodes above
  // them (BuildOptions::cells), and moves the store into place. An Error when no block added a
  // node (nothing to draw): no empty store is written.
  // progress: called as the cell pass goes, with blocks all done.
  Result<Skeleton> finish(
      double buildSeconds,
      const std::function<void(std::size_t done, std::size_t total)>& progress = {});
  const Skeleton& skeleton() const { return skeleton_; }
  std::uint64_t inputTriangles() const { return inputTriangles_; }

 private:
  HlodBuilder() = default;
  // Adds the block's view-dependent object to out (BuildOptions::vdr).
  void prepareVdr(const Mesh& block, std::span<const glm::dvec3> seam,
                  std::span<const CutPlane> sides, PreparedBlock& out) const;
  BuildOptions options_;
  std::unique_ptr<Simplifier> simplifier_;
  std::unique_ptr<NodeStoreWriter> writer_;
  Skeleton skeleton_;
  std::uint64_t inputTriangles_ = 0;
  std::uint32_t blockCount_ = 0;
  std::vector<std::optional<LatLon>> anchors_;  // per root
  std::vector<std::vector<CutPlane>> sides_;    // per block
  std::vector<std::vector<glm::dvec3>> seams_;  // per block
};

// The quadtree of a skeleton's roots (Parry sec. 3). When every root has a geographic anchor:
// over the globe, each root in the cell of its (longitude, latitude). Otherwise over the model's
// own horizontal coordinates (the two axes across `up`), each root at its box's centre, in a
// square around them. Depth: quadtreeDepthFor(the root rectangle's v side in metres or model
// units, the median block's larger horizontal side), a block being the roots that share an
// anchor (one block split by material or size), or each root without anchors.
BlockQuadtree quadtreeOfRoots(const Skeleton& skeleton,
                              std::span<const std::optional<LatLon>> anchors);

// One input of a build: a city folder (its blocks loaded one at a time) or an imported model.
struct BuildInput {
  std::string name;  // as the user gave it, for messages
  std::optional<std::filesystem::path> cityDir;
  Model model;  // when not a city folder
};

// Builds one store from several inputs: a region of cities in one quadtree. With more than one
// input and any of them geo-referenced (a city folder, a CityJSON with a geographic, geocentric,
// RD New or UTM CRS), every input must be: all are placed, through ECEF in double precision, in
// the east-north-up frame of the first (a projected first input: the ENU frame at its centre),
// and an input without a geographic anchor is an Error naming it. Inputs without any anchor
// (mesh files) are joined as they are. Models are grouped into blocks (groupBuildingsIntoBlocks)
// and cut by material and maxBlockTriangles; city blocks are cut by maxBlockTriangles.
Result<Skeleton> buildStoreFromInputs(std::vector<BuildInput> inputs,
                                      const std::filesystem::path& dir, const BuildOptions& options,
                                      const BuildProgressFn& progress = {});

// Builds a store from a model in memory: its buildings grouped into blocks of options.blockSize
// (a model without city objects is one), each cut by material and maxBlockTriangles; its up
// axis is options.up or else upAxisOf(model), its CRS model.crs; blocks are anchored through
// GeoReference::of(model.crs) when it is known.
Result<Skeleton> buildStoreFromModel(const Model& model, const std::filesystem::path& dir,
                                     const BuildOptions& options,
                                     const BuildProgressFn& progress = {});

// Builds a store from a city folder, loading one block at a time; a city without blocks is an
// Error before anything is written.
Result<Skeleton> buildStoreFromCity(const std::filesystem::path& cityDir,
                                    const std::filesystem::path& dir, const BuildOptions& options,
                                    const BuildProgressFn& progress = {});

}  // namespace hlod
