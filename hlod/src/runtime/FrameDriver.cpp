// The render thread's side of Lakhia III-C/D (front selection with v_time feedback, the loading
// thread fed with load priorities) and Manocha 5.5 (render while loading: nodes not yet on the
// GPU are drawn at a coarser level, never waited for). See hlod/runtime/FrameDriver.h.
#include "hlod/runtime/FrameDriver.h"

#include "hlod/runtime/Framing.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <optional>

namespace hlod {

namespace {

using Clock = std::chrono::steady_clock;

// Durations on the session's clock (the loader's, Loader::clock): a test's clock runs the
// frame loop without sleeping and its times are exact.
double msSince(LinkClock& clock, LinkClock::TimePoint start) {
  return LinkClock::Milliseconds(clock.now() - start).count();
}

}  // namespace

namespace {

// The positions of the front's nodes in near-to-far order.
std::vector<std::size_t> nearToFarOrder(const Skeleton& skeleton, const glm::dvec3& eye,
                                        std::span<const std::uint32_t> front) {
  std::vector<std::pair<double, std::size_t>> ordered;
  ordered.reserve(front.size());
  for (std::size_t i = 0; i < front.size(); ++i) {
    assert(front[i] < skeleton.nodes.size());
    const Aabb& b = skeleton.nodes[front[i]].bounds;
    const glm::dvec3 d = glm::clamp(eye, b.min, b.max) - eye;
    ordered.emplace_back(glm::dot(d, d), i);
  }
  std::stable_sort(ordered.begin(), ordered.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::size_t> out;
  out.reserve(ordered.size());
  for (const auto& [d2, i] : ordered) out.push_back(i);
  return out;
}

}  // namespace

std::vector<std::uint32_t> nearToFar(const Skeleton& skeleton, const glm::dvec3& eye,
                                     std::span<const std::uint32_t> front) {
  std::vector<std::uint32_t> out;
  out.reserve(front.size());
  for (std::size_t i : nearToFarOrder(skeleton, eye, front)) out.push_back(front[i]);
  return out;
}

void orderNearToFar(const Skeleton& skeleton, const glm::dvec3& eye,
                    std::vector<std::uint32_t>& front, std::vector<NodeDraw>& draws) {
  assert(draws.size() == front.size());
  std::vector<std::uint32_t> f;
  std::vector<NodeDraw> d;
  f.reserve(front.size());
  d.reserve(front.size());
  for (std::size_t i : nearToFarOrder(skeleton, eye, front)) {
    f.push_back(front[i]);
    d.push_back(draws[i]);
  }
  front = std::move(f);
  draws = std::move(d);
}

FrameDriver::FrameDriver(std::unique_ptr<Selector> selector,
                         std::unique_ptr<Selector> prefetchSelector, Loader& loader,
                         NodeRenderer& renderer, const FrameDriverOptions& options)
    : selector_(std::move(selector)),
      prefetchSelector_(std::move(prefetchSelector)),
      loader_(loader),
      renderer_(renderer),
      options_(options),
      predictor_(options.prediction),
      occlusion_(selector_->skeleton(), options.occlusionParams),
      occlusionAuto_(options.occlusion) {
  assert(selector_);
  renderer_.setGpuBudget(options_.gpuBudgetBytes);
  assert(options_.width > 0 && options_.height > 0);
  const Skeleton& skel = selector_->skeleton();
  for (std::uint32_t r : skel.roots) bounds_.extend(skel.nodes[r].bounds);
}

void FrameDriver::drainLoader() {
  for (auto& e : loader_.drainEvents()) {
    if (e.kind == LoaderEvent::Kind::Loaded) {
      if (e.mesh) renderer_.queueUpload(e.node, std::move(e.mesh));
    } else {
      renderer_.evict(e.node);
    }
  }
}

void FrameDriver::requeue(std::span<const std::uint32_t> nodes) {
  for (std::uint32_t n : nodes) {
    if (renderer_.pendingOrOnGpu(n) || !loader_.isResident(n)) continue;
    if (auto mesh = loader_.residentPayload(n)) renderer_.queueUpload(n, std::move(mesh));
  }
}

DrawSplit splitDraw(const DrawReport& report) {
  DrawSplit s;
  const double total = std::isfinite(report.ms) ? std::max(0.0, report.ms) : 0.0;
  for (const PassTime& p : report.passes) {
    const double ms = std::isfinite(p.gpuMs) ? std::max(0.0, p.gpuMs) : 0.0;
    if (isScreenPass(p.name)) s.screenMs += ms;
    if (p.name == "shadow") s.shadowMs += ms;
    if (p.name == "occlusion") s.occlusionMs += ms;
  }
  s.screenMs = std::min(s.screenMs, total);
  s.shadowMs = std::min(s.shadowMs, total - s.screenMs);
  s.occlusionMs = std::min(s.occlusionMs, total - s.screenMs - s.shadowMs);
  s.geometryMs = total - s.screenMs - s.shadowMs - s.occlusionMs;
  return s;
}

Result<DrawSplit> FrameDriver::timeDraws(const Camera& camera, std::span<const std::uint32_t> front,
                                         std::span<const NodeDraw> draws) {
  // The first draw pays the first-use costs; the median of the next three is this machine's
  // speed (one timed draw on a shared machine was off by up to 1.7x in the first frame).
  if (auto warm = renderer_.draw(camera, front, draws); !warm) return warm.error();
  std::array<DrawSplit, 3> timed;
  for (DrawSplit& t : timed) {
    auto drawn = renderer_.draw(camera, front, draws);
    if (!drawn) return drawn.error();
    t = splitDraw(*drawn);
  }
  std::sort(timed.begin(), timed.end(),
            [](const DrawSplit& a, const DrawSplit& b) { return a.geometryMs < b.geometryMs; });
  const DrawSplit& median = timed[1];
  screenPassMs_ = median.screenMs;
  if (median.shadowMs > 0.0 && median.geometryMs > 0.0)
    shadowShare_.set(median.shadowMs / median.geometryMs);
  return median;
}

double FrameDriver::fixedPartMs(double geometryMs) const {
  // At most half of a draw is taken as fixed: a noisy measurement of the fixed cost never leaves
  // v_time learning from nothing.
  return std::min(fixedMs_, 0.5 * geometryMs);
}

double FrameDriver::frontMs(double geometryMs) const {
  return geometryMs - fixedPartMs(geometryMs);
}

double FrameDriver::frontDraws() const {
  return renderer_.drawsShadowPass() ? 1.0 + shadowShare_.vTime() : 1.0;
}

Status FrameDriver::start(double knownVTime, double knownFixedMs) {
  if (auto roots = loader_.loadRoots(); !roots) return roots.error();
  // hlod_0 is what everything falls back to: on the GPU before the first frame, unbudgeted.
  drainLoader();
  if (auto u = renderer_.upload(1e300, 0); !u) return u.error();
  while (renderer_.pendingUploads() > 0)
    if (auto u = renderer_.upload(1e300, 0); !u) return u.error();

  const Skeleton& skel = selector_->skeleton();
  const bool known = knownVTime > 0.0 && std::isfinite(knownVTime);
  // The whole model in view, upright, as its default view shows it.
  const double aspect = static_cast<double>(options_.width) / options_.height;
  const Camera cam = bounds_.empty() ? Camera{} : defaultView(bounds_, skel.up, 60.0, aspect);
  TimedFront roots;
  if (!bounds_.empty()) {
    auto empty = timeDraws(cam, {}, {});
    if (!empty) return empty.error();
    fixedMs_ = empty->geometryMs;
    const std::vector<std::uint32_t> front = nearToFar(skel, cam.position, skel.roots);
    auto timed = timeDraws(cam, front, {});
    if (!timed) return timed.error();
    for (std::uint32_t r : skel.roots)
      roots.cost += std::max(skel.nodes[r].cost, selector_->params().lakhia.c_minCost);
    roots.geometryMs = timed->geometryMs;
    // Per-pixel passes do not scale with the front, and the shadow pass has its share: v_time is
    // the geometry pass per unit of cost.
    if (timed->geometryMs > 0.0 && roots.cost > 0.0)
      measuredVTime_ = frontMs(timed->geometryMs) / roots.cost;
  }
  if (known && knownFixedMs > 0.0 && std::isfinite(knownFixedMs)) fixedMs_ = knownFixedMs;
  reservedFixedMs_ = fixedMs_;
  const double v = known ? knownVTime : measuredVTime_;
  if (v > 0.0 && std::isfinite(v)) {
    selector_->setVTime(v);
    if (prefetchSelector_) prefetchSelector_->setVTime(v);
  }
  if (options_.loaderThread) loader_.start();
  if (!known && !bounds_.empty() && measuredVTime_ > 0.0 && selector_->budgeted())
    return selector_->remakeable() ? probeVTime(cam, roots) : probeOwnVTime(cam);
  return Ok{};
}

void FrameDriver::forgetProbeFrames() {
  frames_ = 0;
  recent_.clear();
  lastFront_.clear();
  lastDraws_.clear();
}

Status FrameDriver::probeOwnVTime(const Camera& camera) {
  CameraSample sample;
  sample.camera = camera;
  const auto settleTimeout = options_.settleTimeout;
  options_.settleTimeout = std::min(settleTimeout, std::chrono::milliseconds(1000));
  Status status = Ok{};
  for (int i = 0; i < 4; ++i) {
    auto frame = renderFrame(sample, FrameMode::Settled);
    if (!frame) {
      status = frame.error();
      break;
    }
    auto timed = timeDraws(camera, lastFront_, lastDraws_);
    if (!timed) {
      status = timed.error();
      break;
    }
    const double cost = selector_->lastEstimatedCost();
    if (!(timed->geometryMs > 0.0 && cost > 0.0)) break;
    const double v = frontMs(timed->geometryMs) / cost;
    const bool steady = std::abs(v / measuredVTime_ - 1.0) < 0.1;
    measuredVTime_ = v;
    reservedFixedMs_ = fixedPartMs(timed->geometryMs);
    selector_->setVTime(v);
    if (prefetchSelector_) prefetchSelector_->setVTime(v);
    if (steady) break;
  }
  options_.settleTimeout = settleTimeout;
  forgetProbeFrames();
  return status;
}

Result<FrameDriver::TimedFront> FrameDriver::probeFront(const Camera& camera, double vTime) {
  // Its own selector, so that the probe leaves no hysteresis or toggle history for frame 0.
  auto probe = makeSelector(selector_->name(), selector_->skeleton(), selector_->params());
  if (!probe) return probe.error();
  (*probe)->setVTime(vTime);
  std::swap(selector_, *probe);
  CameraSample sample;
  sample.camera = camera;
  // A session that streams slowly (or --io-mbps) is not held up: what loads in a second is
  // measured, coarser.
  const auto settleTimeout = options_.settleTimeout;
  options_.settleTimeout = std::min(settleTimeout, std::chrono::milliseconds(1000));
  auto first = renderFrame(sample, FrameMode::Settled);
  options_.settleTimeout = settleTimeout;
  std::swap(selector_, *probe);
  if (!first) return first.error();
  // renderFrame drew the front once: its first use is paid, timeDraws pays it again (cheap).
  auto timed = timeDraws(camera, lastFront_, lastDraws_);
  if (!timed) return timed.error();
  forgetProbeFrames();
  return TimedFront{(*probe)->lastEstimatedCost(), timed->geometryMs};
}

// hlod_0 is few nodes, each drawn small: a front that fills the budget has many more draw calls
// and larger triangles per unit of cost, and on llvmpipe took 1.16x (median) what hlod_0's
// v_time promised (coldstart_bench). So v_time comes from such a front: the one the budget
// selects for `camera`, loaded, drawn once to pay its first use, then timed (median of 3).
// The same camera's hlod_0 and that front also give the part of the geometry pass that no
// front changes: filling the pixels the model covers, which a finer front covers alike. On
// llvmpipe it is most of a small front's time, and a v_time through the origin then prices
// every refinement at several times its cost (Lakhia at 8 ms drew NASA's Mars set's root alone).
// Where the budget's front is not at least twice hlod_0's cost, a front of twice the budget is
// timed instead.
Status FrameDriver::probeVTime(const Camera& camera, const TimedFront& roots) {
  auto front = probeFront(camera, measuredVTime_);
  if (!front) return front.error();
  if (front->cost < 2.0 * roots.cost) {
    auto larger = probeFront(camera, 0.5 * measuredVTime_);
    if (!larger) return larger.error();
    front = std::move(larger);
  }
  if (!(front->geometryMs > 0.0 && front->cost > 0.0)) return Ok{};
  if (front->cost >= 2.0 * roots.cost && front->geometryMs > roots.geometryMs) {
    const double slope = (front->geometryMs - roots.geometryMs) / (front->cost - roots.cost);
    const double intercept = roots.geometryMs - slope * roots.cost;
    // At least the empty front's, and never all of hlod_0's time.
    fixedMs_ = std::clamp(intercept, fixedMs_, std::max(fixedMs_, 0.9 * roots.geometryMs));
  }
  measuredVTime_ = frontMs(front->geometryMs) / front->cost;
  reservedFixedMs_ = fixedPartMs(front->geometryMs);
  if (measuredVTime_ > 0.0) {
    selector_->setVTime(measuredVTime_);
    if (prefetchSelector_) prefetchSelector_->setVTime(measuredVTime_);
  }
  return Ok{};
}

Status FrameDriver::uploadSettled(FrameRecord& rec) {
  drainLoader();
  // The timeline's upload begins at the frame's first upload; later ones add to its duration.
  if (rec.uploadMs == 0.0) rec.timeline.uploadStartUs = microsecondsOf(loader_.clock().now());
  while (renderer_.pendingUploads() > 0) {
    auto u = renderer_.upload(1e300, 0);
    if (!u) return u.error();
    rec.uploadMs += u->ms;
    rec.uploads += u->uploads;
    rec.uploadBytes += u->bytes;
    if (u->uploads == 0) break;  // the rest deferred by the GPU memory budget
  }
  return Ok{};
}

Result<std::optional<DrawReport>> FrameDriver::drawWhileLoading(const View& view,
                                                                const OcclusionPlan* plan,
                                                                FrameRecord& rec) {
  auto uploadAll = [&] { return uploadSettled(rec); };
  if (auto s = uploadAll(); !s) return s.error();
  // L_I: the front's nodes in memory now (on the GPU after the uploads); L_O: the rest.
  std::vector<std::size_t> in, out;
  for (std::size_t i = 0; i < lastFront_.size(); ++i)
    (renderer_.onGpu().isResident(lastFront_[i]) ? in : out).push_back(i);
  rec.listIn = static_cast<std::uint32_t>(in.size());
  rec.listOut = static_cast<std::uint32_t>(out.size());
  if (auto s = renderer_.beginParts(view.camera, lastFront_, lastDraws_, plan); !s)
    return s.error();
  if (auto s = renderer_.drawPart(in); !s) return s.error();
  const auto deadline = loader_.clock().now() + options_.settleTimeout;
  std::vector<std::uint32_t> waiting;
  while (!out.empty()) {
    if (auto s = uploadAll(); !s) return s.error();
    std::vector<std::size_t> arrived;
    std::erase_if(out, [&](std::size_t i) {
      const bool here = renderer_.onGpu().isResident(lastFront_[i]);
      if (here) arrived.push_back(i);
      return here;
    });
    if (!arrived.empty()) {
      if (auto s = renderer_.drawPart(arrived); !s) return s.error();
      continue;
    }
    // Nothing new on the GPU: wait for the loader (a stall) for the nodes it does not hold yet.
    waiting.clear();
    for (std::size_t i : out)
      if (!loader_.isResident(lastFront_[i])) waiting.push_back(lastFront_[i]);
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - loader_.clock().now());
    if (waiting.empty() || left.count() <= 0) break;  // held but not uploadable, or too late
    rec.stalls = 1;
    if (!loader_.waitUntilAnyResident(waiting, left)) break;
  }
  auto drawn = renderer_.endParts();
  if (!drawn) return drawn.error();
  // L_O did not all come (memory cap, a failed load, the timeout): drawn coarser instead.
  if (!out.empty()) return std::optional<DrawReport>{};
  return std::optional<DrawReport>{std::move(*drawn)};
}

bool FrameDriver::beginOcclusion(const CameraSample& sample) {
  // Last frame's answers: finished with its glFinish, so reading them does not wait.
  std::vector<OcclusionResult> answers = renderer_.occlusionResults();
  const bool active = occlusionAuto_.active();
  // Last frame's visibility stands for this one only when the camera moved little: after more
  // than half a second between the frames (a studied frame far along a path, a paused page) or
  // a step of more than 2% of the model's size (a reset view), it is forgotten and the frame
  // draws everything in the frustum.
  bool jumped = !haveLastSample_;
  if (haveLastSample_) {
    const double dt = sample.time - lastSample_.time;
    const double step = glm::length(sample.camera.position - lastSample_.camera.position);
    jumped = !(dt >= 0.0 && dt <= 0.5) || !(step <= 0.02 * glm::length(bounds_.size()));
  }
  lastSample_ = sample;
  haveLastSample_ = true;
  if (!active) {
    occlusionRan_ = false;
    return false;
  }
  if (!occlusionRan_ || jumped) {
    occlusion_.reset();
  } else {
    occlusion_.receive(answers);
  }
  return true;
}

void FrameDriver::endOcclusion(const Selection& sel, const DrawSplit& split, FrameRecord& rec) {
  const bool ran = occlusionAuto_.active();
  rec.occlusion = ran;
  if (ran) {
    rec.occlusionQueries = occlusion_.counters().queries;
    double hiddenCost = 0.0;
    for (std::uint32_t n : sel.occluded)
      hiddenCost +=
          std::max(selector_->skeleton().nodes[n].cost, selector_->params().lakhia.c_minCost);
    occlusionMs_ = split.occlusionMs;
    occlusionAuto_.update(true, selector_->vTime() * sel.frontDraws * hiddenCost,
                          split.occlusionMs);
  } else {
    occlusionMs_ = 0.0;
    occlusionAuto_.update(false, 0.0, 0.0);
  }
  occlusionRan_ = ran;
}

Result<FrameRecord> FrameDriver::renderFrame(const CameraSample& sample, FrameMode mode,
                                             const CameraSample* lookahead) {
  const auto frameStart = loader_.clock().now();
  const bool settled = mode == FrameMode::Settled;
  FrameRecord rec;
  rec.timeline.startUs = microsecondsOf(frameStart);
  double waitMs = 0.0;

  drainLoader();
  if (!settled) {
    rec.timeline.uploadStartUs = microsecondsOf(loader_.clock().now());
    auto u = renderer_.upload(options_.uploadBudgetMs, options_.uploadBudgetBytes);
    if (!u) return u.error();
    rec.uploadMs = u->ms;
    rec.uploads = u->uploads;
    rec.uploadBytes = u->bytes;
  }

  View view{sample.camera, sample.velocity, options_.width, options_.height};
  view.fogCullDistance = options_.fogCullDistance;
  view.camera.aspect = static_cast<double>(options_.width) / options_.height;
  // This frame's uploads are done, and the per-pixel passes (sky, SSAO, outline) will cost what
  // they cost last frame whatever the front: the geometry gets the rest of the budget.
  const bool culling = beginOcclusion(sample);
  view.occlusion = culling ? &occlusion_ : nullptr;
  // The occlusion queries' box pass costs what it cost last frame: reserved as the per-pixel
  // passes are.
  view.spentMs = rec.uploadMs + screenPassMs_ + reservedFixedMs_ + (culling ? occlusionMs_ : 0.0);
  view.frontDraws = frontDraws();
  const auto selectStart = loader_.clock().now();
  rec.timeline.selectStartUs = microsecondsOf(selectStart);
  // Settled: select as if everything were resident; that front is then loaded before drawing.
  const AllResident allResident;
  Selection sel = selector_->select(
      view, settled ? static_cast<const Residency&>(allResident) : renderer_.onGpu());
  rec.selectorMs = msSince(loader_.clock(), selectStart);
  loader_.setWanted(sel.loadPriorities);
  // Wanted and in memory, but not on the GPU (its budget freed them): uploaded again.
  requeue(settled ? std::span<const std::uint32_t>(sel.front) : sel.notResident);

  // Known-path prefetch: the selection for a camera further along the path, at lower priority.
  // Without a path, a realtime frame predicts one from the camera's motion (Manocha sec. 5.3).
  std::optional<CameraSample> predicted;
  if (!lookahead && !settled && options_.predict) {
    predictor_.observe(sample);
    predicted = predictor_.predict();
    if (predicted) lookahead = &*predicted;
  }
  if (lookahead && prefetchSelector_) {
    View ahead{lookahead->camera, lookahead->velocity, options_.width, options_.height};
    ahead.camera.aspect = view.camera.aspect;
    ahead.occlusion = view.occlusion;
    prefetchSelector_->setVTime(selector_->vTime());
    Selection future = prefetchSelector_->select(ahead, allResident);
    for (auto& r : future.loadPriorities) r.priority *= options_.prefetchWeight;
    loader_.prefetch(future.loadPriorities);
  }

  std::optional<DrawReport> drawnInParts;
  if (settled) {
    auto onGpu = [&] {
      return std::all_of(sel.front.begin(), sel.front.end(),
                         [&](std::uint32_t n) { return renderer_.onGpu().isResident(n); });
    };
    if (!onGpu() && options_.renderWhileLoading && renderer_.canDrawInParts()) {
      // Manocha 5.5: the resident part drawn while the rest loads.
      lastFront_ = sel.front;
      lastDraws_ = sel.draws;
      orderNearToFar(selector_->skeleton(), view.camera.position, lastFront_, lastDraws_);
      OcclusionPlan plan;
      if (culling) plan = occlusion_.plan(lastFront_, sel.occluded);
      const auto waitStart = loader_.clock().now();
      rec.timeline.drawStartUs = microsecondsOf(waitStart);
      auto parts = drawWhileLoading(view, culling ? &plan : nullptr, rec);
      if (!parts) return parts.error();
      rec.timeline.drawEndUs = microsecondsOf(loader_.clock().now());
      drawnInParts = std::move(*parts);
      waitMs = std::max(
          0.0, msSince(loader_.clock(), waitStart) - (drawnInParts ? drawnInParts->ms : 0.0));
      if (!drawnInParts) {
        // L_O did not come: drawn coarser from what is on the GPU, as below.
        sel = selector_->select(view, renderer_.onGpu());
        loader_.setWanted(sel.loadPriorities);
      }
    } else if (!onGpu()) {
      // Settled uploads are unbudgeted and, like the wait, not part of the frame time.
      const auto waitStart = loader_.clock().now();
      const bool loaded = std::all_of(sel.front.begin(), sel.front.end(),
                                      [&](std::uint32_t n) { return loader_.isResident(n); });
      if (!loaded) {
        // The renderer has to wait for the loader: a stall.
        rec.stalls = 1;
        loader_.waitUntilResident(sel.front, options_.settleTimeout);
      }
      if (auto u = uploadSettled(rec); !u) return u.error();
      if (!onGpu()) {
        // Memory cap, a failed load or the timeout: the front does not fit. Draw what is
        // there, coarser.
        sel = selector_->select(view, renderer_.onGpu());
        loader_.setWanted(sel.loadPriorities);
      }
      waitMs = msSince(loader_.clock(), waitStart);
    }
  }

  Result<DrawReport> drawn = DrawReport{};
  if (drawnInParts) {
    drawn = std::move(*drawnInParts);
  } else {
    lastFront_ = sel.front;
    lastDraws_ = sel.draws;
    orderNearToFar(selector_->skeleton(), view.camera.position, lastFront_, lastDraws_);
    OcclusionPlan plan;
    if (culling) plan = occlusion_.plan(lastFront_, sel.occluded);
    rec.timeline.drawStartUs = microsecondsOf(loader_.clock().now());
    drawn = renderer_.draw(view.camera, lastFront_, lastDraws_, culling ? &plan : nullptr);
    if (!drawn) return drawn.error();
    rec.timeline.drawEndUs = microsecondsOf(loader_.clock().now());
  }

  // Frame time: this frame's uploads plus the GL work through glFinish (settled-mode uploads
  // belong to the stall, not to the frame). v_time learns from the drawing alone.
  // The per-pixel passes' measured time leaves the feedback (and is spent next frame, above); the
  // shadow pass's share of the geometry pass is learnt on its own (View::frontDraws), so v_time
  // is the geometry pass's alone and carries over between scenes with and without shadows.
  const DrawSplit split = splitDraw(*drawn);
  screenPassMs_ = split.screenMs;
  selector_->feedback(frontMs(split.geometryMs));
  reservedFixedMs_ = fixedPartMs(split.geometryMs);
  if (split.shadowMs > 0.0 && split.geometryMs > 0.0)
    shadowShare_.update(split.shadowMs, split.geometryMs);
  rec.index = frames_++;
  rec.time = sample.time;
  fillFromSelection(rec, sel);
  endOcclusion(sel, split, rec);
  lastOccluded_ = sel.occluded;
  rec.gpuBytes = renderer_.gpuBytes();
  rec.gpuEvictions = renderer_.takeGpuEvictions();
  fillFromLoader(rec, loader_.counters());
  rec.triangles = drawn->triangles;  // what was drawn (equal to the front's numTri sum)
  rec.drawMs = drawn->ms;
  rec.queryGpuMs = drawn->gpuMs;
  for (const PassTime& p : drawn->passes) {
    [[maybe_unused]] const bool known = setPassMs(rec, p.name, p.gpuMs);
    assert(known && "a pass FrameRecord has no field for");
  }
  rec.gpuMs = (settled ? 0.0 : rec.uploadMs) + drawn->ms;
  rec.pendingUploads = static_cast<std::uint32_t>(renderer_.pendingUploads());
  rec.wallMs = msSince(loader_.clock(), frameStart);
  rec.cpuMs = rec.wallMs - waitMs;
  if (options_.recentFrames > 0) {
    if (recent_.size() >= options_.recentFrames) recent_.pop_front();
    recent_.push_back(rec);
  }
  return rec;
}

}  // namespace hlod
