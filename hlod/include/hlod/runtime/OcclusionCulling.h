#pragma once
// Occlusion culling with hardware occlusion queries, read one frame late: the state and the
// decisions, without GL. The renderer issues the queries this plans (NodeRenderer::draw with an
// OcclusionPlan) and hands their results back at the next frame (NodeRenderer::occlusionResults).
//
// From Manocha, "Interactive Display of Complex Environments" (shared/seeds):
//  - sec. 4.1, 5.1.2: the visible geometry of frame i is the occluder set of frame i + 1. The
//    front's nodes that were visible last frame (or are not known yet) are drawn first, near to
//    far: they are the occluders, and they are drawn anyway;
//  - sec. 4.2 (HC): the occlusion representation is the depth buffer after the occluders; the
//    other candidates' bounding boxes are drawn against it inside occlusion queries, with depth
//    and colour writes off;
//  - sec. 2.3: HLODs are hierarchical occluders and occludees. The front walk stops at a node
//    known hidden, whatever its level (Selector), so one query on a hidden cell or hlod_0 culls
//    its whole subtree; and a node whose reached children are all hidden is queried in their
//    place (the visibility pull-up of CHC, Bittner et al. 2004).
// From CHC++ (Mattausch, Bittner, Wimmer, "CHC++: Coherent Hierarchical Culling Revisited",
// Eurographics 2008):
//  - no stalls: every result is read a frame late (the paper waits for results within the
//    frame where it has other work; hlodr has none to interleave, so it takes them next frame);
//  - a visible node is assumed visible for c_visibleFrames frames and then tested again with its
//    own draw wrapped in the query (it is drawn anyway); its first interval is jittered so that
//    nodes that became visible together do not all come due in one frame (sec. 4.2);
//  - hidden nodes are queried in batches (multiqueries, sec. 4.3): a node hidden for i frames
//    stays hidden with probability p(i) = 0.99 - 0.7 e^-i; nodes sorted by p are grouped while
//    the batch's value |M| / C(M), C(M) = 1 + (1 - prod p) |M|, grows. A batch that comes back
//    hidden keeps all its nodes hidden with one query. One that comes back visible makes its
//    nodes unknown: they are drawn next frame, each with its draw queried (CHC++ re-queries them
//    at once, which would need a wait).
// hlodr's own rules, where neither says:
//  - a node whose result has not come back, or whose box holds the camera or crosses the near
//    plane (the renderer does not query such a box), counts as visible;
//  - a hidden result is trusted for c_trustFrames frames, and only while no ancestor has been
//    found visible since; otherwise the node is unknown again and drawn, so that a subtree
//    skipped while its ancestor was hidden is never left out on a stale answer (it shows the
//    frame after its ancestor's box does);
//  - a pulled-up node whose box comes back visible while its children were hidden (a block's
//    box rising above the wall its buildings stay behind) is not pulled up again for
//    c_noPullFrames frames: its children are queried one by one instead of being drawn every
//    other frame;
//  - the first frame of a session, and the frame after a camera jump (reset()), draws
//    everything in the frustum.
#include <cstdint>
#include <span>
#include <vector>

#include "hlod/store/Skeleton.h"

namespace hlod {

// What a selector asks while it walks the front (View::occlusion).
class OcclusionOracle {
 public:
  virtual ~OcclusionOracle() = default;
  // The node's box was found hidden by a recent query: it is not drawn, not refined, and its
  // box is queried again this frame.
  virtual bool occluded(std::uint32_t node) const = 0;
};

struct OcclusionParams {
  std::uint32_t c_visibleFrames = 8;  // CHC++'s n_av: frames a visible node is assumed visible
  std::uint32_t c_trustFrames = 2;    // frames a hidden result is trusted (see above)
  std::size_t c_maxBatch = 32;        // the most nodes one multiquery holds
  std::uint32_t c_noPullFrames = 30;  // see above
};

// The queries of one frame.
struct OcclusionPlan {
  // Per node of the front (in the order it is drawn): 1 to wrap its draw in a query.
  std::vector<std::uint8_t> queryDraw;
  // Each batch is one query over the boxes of its nodes, after the whole front is drawn.
  std::vector<std::vector<std::uint32_t>> boxBatches;
  std::size_t queries() const;
};

// The answer to one query of a plan: the nodes it covered and the samples that passed the
// depth test. Not answered: the renderer did not issue it (a box that holds the camera or
// crosses the near plane) or its result was not available; its nodes are unknown again, and so
// drawn as visible.
struct OcclusionResult {
  std::vector<std::uint32_t> nodes;
  std::uint64_t samples = 0;
  bool answered = true;
};

struct OcclusionCounters {
  std::uint32_t queries = 0;     // queries planned this frame (draw-wrapped and box batches)
  std::uint32_t boxQueries = 0;  // of them, over boxes
  std::uint32_t drawQueries = 0;
  std::uint32_t queriedBoxes = 0;  // boxes drawn in the box queries
  std::uint32_t pulledUp = 0;      // nodes queried in place of their hidden children
};

class OcclusionCulling final : public OcclusionOracle {
 public:
  explicit OcclusionCulling(const Skeleton& skeleton, const OcclusionParams& params = {});

  bool occluded(std::uint32_t node) const override;

  // Forgets every result: the next frame draws everything in the frustum and queries it.
  void reset();
  // The results of the previous frame's queries, at the start of a frame.
  void receive(std::span<const OcclusionResult> results);
  // After the selection: this frame's queries. front: the nodes drawn, in the order they are
  // drawn; hidden: the nodes the walk left out as occluded (Selection::occluded).
  OcclusionPlan plan(std::span<const std::uint32_t> front, std::span<const std::uint32_t> hidden);

  // Frames planned so far (the frame the next plan() belongs to is frame() + 1).
  std::uint32_t frame() const { return frame_; }
  const OcclusionCounters& counters() const { return counters_; }
  // The last measured samples of a node found visible (0 when unknown or hidden).
  std::uint64_t samples(std::uint32_t node) const { return state_[node].samples; }

  // CHC++'s probability that a node hidden for `frames` frames stays hidden.
  static double keepProbability(std::uint32_t frames);
  // Groups nodes (with their keep probabilities, sorted descending) into multiqueries by
  // CHC++'s value |M| / (1 + (1 - prod p) |M|), at most maxBatch each: the sizes, in order.
  static std::vector<std::size_t> batchSizes(std::span<const double> sortedKeep,
                                             std::size_t maxBatch);

 private:
  enum class Known : std::uint8_t { Unknown, Visible, Hidden };
  struct NodeState {
    Known known = Known::Unknown;
    std::uint32_t resultFrame = 0;   // frame whose query gave `known`
    std::uint32_t hiddenFrames = 0;  // consecutive frames found hidden
    std::uint32_t nextTest = 0;      // visible: frame at which it is queried again
    std::uint64_t samples = 0;
    std::uint32_t shownAt = 0;       // frame of the last query that found its box not hidden
    std::uint32_t pulledAt = 0;      // frame it was last queried in its children's place
    std::uint32_t noPullUntil = 0;
  };
  bool freshHidden(std::uint32_t node) const;  // in plan(): hidden by the last plan's query
  std::uint32_t jitter(std::uint32_t node) const;

  const Skeleton& skeleton_;
  OcclusionParams params_;
  std::vector<NodeState> state_;
  std::uint32_t frame_ = 0;
  OcclusionCounters counters_;
  std::vector<std::uint32_t> reached_;  // frame stamp: node is drawn, hidden or an ancestor
  std::vector<std::uint32_t> hiddenAt_;
};

}  // namespace hlod
