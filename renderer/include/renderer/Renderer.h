#pragma once
// Offscreen renderer: one framebuffer (RGBA8 colour, 32-bit float depth, reversed-Z), the shader
// variants of the declared effects, and the frame as a list of passes, each timed with a
// GL_TIME_ELAPSED query. One Renderer per GL context (and so per thread / viewing session).
#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "hlod/Mesh.h"
#include "hlod/Result.h"
#include "hlod/metrics/ImageMetrics.h"
#include "renderer/FrameView.h"
#include "renderer/GlContext.h"
#include "renderer/GpuMesh.h"
#include "renderer/ShaderProgram.h"

namespace renderer {

// The effects a scene declares. Only these are compiled and executed.
struct Effects {
  bool textures = true;     // sample base-colour textures where a mesh has one
  bool lambert = true;      // directional sun + hemisphere ambient; false: unlit
  bool fog = false;         // exponential distance fog towards the background colour
  double fogDensity = 0.0;  // per world unit; 0 picks one from the view distance
  glm::vec3 background{0.70f, 0.80f, 0.90f};
};

struct RenderOptions {
  int width = 1280;
  int height = 720;
  Effects effects;
  glm::dvec3 up{0.0, 0.0, 1.0};                // world up (hemisphere light)
  glm::dvec3 sunDirection{0.45, -0.35, 0.82};  // towards the sun, world space
};

struct PassTiming {
  std::string name;
  double gpuMs = 0.0;
};

struct FrameTiming {
  double cpuMs = 0.0;  // wall time of the frame's GL work through glFinish
  double gpuMs = 0.0;  // sum of the passes' GL_TIME_ELAPSED
  std::vector<PassTiming> passes;
  std::uint64_t triangles = 0;
  std::uint64_t drawCalls = 0;
};

class Renderer {
 public:
  static constexpr int kMaxSize = 8192;  // largest framebuffer side

  // The context must be current on this thread for the Renderer's whole life.
  static hlod::Result<std::unique_ptr<Renderer>> create(GlContext& context,
                                                        const RenderOptions& options);

  // Draws the meshes camera-relative and waits for the GL (glFinish) so the times are real.
  FrameTiming drawFrame(const FrameView& view, std::span<const GpuMesh* const> meshes);

  // The last frame's pixels, RGBA8, row 0 at the top.
  hlod::Image readback();

  // Which pixels of the last frame show geometry, from its depth buffer (row 0 at the top):
  // exact whatever the background is (a clear colour, a sky, fog), where a colour test misses
  // the pixels where geometry happens to match the background and 8-bit rounding.
  hlod::metrics::Mask coverage();

  const GlFunctions& gl() const { return context_.gl(); }
  const RenderOptions& options() const { return options_; }

 private:
  Renderer(GlContext& context, const RenderOptions& options)
      : context_(context), options_(options) {}
  hlod::Status init();
  const ShaderProgram& program(bool textured);

  GlContext& context_;
  RenderOptions options_;
  GlObject framebuffer_, colour_, depth_;
  std::map<bool, ShaderProgram> programs_;  // by "textured"
  GlObject geometryQuery_;
};

// Writes an image; the format follows the extension (.png, .jpg/.jpeg, .exr, .tif, ...).
hlod::Status writeImage(const std::string& path, const hlod::Image& image);

}  // namespace renderer
