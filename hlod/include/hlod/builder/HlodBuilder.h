#pragma once
// The HLOD builder (Lakhia III-A and III-B): blocks in, a node store on disk out.
//
// Per block b: hlod_0 is the block simplified to desiredTri triangles (simplification factor
// s_0 = numTri_b / desiredTri); a node with factor s > 1 is split by levelFactor - 1 planes
// perpendicular to the longest dimension of its piece (equal widths) into levelFactor children,
// each simplified from the original triangles of its piece with factor s / levelFactor. A node
// whose factor is <= 1 is a leaf and holds its piece's original triangles. Cut vertices lie on
// open borders, which the simplifiers lock, so neighbouring nodes meet at the cuts. Textures are
// cropped to the node's texture-coordinate range and down-sampled by the same factor (side
// / sqrt(s), at least kMinTextureSide pixels).
//
// Out of core: blocks are added one at a time; a block's payloads go straight to payload.bin and
// only the NodeInfo records stay in memory, so memory is bounded by the largest block.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hlod/builder/PlaneSplit.h"
#include "hlod/builder/Preprocess.h"
#include "hlod/builder/SeamVertices.h"
#include "hlod/builder/Simplifier.h"
#include "hlod/store/NodeStore.h"

namespace hlod {

// A mesh file is cut into blocks of at most this many triangles before the HLOD is built.
constexpr std::size_t kDefaultMaxBlockTriangles = 200000;
// 800: the default city's hlod_0 nodes then hold about 52k triangles. On llvmpipe at 1280x720 a
// street-level frame of the ~48 visible hlod_0 nodes takes about 21 ms (most of it filling
// pixels), which leaves a 33 ms budget room to refine near the camera; with 2000 that frame took
// about 30 ms and the budget could not be held.
constexpr std::uint32_t kDefaultDesiredTri = 800;
constexpr int kMinTextureSide = 8;

struct BuildOptions {
  int levelFactor = 3;                            // C_levelFactor, >= 2
  std::uint32_t desiredTri = kDefaultDesiredTri;  // C_desiredTri, >= 1
  std::string simplifier = "meshopt";             // "meshopt" or "openmesh"
  double cTex = kDefaultCTex;                     // c_tex of eq. 1
  std::size_t maxBlockTriangles = kDefaultMaxBlockTriangles;
  // The store's up axis whatever the input's convention (upAxisOf; a city folder: Z).
  std::optional<UpAxis> up;
};

// One node of a block's hierarchy, as built in memory (world coordinates, double).
// info.parent and info.firstChild are indices into the block's node list; payload fields unset.
struct BlockNode {
  NodeInfo info;
  Mesh mesh;
  double simplification = 0.0;    // the node's simplification factor (<= 1 at the leaves)
  int cutAxis = -1;               // the axis its children were cut along (-1 for a leaf)
  std::vector<double> cutPlanes;  // positions of those planes
  std::vector<CutPlane> planes;  // the cutting planes that bound its piece (block's and ancestors')
};

// A block to build: its triangles, the planes it was cut from its neighbours along, and its
// sides: planes where its ground meets a neighbouring block's (a city block's street middles).
// The outline there is kept at every level, or coarse levels open cracks between the blocks.
struct Block {
  Mesh mesh;
  std::vector<CutPlane> planes;
  std::vector<CutPlane> sides;
};

// Builds the hierarchy of one block in memory (nodes in breadth-first order, the block root first;
// children contiguous). The block is welded first (weldVertices). An empty block gives no nodes.
// Vertices on the block's planes and on every cut are locked while simplifying, and the open
// border on its sides keeps its corners (straight runs between them may lose vertices, as
// kVertexOnOutline says); afterwards the
// seam vertices of the block's own cuts and of neighbourSeams are inserted into every node's seam
// edges (see SeamVertices), so no T-junction remains between any two nodes.
std::vector<BlockNode> buildBlockHierarchy(const Mesh& block, const BuildOptions& options,
                                           const Simplifier& simplifier,
                                           const std::vector<CutPlane>& blockPlanes = {},
                                           const SeamVertices* neighbourSeams = nullptr,
                                           const std::vector<CutPlane>& blockSides = {});

// The seam vertices buildBlockHierarchy would record for this block, found by making the same cuts
// without simplifying (for blocks that share planes with others).
SeamVertices planBlockSeams(const Mesh& block, const BuildOptions& options,
                            const std::vector<CutPlane>& blockPlanes);

// Cuts a model into blocks: meshes are grouped by material (texture and base colour, so every
// block has one texture), each group is merged and split in halves along the longest axis of its
// bounding box (triangles cut at the plane) until each block has at most maxTriangles triangles.
std::vector<Block> cutIntoBlocks(const Model& model, std::size_t maxTriangles);

// Crops a texture to the texel rectangle that texCoords (all in [0,1]) use, rewriting texCoords
// to the crop, and box-filters it to about 1/sqrt(factor) of its side (at least kMinTextureSide
// pixels, never enlarged). Texture coordinates outside [0,1] (wrapping) keep the whole texture.
std::shared_ptr<const Image> prepareNodeTexture(const Image& texture,
                                                std::vector<glm::vec2>& texCoords, double factor);

// Box-filter resize of an RGBA8 image (OpenImageIO ImageBufAlgo::resize, "box" filter).
Image resizeImage(const Image& image, int width, int height);

struct BuildProgress {
  std::size_t blocksDone = 0;
  std::size_t blockCount = 0;
  std::uint64_t trianglesDone = 0;  // input triangles of the finished blocks
  double seconds = 0.0;
};
using BuildProgressFn = std::function<void(const BuildProgress&)>;

// Streams blocks into a node store at `dir` (written under a temporary name, renamed in finish).
class HlodBuilder {
 public:
  static Result<std::unique_ptr<HlodBuilder>> create(const std::filesystem::path& dir,
                                                     const BuildOptions& options);
  // The model's up axis (options.up wins over it) and CRS, stored in the skeleton; without a
  // call the store is Z up (or options.up) with no CRS, as a city folder is.
  void setModelFrame(UpAxis up, const ModelCrs& crs);
  // Builds the block's subtree and appends its payloads; the block can be freed afterwards.
  // planes: those the block was cut along; neighbourSeams: seam vertices of the blocks sharing
  // them (planBlockSeams); sides: as Block::sides.
  Status addBlock(const Mesh& block, const std::vector<CutPlane>& planes = {},
                  const SeamVertices* neighbourSeams = nullptr,
                  const std::vector<CutPlane>& sides = {});
  // Writes the skeleton and moves the store into place. An Error when no block added a node
  // (nothing to draw): no empty store is written.
  Result<Skeleton> finish(double buildSeconds);
  const Skeleton& skeleton() const { return skeleton_; }
  std::uint64_t inputTriangles() const { return inputTriangles_; }

 private:
  HlodBuilder() = default;
  BuildOptions options_;
  std::unique_ptr<Simplifier> simplifier_;
  std::unique_ptr<NodeStoreWriter> writer_;
  Skeleton skeleton_;
  std::uint64_t inputTriangles_ = 0;
  std::uint32_t blockCount_ = 0;
};

// Builds a store from a model in memory (cut into blocks first); its up axis is options.up or
// else upAxisOf(model), its CRS model.crs.
Result<Skeleton> buildStoreFromModel(const Model& model, const std::filesystem::path& dir,
                                     const BuildOptions& options,
                                     const BuildProgressFn& progress = {});

// Builds a store from a city folder, loading one block at a time; a city without blocks is an
// Error before anything is written.
Result<Skeleton> buildStoreFromCity(const std::filesystem::path& cityDir,
                                    const std::filesystem::path& dir, const BuildOptions& options,
                                    const BuildProgressFn& progress = {});

}  // namespace hlod
