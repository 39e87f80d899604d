#pragma once
// What of a front is really seen: its meshes drawn into an integer target with each pixel
// holding (mesh, primitive) ids, then counted. The primitives actually visible, for the culling
// efficiency of Manocha sec. 6.2 (primitives in the potentially visible set over primitives
// visible), and the triangles of the nodes that show at least one pixel. A measurement: not
// part of any frame's time.
#include <cstdint>
#include <memory>
#include <span>

#include "hlod/Result.h"
#include "renderer/FrameView.h"
#include "renderer/GlObject.h"
#include "renderer/GpuMesh.h"
#include "renderer/ShaderProgram.h"

namespace renderer {

struct VisibleCount {
  std::uint64_t primitives = 0;     // distinct (mesh, primitive) pairs on some pixel
  std::uint32_t meshes = 0;         // meshes with at least one pixel
  std::uint64_t meshTriangles = 0;  // the drawn triangles of those meshes
};

class IdBuffer {
 public:
  static hlod::Result<std::unique_ptr<IdBuffer>> create(const GlFunctions& gl, int width,
                                                        int height);
  // Draws the meshes (as they are set to draw) from the view and counts what shows.
  VisibleCount count(const FrameView& view, std::span<const GpuMesh* const> meshes);

 private:
  IdBuffer(const GlFunctions& gl, int width, int height)
      : gl_(gl), width_(width), height_(height) {}
  const GlFunctions& gl_;
  int width_, height_;
  ShaderProgram program_;
  GlObject framebuffer_, ids_, depth_;
};

}  // namespace renderer
