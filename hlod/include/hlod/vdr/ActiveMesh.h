#pragma once
// The active front of a vertex hierarchy and its faces, changed by vertex splits and edge
// collapses in any order, each applied only when it is fold-over safe by the neighbourhood test
// of Manocha sec. 3: "The face neighborhood is stored for each edge collapse and vertex split
// operation when creating the hierarchy. At runtime, an operation is considered fold-over safe
// only if its current neighborhood is identical to the stored neighborhood."
//  - split(v): the faces around v now must be those the collapse into v left (its stored
//    neighbourhood with the children renamed v, the faces that held both gone), each at the
//    same vertices;
//  - collapse(v): the faces around v's two children now must be the stored neighbourhood itself.
// Every face changed by an operation then takes corners it had at some moment of the build, so
// the build's fold-over tests hold at run time in any order (a face never turns against its
// input triangle). What the test refuses can be made possible by first splitting the coarser
// neighbours it names (forcedSplits, after Hoppe 1997's force_vsplit).
//
// Faces are the input's triangles, each drawn with its corners at their leaves' active
// ancestors while those differ (VertexHierarchy.h). Corners are kept in per-vertex lists, so that
// an operation costs the faces around it.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "hlod/Mesh.h"
#include "hlod/vdr/VertexHierarchy.h"

namespace hlod::vdr {

class ActiveMesh {
 public:
  // The coarsest state: the hierarchy's roots active. The hierarchy must outlive it.
  explicit ActiveMesh(const VertexHierarchy& hierarchy);

  const VertexHierarchy& hierarchy() const { return h_; }
  bool isActive(std::uint32_t v) const { return active_[v] != 0; }
  bool isLive(std::uint32_t face) const { return live_[face] != 0; }
  // The vertices a live face's corners are at now.
  std::array<std::uint32_t, 3> corners(std::uint32_t face) const {
    return {corner_[3 * face], corner_[3 * face + 1], corner_[3 * face + 2]};
  }
  std::uint32_t activeVertexCount() const { return activeCount_; }
  std::uint32_t liveFaceCount() const { return liveCount_; }
  std::vector<std::uint32_t> activeVertices() const;
  std::vector<std::uint32_t> liveFaces() const;
  // The live faces with a corner at v (v active), each once.
  std::vector<std::uint32_t> facesAround(std::uint32_t v) const;
  // Whether v lies below (or is) `ancestor` in the hierarchy.
  bool isBelow(std::uint32_t v, std::uint32_t ancestor) const;
  // The active vertex at or above v (v itself when active), kNone when v is split.
  std::uint32_t activeAtOrAbove(std::uint32_t v) const;

  // The neighbourhood test: v active and made by a collapse, and the faces around it are those
  // the collapse left.
  bool canSplit(std::uint32_t v) const;
  // v's two children active, and the faces around them are the stored neighbourhood.
  bool canCollapse(std::uint32_t v) const;
  // The vertices that must be split first for split(v) to pass the test: the active
  // ancestors of the stored neighbourhood's vertices that are not active (coarser than when v
  // was made). Empty when nothing coarser stands in the way.
  std::vector<std::uint32_t> coarserNeighbours(std::uint32_t v) const;

  // The operations; each asserts its test. touchedFaces() then lists the faces whose corners
  // moved, that became live or that died.
  void split(std::uint32_t v);
  void collapse(std::uint32_t v);
  // split(v) without the neighbourhood test (v active and made by a collapse): what the test
  // prevents, for the tests that show it.
  void splitUnchecked(std::uint32_t v);
  std::span<const std::uint32_t> touchedFaces() const { return touched_; }

 private:
  void splitImpl(std::uint32_t v);
  void link(std::uint32_t corner, std::uint32_t v);
  void unlink(std::uint32_t corner);
  std::uint32_t cornersAt(std::uint32_t v) const;

  const VertexHierarchy& h_;
  std::vector<std::uint8_t> active_;
  std::vector<std::uint8_t> live_;
  std::vector<std::uint32_t> corner_;  // per face corner (3 face + i): its vertex now
  // Per active vertex: a doubly linked list of the live corners at it.
  std::vector<std::uint32_t> head_, next_, prev_;
  // Per vertex the range of its leaves' depth-first numbers (VertexHierarchy::leafRanges):
  // isBelow in O(1), for the corners a split hands to one child or the other.
  std::vector<std::uint32_t> first_, last_;
  std::uint32_t activeCount_ = 0, liveCount_ = 0;
  std::vector<std::uint32_t> touched_;
};

// The mesh the front draws now: the hierarchy's leaf positions and the live faces at their
// corners' vertices (for tests and tools; what is drawn comes from the clusters).
Mesh currentMesh(const ActiveMesh& mesh);

}  // namespace hlod::vdr
