#pragma once
// The builder's study (`hlodr study-build`): how far each simplifier's levels lie from the
// original surface, what they keep, and what they cost to build. Per level d, the surface drawn
// when the front is cut at d (the nodes of level d and the leaves above it) is measured against
// the block's original triangles: symmetric Hausdorff and RMS distance, sampled on both surfaces
// (metrics::surfaceDistance), and the simplified triangles that face away from the original or
// stand off it farther than the level's own error estimate (metrics::checkFacing). The object
// hierarchy of a model is studied the same way, as one tree over the whole model.
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "hlod/Result.h"
#include "hlod/builder/HlodBuilder.h"

namespace hlod::study {

struct BuildStudyOptions {
  std::vector<std::string> simplifiers{"meshopt", "openmesh"};
  BuildOptions build;                   // levelFactor, desiredTri (simplifier is set per run)
  std::size_t samplesPerBlock = 20000;  // surface samples per level and block, on each surface
};

struct LevelFigures {
  int level = 0;
  std::size_t blocks = 0;       // blocks that reach this level
  std::size_t nodes = 0;        // nodes of the level (leaves above it not counted)
  std::size_t triangles = 0;    // of the cut at this level (leaves above it included)
  double hausdorff = 0.0;       // largest over the blocks, world units
  double rms = 0.0;             // over all samples of all blocks
  double relHausdorff = 0.0;    // largest over the blocks of hausdorff / block diagonal
  double geometricError = 0.0;  // largest error the builder recorded for a node of the level
  std::size_t simplifiedTriangles = 0;  // triangles of the level's simplified (inner) nodes
  std::size_t flipped = 0;              // of them, facing away from the original surface
  std::size_t standingOff = 0;          // of them, standing off it farther than their node's error
  double maxOff = 0.0;                  // the farthest any of them stands off, world units
  double sumSquares = 0.0;              // (for rms)
  std::size_t samples = 0;              // (for rms)
};

struct SimplifierFigures {
  std::string simplifier;
  std::string hierarchy = "planes";  // or "objects" (addObjectModel)
  double buildSeconds = 0.0;         // buildBlockHierarchy over all blocks (measuring not included)
  std::size_t inputTriangles = 0;
  std::vector<LevelFigures> levels;
};

class BuildStudy {
 public:
  // An Error for an unknown simplifier name or bad build options.
  static Result<BuildStudy> create(const BuildStudyOptions& options);
  // Builds the block's hierarchy with each simplifier and measures its levels.
  Status addBlock(const Block& block);
  // The object hierarchy of a whole model (Manocha sec. 2.2; builder/ObjectHierarchy.h), built
  // with each simplifier into a store in `scratch` (a folder, removed after), its levels measured
  // as a block's against the whole model with samplesPerBlock for every maxBlockTriangles
  // triangles of it (as many samples as the plane cuts' blocks take together). Figures of their
  // own, hierarchy "objects", after the planes'.
  Status addObjectModel(const Model& model, const std::filesystem::path& scratch);
  const std::vector<SimplifierFigures>& figures() const { return figures_; }

 private:
  BuildStudyOptions options_;
  std::vector<std::unique_ptr<Simplifier>> simplifiers_;
  std::vector<SimplifierFigures> figures_;
};

// The figures as JSON (an object with "simplifiers": [...]) and as CSV (one row per simplifier
// and level; a header line first).
std::string buildStudyJson(const std::vector<SimplifierFigures>& figures);
std::string buildStudyCsv(const std::vector<SimplifierFigures>& figures);

}  // namespace hlod::study
