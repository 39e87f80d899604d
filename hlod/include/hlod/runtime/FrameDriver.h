#pragma once
// The frame loop of one viewing session, without GL (Lakhia III-C/D, Manocha 5.5). Its GPU side
// is a NodeRenderer: renderer::GpuNodeRenderer on a real context, a simulated one in tests, so
// that realtime and settled frames are tested with a simulated clock as the selectors are.
//
// A frame:
//   1. drain the loader's events: an unloaded node loses its GPU copy at once (the resident set
//      stays closed upwards: the loader unloads children first); a loaded one queues for upload;
//   2. realtime: upload queued nodes under the per-frame upload budget (at least one a frame, so
//      uploads always progress); what does not fit waits for the next frame;
//   3. select the front against what is on the GPU, the uploads' time already spent
//      (View::spentMs); settled: as if everything were resident;
//   4. give the load priorities to the loader (and, with a look-ahead camera, the prefetch);
//   5. settled: wait until that front is loaded and upload it (a stall when it was not loaded);
//   6. draw the front near to far; frame time = this frame's uploads + the drawing through
//      glFinish; the drawing alone goes to the selector's v_time feedback.
// With occlusion culling (OcclusionCulling.h), the answers to last frame's queries are taken
// before the selection (step 3), which then leaves hidden nodes out, and step 6 draws the front
// (the occluders) first and then queries the boxes of the hidden nodes.
// Realtime never waits for the loader: a node whose children are not on the GPU is drawn at its
// own level. Settled frames do not depend on I/O timing (for videos and reference frames).
#include <chrono>
#include <cstdint>
#include <deque>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "hlod/Result.h"
#include "hlod/runtime/CameraPath.h"
#include "hlod/runtime/FrameStats.h"
#include "hlod/runtime/Loader.h"
#include "hlod/runtime/MotionPredictor.h"
#include "hlod/runtime/OcclusionAuto.h"
#include "hlod/runtime/OcclusionCulling.h"
#include "hlod/runtime/Selector.h"

namespace hlod {

enum class FrameMode { Realtime, Settled };

struct UploadReport {
  double ms = 0.0;  // time of the uploads' GL work
  std::uint32_t uploads = 0;
  std::uint64_t bytes = 0;
  std::uint32_t deferred = 0;  // left out: no room under the GPU memory budget
};

struct PassTime {
  std::string name;
  double gpuMs = 0.0;
};

struct DrawReport {
  double ms = 0.0;     // wall time of the frame's GL work through glFinish
  double gpuMs = 0.0;  // the passes' timer queries summed
  std::vector<PassTime> passes;
  std::uint64_t triangles = 0;
  std::uint64_t drawCalls = 0;
};

// The GPU side of a session: copies of the resident nodes, their upload queue, the drawing.
class NodeRenderer {
 public:
  virtual ~NodeRenderer() = default;
  // A payload finished loading: queue it for upload (in order: parents before children).
  virtual void queueUpload(std::uint32_t node, std::shared_ptr<const LocalMesh> mesh) = 0;
  // The loader dropped the node: free its GPU copy, or its queued upload.
  virtual void evict(std::uint32_t node) = 0;
  // Uploads queued nodes in order until budgetMs or budgetBytes (0: no byte limit) is spent, at
  // least one. An upload that fails (the GL refused it) is an Error naming the node.
  virtual Result<UploadReport> upload(double budgetMs, std::uint64_t budgetBytes) = 0;
  virtual std::size_t pendingUploads() const = 0;
  // The nodes that have a GPU copy: what a realtime frame may draw.
  virtual const Residency& onGpu() const = 0;
  // Draws the front, ordered near to far, as seen by the camera: per node what draws says (in
  // the front's order; empty: every node whole). occlusion: this frame's queries (nullptr:
  // none): the draws it flags are wrapped in a query, and after the whole front its box batches
  // are drawn inside queries with depth and colour writes off, timed as the pass "occlusion".
  // A box that holds the camera or crosses the near plane is not queried.
  virtual Result<DrawReport> draw(const Camera& camera, std::span<const std::uint32_t> front,
                                  std::span<const NodeDraw> draws,
                                  const OcclusionPlan* occlusion = nullptr) = 0;
  // The answers to the last frame's queries, taken once (a second call returns nothing): read
  // after that frame's glFinish, so without a wait, and used by the frame after it. A query
  // whose result is not available, or that was not issued, is answered "not answered". Draws
  // without queries in between (a measurement) leave them alone.
  virtual std::vector<OcclusionResult> occlusionResults() { return {}; }
  // Bytes of the GPU copies held now (buffers, and each texture once).
  virtual std::uint64_t gpuBytes() const { return 0; }
  // GPU copies freed by the GPU memory budget since the last call.
  virtual std::uint32_t takeGpuEvictions() { return 0; }
  // The GPU memory budget in bytes (0: none), kept by least-recently-drawn replacement
  // (GpuMemoryManager); an upload that finds no room is deferred.
  virtual void setGpuBudget(std::uint64_t /*bytes*/) {}
  // Whether the node is on the GPU or queued for an upload.
  virtual bool pendingOrOnGpu(std::uint32_t node) const { return onGpu().isResident(node); }
  // Render while loading (Manocha sec. 5.5): a frame drawn in parts, the resident part of its
  // front first (L_I) and each missing node as it arrives (L_O). beginParts takes the whole
  // front (near to far) and its queries; drawPart draws the nodes at these positions of it (on
  // the GPU); endParts finishes the frame. Renderers that cannot (no parts, or a shadow pass
  // whose map needs the whole front first) answer false and are drawn whole.
  virtual bool canDrawInParts() const { return false; }
  virtual Status beginParts(const Camera& /*camera*/, std::span<const std::uint32_t> /*front*/,
                            std::span<const NodeDraw> /*draws*/,
                            const OcclusionPlan* /*occlusion*/) {
    return makeError("this renderer draws no parts");
  }
  virtual Status drawPart(std::span<const std::size_t> /*positions*/) {
    return makeError("this renderer draws no parts");
  }
  virtual Result<DrawReport> endParts() { return makeError("this renderer draws no parts"); }
  // The last frame's pixels, RGBA8, row 0 at the top.
  virtual Image readback() = 0;
  // Whether draw() runs a "shadow" pass: the front drawn again, depth only, from the sun.
  virtual bool drawsShadowPass() const { return false; }
};

// A drawn frame's time by what it scales with. screenMs: the per-pixel passes (isScreenPass), a
// cost of the frame size, not of the front, which the budget reserves and the v_time feedback
// leaves out. shadowMs: the shadow pass, which draws the front again (View::frontDraws).
// geometryMs: the rest of the frame's time through glFinish, which v_time learns from. Each at
// least 0; a pass timer that reads more than the frame is cut to it.
struct DrawSplit {
  double geometryMs = 0.0;
  double shadowMs = 0.0;
  double screenMs = 0.0;
  double occlusionMs = 0.0;  // the occlusion queries' box pass: reserved, left out of v_time
};
DrawSplit splitDraw(const DrawReport& report);

struct FrameDriverOptions {
  double uploadBudgetMs = 2.0;                     // realtime: per-frame upload time
  std::uint64_t uploadBudgetBytes = 0;             // realtime: per-frame upload bytes; 0 = none
  double prefetchWeight = 0.5;                     // prefetch priorities are scaled by this
  std::chrono::milliseconds settleTimeout{60000};  // settled: longest wait for one frame
  int width = 1280;
  int height = 720;
  std::size_t recentFrames = 600;  // records kept in recent(): a bounded ring for long sessions
  // The scene's fog: nodes wholly beyond this are not selected (View::fogCullDistance).
  double fogCullDistance = std::numeric_limits<double>::infinity();
  // start() starts the loader's thread; tests leave it off and step the loader themselves.
  bool loaderThread = true;
  // Occlusion culling: on, off, or auto (on while it pays: OcclusionAuto).
  OcclusionMode occlusion = OcclusionMode::Auto;
  OcclusionParams occlusionParams;
  std::uint64_t gpuBudgetBytes = 0;  // GPU memory budget (NodeRenderer::setGpuBudget); 0: none
  // Settled frames draw the resident part of their front while the loader brings the rest
  // (Manocha sec. 5.5) where the renderer can draw in parts; false: they wait for all of it.
  bool renderWhileLoading = true;
  // Realtime frames without a look-ahead camera (an interactive session) prefetch for the
  // camera their recent motion predicts (MotionPredictor).
  bool predict = false;
  MotionPredictorParams prediction;
};

// A machine's speed at drawing a store's fronts at one frame size: v_time (ms per unit of
// cost) and the geometry pass's fixed part (FrameDriver::fixedMs).
struct FrontTiming {
  double vTime = 0.0;
  double fixedMs = 0.0;
};

class FrameDriver {
 public:
  // The selector (and an optional second one with its own hysteresis state for look-ahead
  // cameras) is owned; loader and renderer must outlive the driver.
  FrameDriver(std::unique_ptr<Selector> selector, std::unique_ptr<Selector> prefetchSelector,
              Loader& loader, NodeRenderer& renderer, const FrameDriverOptions& options);

  // Loads hlod_0 and puts it on the GPU (unbudgeted: before the first frame), then draws it once
  // from a camera that frames the model: first-use costs (shader JIT, texture residency) are
  // not frame 0's. That draw measures this machine's ms per unit of cost, which the selectors
  // start from (so a session's first frame is budget-bound, not drawn at an arbitrary v_time),
  // unless a v_time is given: one measured before (another session of the same store). With a
  // budgeted selector and no v_time given, one settled frame of that camera at the budget is
  // then drawn and timed (probeVTime; for a selector that is not remakeable(), its own frames:
  // probeOwnVTime): no frame of the session, it only sets v_time.
  // knownFixedMs: the fixed part of the geometry pass that session measured (fixedMs()).
  Status start(double knownVTime = 0.0, double knownFixedMs = 0.0);

  // One frame for `sample` (time = path time). lookahead: a camera further along a known path
  // whose selection goes to the loader's prefetch (nullptr: none).
  Result<FrameRecord> renderFrame(const CameraSample& sample, FrameMode mode,
                                  const CameraSample* lookahead = nullptr);

  Selector& selector() { return *selector_; }
  const Selector& selector() const { return *selector_; }
  Loader& loader() { return loader_; }
  NodeRenderer& renderer() { return renderer_; }
  const FrameDriverOptions& options() const { return options_; }
  std::uint64_t framesRendered() const { return frames_; }
  // The front the last frame drew, near to far.
  const std::vector<std::uint32_t>& lastFront() const { return lastFront_; }
  const std::vector<NodeDraw>& lastDraws() const { return lastDraws_; }  // lastFront()'s
  // The nodes the last frame left out as occluded (Selection::occluded).
  const std::vector<std::uint32_t>& lastOccluded() const { return lastOccluded_; }
  // The last options().recentFrames records, oldest first.
  const std::deque<FrameRecord>& recent() const { return recent_; }
  // The v_time start() measured (0 before start, or when it was given): the probe's where
  // there was one, else hlod_0's.
  double measuredVTime() const { return measuredVTime_; }
  // The part of a geometry pass that no front changes (clearing, the finish, filling the pixels
  // the model covers), reserved from the budget and kept out of v_time: an empty front's time,
  // or where start() probed, hlod_0's time less what its cost accounts for at the probe's
  // v_time (see probeVTime).
  double fixedMs() const { return fixedMs_; }
  // What a later session of the same store and frame size can start from (start's arguments).
  FrontTiming timing() const { return {selector_->vTime(), fixedMs_}; }
  // The occlusion culling state (its counters are the last frame's).
  const OcclusionCulling& occlusion() const { return occlusion_; }

 private:
  void drainLoader();
  // Queues for upload the nodes the loader holds but the GPU does not (freed there by the GPU
  // memory budget): the frame wants them again.
  void requeue(std::span<const std::uint32_t> nodes);
  // Settled: what the loader holds goes to the GPU, unbudgeted (the wait's time, not the
  // frame's), up to what the GPU memory budget defers.
  Status uploadSettled(FrameRecord& rec);
  // A settled frame whose front is not all on the GPU, drawn while the rest loads (L_I first,
  // then each node of L_O as it arrives). Nothing (no report) when the renderer cannot, or when
  // L_O did not arrive in time (the frame is then drawn coarser as before).
  Result<std::optional<DrawReport>> drawWhileLoading(const View& view, const OcclusionPlan* plan,
                                                     FrameRecord& rec);
  struct TimedFront {
    double cost = 0.0;        // the selector's estimate, in units of cost
    double geometryMs = 0.0;  // its geometry pass, median of three
  };
  Status probeVTime(const Camera& camera, const TimedFront& roots);
  // For a selector that is not remakeable(): its own settled frames at `camera`, each timed and
  // setting v_time for the next, until v_time moves by less than 10% (at most 4); then
  // forgotten as frames.
  Status probeOwnVTime(const Camera& camera);
  // The probes' frames are not frames of the session.
  void forgetProbeFrames();
  // The front a budgeted selector at `vTime` picks for `camera`, loaded and timed.
  Result<TimedFront> probeFront(const Camera& camera, double vTime);
  // Draws `front` once to pay its first use, then three times: the draw of median geometry time.
  Result<DrawSplit> timeDraws(const Camera& camera, std::span<const std::uint32_t> front,
                              std::span<const NodeDraw> draws);
  // View::frontDraws of the next frame: 1, plus the shadow pass's share where there is one.
  double frontDraws() const;
  // Whether this frame culls by occlusion, after taking last frame's answers; resets the
  // culling state after a camera jump or when auto turns it back on.
  bool beginOcclusion(const CameraSample& sample);
  void endOcclusion(const Selection& selection, const DrawSplit& split, FrameRecord& record);

  std::unique_ptr<Selector> selector_;
  std::unique_ptr<Selector> prefetchSelector_;
  Loader& loader_;
  NodeRenderer& renderer_;
  FrameDriverOptions options_;
  Aabb bounds_;
  std::uint64_t frames_ = 0;
  double measuredVTime_ = 0.0;
  double screenPassMs_ = 0.0;  // the last frame's per-pixel passes (DrawSplit::screenMs)
  double fixedMs_ = 0.0;       // see fixedMs()
  // The part of a draw's geometry pass taken as fixed (at most fixedMs_), and the rest: what
  // v_time learns from.
  double fixedPartMs(double geometryMs) const;
  double frontMs(double geometryMs) const;
  // The fixed part the last feedback took out of v_time's measurement, reserved from the next
  // frame's budget: the same part, so that the last front's estimate is its measured time.
  double reservedFixedMs_ = 0.0;
  // The shadow pass's ms per geometry-pass ms (median of three, low-passed as v_time is). Before
  // its first measurement the shadow pass counts as drawing the front again: a share of 1.
  VTimeFeedback shadowShare_{1.0, 0.3, 4.0, 2.0};
  std::deque<FrameRecord> recent_;
  std::vector<std::uint32_t> lastFront_;
  std::vector<NodeDraw> lastDraws_;  // lastFront_'s
  std::vector<std::uint32_t> lastOccluded_;
  MotionPredictor predictor_;
  OcclusionCulling occlusion_;
  OcclusionAuto occlusionAuto_;
  bool occlusionRan_ = false;    // the last frame culled (its answers are due now)
  double occlusionMs_ = 0.0;     // the last culling frame's box pass, reserved like a pass
  bool haveLastSample_ = false;  // lastSample_ holds the previous frame's camera
  CameraSample lastSample_;
};

// The front of a selection ordered near to far from the camera (by distance to each node's box):
// the depth test then rejects hidden fragments before they are shaded, which on a software
// rasteriser is most of a street-level frame.
std::vector<std::uint32_t> nearToFar(const Skeleton& skeleton, const glm::dvec3& eye,
                                     std::span<const std::uint32_t> front);
// The same order for a front and its draws together.
void orderNearToFar(const Skeleton& skeleton, const glm::dvec3& eye,
                    std::vector<std::uint32_t>& front, std::vector<NodeDraw>& draws);

}  // namespace hlod
