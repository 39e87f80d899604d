#pragma once
// The GL side of occlusion culling (hlod/runtime/OcclusionCulling.h): GL_SAMPLES_PASSED queries
// around the draws the plan wraps, and the box pass, the "hardware culling" of Manocha sec. 4.2:
// the boxes of the hidden nodes drawn inside queries against the depth of the front just drawn,
// with depth and colour writes off. Results are read at the next frame, after this one's
// glFinish, so reading them never waits (a result that is not available is reported as such).
// Also draws boxes tinted into the frame, for the debug view (the paper's Fig. 5).
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "hlod/Mesh.h"
#include "hlod/Result.h"
#include "renderer/FrameView.h"
#include "renderer/GlObject.h"
#include "renderer/ShaderProgram.h"

namespace renderer {

class OcclusionQueries {
 public:
  static hlod::Result<std::unique_ptr<OcclusionQueries>> create(const GlFunctions& gl);

  // A new frame: the previous frame's queries are forgotten (read them first).
  void beginFrame();
  // Wraps one draw: begin() before it, end() after it; the answer comes in drawSamples().
  void beginDraw();
  void endDraw();
  // The box pass: one query per batch, each box drawn as a cube (both faces: the eye may be
  // between a face and the geometry). Needs the frame's framebuffer bound with its depth.
  void queryBoxes(const FrameView& view, std::span<const std::vector<hlod::Aabb>> batches);
  // Samples that passed, in the order the draws and the batches were queried; nullopt where the
  // result is not available.
  std::vector<std::optional<std::uint64_t>> drawSamples() const;
  std::vector<std::optional<std::uint64_t>> boxSamples() const;
  // Draws boxes blended over the frame, faces at `colour`'s alpha and edges opaque, without the
  // depth test.
  void drawTinted(const FrameView& view, std::span<const hlod::Aabb> boxes, glm::vec4 colour);
  int queryObjects() const { return static_cast<int>(pool_.size()); }

 private:
  explicit OcclusionQueries(const GlFunctions& gl) : gl_(gl) {}
  GLuint nextQuery();
  void drawBox(const FrameView& view, const hlod::Aabb& box, GLenum mode, GLsizei count,
               const void* offset);
  std::vector<std::optional<std::uint64_t>> read(std::span<const GLuint> ids) const;

  const GlFunctions& gl_;
  ShaderProgram program_;
  GlObject vao_, vbo_, ibo_;
  std::vector<GlObject> pool_;  // grows to the most queries a frame has used
  std::size_t used_ = 0;
  std::vector<GLuint> drawIds_, boxIds_;
};

}  // namespace renderer
