#pragma once
// A hand-made scene for GL tests of the frame loop: nodes that are boxes filling their bounds
// (or a given geometry box), a wall in front of a block of four boxes, served from memory, and
// a rig that runs the FrameDriver on a real (software) GL context.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>

#include "GlTestScene.h"
#include "hlod/runtime/FrameDriver.h"
#include "hlod/runtime/Loader.h"
#include "renderer/GlContext.h"
#include "renderer/GpuNodeRenderer.h"

namespace gltest {

using hlod::Aabb;
using hlod::NodeInfo;

// Serves, for every node, a box: its geometry box where one is given, else its bounds.
class BoxNodeSource final : public hlod::NodeSource {
 public:
  explicit BoxNodeSource(hlod::Skeleton sk, std::vector<Aabb> geometry = {})
      : skeleton_(std::move(sk)), geometry_(std::move(geometry)) {}
  const hlod::Skeleton& skeleton() const override { return skeleton_; }
  hlod::Status readPayloadChunk(std::uint32_t node, std::uint64_t offset,
                                std::span<std::byte> out) const override {
    if (node >= skeleton_.nodes.size() || offset + out.size() > kPayload)
      return hlod::makeError("out of range");
    std::fill(out.begin(), out.end(), std::byte{1});
    return hlod::Ok{};
  }
  hlod::Result<hlod::LocalMesh> decodePayload(std::uint32_t node,
                                              std::span<const std::byte>) const override {
    const Aabb& b = node < geometry_.size() && !geometry_[node].empty()
                        ? geometry_[node]
                        : skeleton_.nodes.at(node).bounds;
    const glm::vec4 colour = node == 0 ? glm::vec4(0.6f, 0.6f, 0.6f, 1.0f)
                                       : glm::vec4(0.9f, 0.3f + 0.1f * (node % 5), 0.2f, 1.0f);
    return hlod::toLocal(gltest::box(b.centre(), b.size() * 0.5, colour));
  }
  static constexpr std::uint64_t kPayload = 64;

 private:
  hlod::Skeleton skeleton_;
  std::vector<Aabb> geometry_;
};

// Node 0: a wall across x = 10 (y in [-20, 20], z in [0, 12]). Node 1: a block behind it at
// x in [20, 30], y in [-8, 8], with four children (2..5), boxes side by side along y.
// Node 6: a box off to the side (y in [30, 34]). With thinNode, node 7: a long thin node from
// x = -5 to 30 whose geometry is only its far end (x in [25, 30]), hidden behind the wall; a
// camera at x = 0, y = -2 is inside its box.
inline hlod::Skeleton wallScene(bool thinNode) {
  hlod::Skeleton sk;
  auto add = [&](std::uint32_t parent, glm::dvec3 lo, glm::dvec3 hi, std::uint32_t level) {
    NodeInfo n;
    n.parent = parent;
    n.level = level;
    n.block = level == 0 ? static_cast<std::uint32_t>(sk.roots.size()) : 1;
    n.bounds.min = lo;
    n.bounds.max = hi;
    n.centre = n.bounds.centre();
    n.numTri = 12;
    n.cost = 12;
    n.staticBenefit = 10;
    n.geometricError = level == 0 && parent == hlod::kNoNode && lo.x > 15 ? 4.0 : 0.0;
    n.payloadSize = BoxNodeSource::kPayload;
    n.memoryBytes = 1024;
    if (parent == hlod::kNoNode) sk.roots.push_back(static_cast<std::uint32_t>(sk.nodes.size()));
    sk.nodes.push_back(n);
  };
  add(hlod::kNoNode, {10, -20, 0}, {11, 20, 12}, 0);
  add(hlod::kNoNode, {20, -8, 0}, {30, 8, 6}, 0);
  for (int k = 0; k < 4; ++k) add(1, {20, -8 + 4.0 * k, 0}, {30, -4 + 4.0 * k, 6}, 1);
  add(hlod::kNoNode, {20, 30, 0}, {24, 34, 6}, 0);
  if (thinNode) add(hlod::kNoNode, {-5, -3, 0}, {30, -1, 6}, 0);
  sk.nodes[1].firstChild = 2;
  sk.nodes[1].childCount = 4;
  // Blocks are numbered by root, in order.
  sk.nodes[6].block = 2;
  if (thinNode) sk.nodes[7].block = 3;
  return sk;
}

inline std::vector<Aabb> wallGeometry() {
  std::vector<Aabb> g(8);
  g[7].min = {25, -3, 0};
  g[7].max = {30, -1, 6};
  return g;
}

struct GlRig {
  explicit GlRig(hlod::OcclusionMode mode = hlod::OcclusionMode::On, bool thinNode = false,
                 std::uint64_t gpuBudgetBytes = 0)
      : source(wallScene(thinNode), wallGeometry()), loader(source) {
    auto c = renderer::createContext(renderer::Backend::Auto);
    if (!c) return;
    context = std::move(*c);
    renderer::RenderOptions ro;
    ro.width = 160;
    ro.height = 90;
    ro.effects = hlod::defaultEffects();
    auto r = renderer::GpuNodeRenderer::create(*context, source.skeleton(), ro);
    if (!r) return;
    gpu = std::move(*r);
    hlod::FrameDriverOptions o;
    o.width = ro.width;
    o.height = ro.height;
    o.loaderThread = false;
    o.occlusion = mode;
    o.gpuBudgetBytes = gpuBudgetBytes;
    driver = std::make_unique<hlod::FrameDriver>(
        std::move(*hlod::makeSelector("full", source.skeleton())), nullptr, loader, *gpu, o);
    if (!driver->start().ok()) driver.reset();
    while (loader.step()) {
    }
  }
  hlod::CameraSample at(double t, glm::dvec3 eye, glm::dvec3 target = {}) const {
    hlod::CameraSample s;
    s.time = t;
    s.camera.position = eye;
    s.camera.target = target == glm::dvec3{} ? eye + glm::dvec3(1, 0, 0) : target;
    s.camera.up = {0, 0, 1};
    s.camera.fovY = 60;
    return s;
  }
  hlod::FrameRecord frame(const hlod::CameraSample& s) {
    auto r = driver->renderFrame(s, hlod::FrameMode::Settled);
    EXPECT_TRUE(r.ok()) << r.message();
    return r ? *r : hlod::FrameRecord{};
  }
  bool drawn(std::uint32_t node) const {
    const auto& f = driver->lastFront();
    return std::find(f.begin(), f.end(), node) != f.end();
  }
  bool behindDrawn() const {
    for (std::uint32_t n = 1; n <= 5; ++n)
      if (drawn(n)) return true;
    return false;
  }

  BoxNodeSource source;
  hlod::Loader loader;
  std::unique_ptr<renderer::GlContext> context;
  std::unique_ptr<renderer::GpuNodeRenderer> gpu;
  std::unique_ptr<hlod::FrameDriver> driver;
};

#define REQUIRE_RIG(rig) \
  if (!(rig).driver) GTEST_SKIP() << "no GL context (EGL or OSMesa) here"

}  // namespace gltest
