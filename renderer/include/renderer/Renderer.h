#pragma once
// Offscreen renderer: one framebuffer (RGBA8 colour, 32-bit float depth, reversed-Z), the shader
// variants of the declared effects, and the frame as a list of passes, each timed with a
// GL_TIME_ELAPSED query. One Renderer per GL context (and so per thread / viewing session).
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "hlod/Mesh.h"
#include "hlod/Result.h"
#include "hlod/metrics/ImageMetrics.h"
#include "hlod/scene/SceneFile.h"
#include "renderer/FrameView.h"
#include "renderer/GlContext.h"
#include "renderer/GpuMesh.h"
#include "renderer/OcclusionQueries.h"
#include "renderer/ShaderProgram.h"
#include "renderer/ShaderVariant.h"

namespace renderer {

// The effects a scene declares (hlod/scene/SceneFile.h). Only these are compiled and executed.
using Effects = hlod::SceneEffects;

struct RenderOptions {
  int width = 1280;
  int height = 720;
  Effects effects = hlod::defaultEffects();
  glm::dvec3 up{0.0, 0.0, 1.0};  // world up (hemisphere light, sky)
};

// The passes a frame may run, in their order. A Renderer runs only those its effects declare.
enum class Pass { Shadow, Geometry, Sky, Ssao, SsaoBlur, Composite, Outline };
const char* passName(Pass pass);
// The passes the effects call for, in frame order (geometry always).
std::vector<Pass> passesFor(const Effects& effects);

struct PassTiming {
  std::string name;
  double gpuMs = 0.0;
};

struct FrameTiming {
  double cpuMs = 0.0;  // wall time of the frame's GL work through glFinish
  double gpuMs = 0.0;  // sum of the passes' GL_TIME_ELAPSED
  // Whether gpuMs and the passes' times are the GPU's (ContextInfo::gpuTimers); on a software
  // rasteriser they are not the passes' time, and cpuMs is the frame's only time.
  bool gpuTimed = false;
  std::vector<PassTiming> passes;
  std::uint64_t triangles = 0;
  std::uint64_t drawCalls = 0;
};

// The GL objects a Renderer owns (not the meshes'): what an undeclared effect must not add.
struct ResourceCounts {
  int framebuffers = 0;
  int renderbuffers = 0;
  int textures = 0;
  int programs = 0;
  int queries = 0;
  int vertexArrays = 0;
  bool operator==(const ResourceCounts&) const = default;
};

// A frame's occlusion queries (OcclusionQueries.h), in drawFrame's terms.
struct OcclusionDraw {
  std::span<const std::uint8_t> queryMesh;              // per mesh: 1 to wrap its draw
  std::span<const std::vector<hlod::Aabb>> boxBatches;  // one query each, after the geometry
  std::span<const GpuMesh* const> shadowCasters;        // hidden, but still casting shadows
  std::span<const hlod::Aabb> tint;                     // debug view: boxes tinted over the frame
};

class Renderer {
 public:
  static constexpr int kMaxSize = 8192;  // largest framebuffer side

  // The context must be current on this thread for the Renderer's whole life.
  static hlod::Result<std::unique_ptr<Renderer>> create(GlContext& context,
                                                        const RenderOptions& options);

  // Draws the meshes camera-relative and waits for the GL (glFinish) so the times are real.
  // occlusion: the frame's queries (nullptr: none); the box pass is timed as "occlusion".
  FrameTiming drawFrame(const FrameView& view, std::span<const GpuMesh* const> meshes,
                        const OcclusionDraw* occlusion = nullptr);
  // The last drawFrame's query answers: per mesh index whose draw was wrapped, and per box
  // batch, in order (nullopt: not available). Empty when it had no queries.
  struct OcclusionAnswers {
    std::vector<std::size_t> queriedMeshes;
    std::vector<std::optional<std::uint64_t>> meshSamples;  // queriedMeshes' answers
    std::vector<std::optional<std::uint64_t>> boxSamples;
  };
  OcclusionAnswers occlusionAnswers() const;

  // The occlusion-switch's hardware culling (Manocha sec. 4.2, HC): one query per batch of boxes
  // against the depth the last frame left (drawn by this context a frame earlier as the
  // occluders, OR), changing nothing; waits for the answers (this context does nothing else).
  std::vector<std::optional<std::uint64_t>> queryBoxesOnLastFrame(
      const FrameView& view, std::span<const std::vector<hlod::Aabb>> batches);

  // Render while loading (Manocha sec. 5.5): a frame drawn in parts as its nodes arrive.
  // beginParts clears the frame; each drawPart draws more of the front, timed through its
  // glFinish (returned, ms); endParts runs the box pass and the passes after the geometry.
  // Not with a shadow pass, whose map needs the whole front before the geometry.
  bool canDrawInParts() const { return !has(Pass::Shadow); }
  void beginParts(const FrameView& view, const OcclusionDraw* occlusion);
  double drawPart(const FrameView& view, std::span<const GpuMesh* const> meshes,
                  std::span<const std::uint8_t> queryMesh);
  FrameTiming endParts(const FrameView& view);

  // The same for meshes that do not fit in memory together (the study's full-detail reference):
  // the passes that draw them (shadow, geometry) draw `parts` parts in turn into their targets,
  // cleared before the first; part(k) gives part k's meshes, valid until the next call (it may
  // upload and free meshes: it runs between draws, inside the pass's timer). With a shadow pass
  // every part is asked for twice, shadow pass first, and view.sceneRadius must be set (the
  // shadow map's fit, which cannot wait for all the meshes).
  using FramePart = std::function<std::vector<const GpuMesh*>(std::size_t part)>;
  FrameTiming drawFrameInParts(const FrameView& view, std::size_t parts, const FramePart& part);

  // The last frame's pixels, RGBA8, row 0 at the top.
  hlod::Image readback();

  // Which pixels of the last frame show geometry, from its depth buffer (row 0 at the top):
  // exact whatever the background is (a clear colour, a sky, fog), where a colour test misses
  // the pixels where geometry happens to match the background and 8-bit rounding.
  hlod::metrics::Mask coverage();

  const GlFunctions& gl() const { return context_.gl(); }
  const RenderOptions& options() const { return options_; }
  // The passes each frame runs, in order.
  const std::vector<Pass>& passes() const { return passes_; }
  ResourceCounts resources() const;
  // The bytes of the render targets (colour, depth, shadow map, SSAO) that a Renderer with these
  // options allocates in init(): what a server counts against its GL memory cap first.
  static std::uint64_t targetBytes(const RenderOptions& options);
  // Programs compiled so far: each variant once, however many frames and meshes.
  int programCompiles() const { return compiles_; }

 private:
  Renderer(GlContext& context, const RenderOptions& options)
      : context_(context), options_(options), passes_(passesFor(options.effects)) {}
  hlod::Status init();
  hlod::Status initShadows();
  hlod::Status initPostTargets();
  // The cached program of a variant, compiled on first use; nullptr if it failed to build.
  const ShaderProgram* program(const VariantKey& key);
  bool has(Pass pass) const;

  void runPass(Pass pass, const FrameView& view, std::span<const GpuMesh* const> meshes,
               FrameTiming& timing, const OcclusionDraw* occlusion);
  // The sun's view for this frame's shadow map, fitted to view's scene sphere (or the meshes').
  void fitShadow(const FrameView& view, std::span<const GpuMesh* const> meshes);
  // Waits for the GL, adds the CPU time since start and reads the passes' timers: those at the
  // indices `timed` (nullptr: all), and the occlusion pass's when it ran.
  void finishFrame(std::chrono::steady_clock::time_point start, FrameTiming& timing,
                   const std::vector<std::size_t>* timed = nullptr);
  void shadowPass(std::span<const GpuMesh* const> meshes,
                  std::span<const GpuMesh* const> moreCasters, bool clear = true);
  void geometryPass(const FrameView& view, std::span<const GpuMesh* const> meshes,
                    FrameTiming& timing, std::span<const std::uint8_t> queryMesh);
  void clearGeometry();
  // Draws meshes into the geometry pass; firstIndex: the first mesh's index in the frame (the
  // occlusion answers are per frame index).
  void drawMeshes(const FrameView& view, std::span<const GpuMesh* const> meshes,
                  FrameTiming& timing, std::span<const std::uint8_t> queryMesh,
                  std::size_t firstIndex);
  void prepareOcclusion(const OcclusionDraw* occlusion);
  void skyPass(const FrameView& view);
  void fullscreenPass(ProgramKind kind, GLuint target, GLuint input, const FrameView& view);

  GlContext& context_;
  RenderOptions options_;
  std::vector<Pass> passes_;
  int compiles_ = 0;
  // Always: the frame's colour and depth (depth a texture when a post pass reads it).
  GlObject framebuffer_, colour_, depth_, depthTexture_;
  std::map<VariantKey, ShaderProgram> programs_;
  std::vector<GlObject> queries_;  // one GL_TIME_ELAPSED query per pass
  // Declared only: the shadow map; SSAO and blur targets; the colour-only target the
  // fullscreen post passes blend into (no depth attached: the depth texture is their input).
  GlObject shadowFramebuffer_, shadowTexture_;
  GlObject aoFramebuffer_, aoTexture_, blurFramebuffer_, blurTexture_;
  GlObject postFramebuffer_, fullscreenVao_;
  // This frame's sun matrix (world relative to the scene sphere's centre -> sun clip space).
  glm::dmat4 shadowViewProjection_{1.0};
  glm::dvec3 shadowCentre_{0.0};
  // Made at the first frame with occlusion queries (a session without culling has none).
  std::unique_ptr<OcclusionQueries> occlusion_;
  GlObject occlusionTimer_;
  std::vector<std::size_t> queriedMeshes_;  // this frame's draws wrapped in a query
  bool occlusionPass_ = false;              // this frame's box pass ran
  // A frame drawn in parts: what it has measured so far.
  FrameTiming parts_;
  std::size_t partsMeshes_ = 0;
  double geometryPartsMs_ = 0.0;
  OcclusionDraw partsOcclusion_;
  bool partsHaveOcclusion_ = false;
};

// Writes an image; the format follows the extension (.png, .jpg/.jpeg, .exr, .tif, ...).
hlod::Status writeImage(const std::string& path, const hlod::Image& image);

}  // namespace renderer
