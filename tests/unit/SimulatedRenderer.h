#pragma once
// A simulated GPU for the frame loop without GL (hlod::NodeRenderer): its draw time is a fixed
// cost per frame plus a cost per triangle, its uploads cost per node, so that realtime and
// settled frames, the upload budget and the v_time feedback are tested with a simulated clock.
// Drawing a node that is not on the GPU is an Error (the frame driver must never do it).
#include <algorithm>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "hlod/runtime/FrameDriver.h"

namespace hlod::test {

class SimulatedRenderer final : public NodeRenderer {
 public:
  explicit SimulatedRenderer(std::size_t nodes) : onGpu_(nodes) {}

  double msPerTriangle = 1e-4;  // 10 M triangles/s
  double msPerSplat = 0.5e-4;   // a point costs half a triangle
  double msPerFrame = 0.5;      // clear, state changes: not proportional to the front
  // Filling the pixels the model covers: any front that is not empty, whatever its detail.
  double msFill = 0.0;
  double msPerUpload = 1.0;
  double msScreenPass = 0.0;  // a per-pixel pass (as SSAO): the same whatever the front
  // A shadow pass that draws the front again at this share of the geometry pass's time (0: none).
  double shadowShare = 0.0;
  // Triangles below hlod_0 cost this many times more (nearer, larger on screen): what a v_time
  // measured on hlod_0 alone does not see.
  double deeperTriangleFactor = 1.0;

  void queueUpload(std::uint32_t node, std::shared_ptr<const LocalMesh> mesh) override {
    pending_.emplace_back(node, std::move(mesh));
  }
  void evict(std::uint32_t node) override {
    onGpu_.set(node, false);
    std::erase_if(pending_, [&](const auto& p) { return p.first == node; });
  }
  Result<UploadReport> upload(double budgetMs, std::uint64_t) override {
    UploadReport r;
    while (!pending_.empty() && (r.uploads == 0 || r.ms < budgetMs)) {
      onGpu_.set(pending_.front().first, true);
      r.bytes += pending_.front().second->indices.size() * 4;
      pending_.pop_front();
      ++r.uploads;
      r.ms += msPerUpload;
    }
    return r;
  }
  std::size_t pendingUploads() const override { return pending_.size(); }
  const Residency& onGpu() const override { return onGpu_; }
  // A visibility oracle for occlusion queries: whether a node would show any pixel. Unset:
  // everything is visible. A query over a box or a draw reports 100 samples for a visible node.
  std::function<bool(std::uint32_t)> hidden;
  double msPerBoxQuery = 0.01;                  // the box pass: per box drawn in a query
  std::vector<std::uint32_t> lastQueriedBoxes;  // every box of the last draw's box pass

  std::vector<OcclusionResult> occlusionResults() override { return std::exchange(answers_, {}); }

  Result<DrawReport> draw(const Camera&, std::span<const std::uint32_t> front,
                          std::span<const NodeDraw> draws,
                          const OcclusionPlan* occlusion = nullptr) override {
    DrawReport d;
    answers_.clear();
    lastQueriedBoxes.clear();
    double boxMs = 0.0;
    if (occlusion) {
      auto seen = [&](std::uint32_t n) { return !hidden || !hidden(n); };
      for (std::size_t i = 0; i < front.size(); ++i)
        if (occlusion->queryDraw.at(i))
          answers_.push_back({{front[i]}, seen(front[i]) ? 100u : 0u});
      for (const auto& batch : occlusion->boxBatches) {
        const bool any = std::any_of(batch.begin(), batch.end(), seen);
        answers_.push_back({batch, any ? 100u : 0u});
        lastQueriedBoxes.insert(lastQueriedBoxes.end(), batch.begin(), batch.end());
        boxMs += msPerBoxQuery * double(batch.size());
      }
    }
    double weighted = 0.0;
    for (std::size_t i = 0; i < front.size(); ++i) {
      const std::uint32_t n = front[i];
      if (!onGpu_.isResident(n)) return makeError("drew a node that is not on the GPU");
      // A node's triangles, the fewer its draw asks for, or its splats at msPerSplat.
      const bool splats = !draws.empty() && draws[i].splats;
      const std::uint64_t t = draws.empty() ? triangles_.at(n) : draws[i].triangles;
      if (splats) {
        weighted += splatCounts_.at(n) * msPerSplat / msPerTriangle;
        continue;
      }
      d.triangles += t;
      weighted += static_cast<double>(t) * (levels_.at(n) > 0 ? deeperTriangleFactor : 1.0);
    }
    const double geometry = msPerFrame + (front.empty() ? 0.0 : msFill) + msPerTriangle * weighted;
    const double shadow = shadowShare * msPerTriangle * weighted;
    d.ms = shadow + geometry + msScreenPass + boxMs;
    d.gpuMs = d.ms;
    if (shadowShare > 0.0) d.passes.push_back({"shadow", shadow});
    d.passes.push_back({"geometry", geometry});
    if (boxMs > 0.0) d.passes.push_back({"occlusion", boxMs});
    if (msScreenPass > 0.0) d.passes.push_back({"ssao", msScreenPass});
    d.drawCalls = front.size();
    lastFront.assign(front.begin(), front.end());
    return d;
  }
  // Render while loading: parts are recorded (each a list of nodes, which must be on the GPU
  // when drawn); the finished frame costs what draw() says of the whole front.
  bool drawsInParts = false;
  std::vector<std::vector<std::uint32_t>> parts;
  bool canDrawInParts() const override { return drawsInParts; }
  Status beginParts(const Camera& camera, std::span<const std::uint32_t> front,
                    std::span<const NodeDraw> draws, const OcclusionPlan* occlusion) override {
    partsCamera_ = camera;
    partsFront_.assign(front.begin(), front.end());
    partsDraws_.assign(draws.begin(), draws.end());
    partsPlan_ = occlusion ? std::optional<OcclusionPlan>(*occlusion) : std::nullopt;
    parts.clear();
    return Ok{};
  }
  Status drawPart(std::span<const std::size_t> positions) override {
    std::vector<std::uint32_t> nodes;
    for (std::size_t i : positions) {
      if (!onGpu_.isResident(partsFront_.at(i))) return makeError("drew a part not on the GPU");
      nodes.push_back(partsFront_[i]);
    }
    parts.push_back(std::move(nodes));
    return Ok{};
  }
  Result<DrawReport> endParts() override {
    return draw(partsCamera_, partsFront_, partsDraws_, partsPlan_ ? &*partsPlan_ : nullptr);
  }

  Image readback() override { return Image{1, 1, {0, 0, 0, 255}}; }
  bool drawsShadowPass() const override { return shadowShare > 0.0; }

  void setTriangles(const Skeleton& sk) {
    for (const NodeInfo& n : sk.nodes) {
      triangles_.push_back(n.numTri);
      splatCounts_.push_back(n.splatCount);
      levels_.push_back(n.level);
    }
  }
  std::vector<std::uint32_t> lastFront;

 private:
  ResidencySet onGpu_;
  std::deque<std::pair<std::uint32_t, std::shared_ptr<const LocalMesh>>> pending_;
  std::vector<std::uint64_t> triangles_;
  std::vector<std::uint32_t> levels_;
  std::vector<std::uint32_t> splatCounts_;
  std::vector<OcclusionResult> answers_;
  Camera partsCamera_;
  std::vector<std::uint32_t> partsFront_;
  std::vector<NodeDraw> partsDraws_;
  std::optional<OcclusionPlan> partsPlan_;
};

}  // namespace hlod::test
