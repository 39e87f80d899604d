#pragma once
// A LocalMesh uploaded to GL buffers (and its texture, if any). Move-only; lives with its context.
#include <cstdint>
#include <memory>

#include "hlod/Mesh.h"
#include "hlod/Result.h"
#include "hlod/runtime/Selector.h"
#include "renderer/GlObject.h"

namespace renderer {

// A texture on the GPU, shared by the meshes drawn with it (nodes of one level may share one).
struct GpuTexture {
  GlObject object;
  std::uint64_t gpuBytes = 0;  // its levels, mipmaps included
};

class GpuMesh {
 public:
  // Uploads interleaved position/normal/texCoord vertices, 32-bit indices and an RGBA8 texture
  // with mipmaps (or takes `texture`, the GPU copy of mesh.texture uploaded before, which then
  // stands in for mesh.texture: a mesh sharing it may be loaded without its own). The context
  // must be current. Returns when the GL work is done, mipmaps included, so that the time spent
  // in it is the upload's whole cost.
  static hlod::Result<GpuMesh> upload(const GlFunctions& gl, const hlod::LocalMesh& mesh,
                                      std::shared_ptr<const GpuTexture> texture = nullptr);
  // The same for a payload the caller shares: a progressive one is kept for setDraw.
  static hlod::Result<GpuMesh> upload(const GlFunctions& gl,
                                      std::shared_ptr<const hlod::LocalMesh> mesh,
                                      std::shared_ptr<const GpuTexture> texture = nullptr);

  void draw(const GlFunctions& gl) const;

  // What draw() draws from now on: the mesh whole, fewer triangles from its progression
  // (rebuilding the index buffer when the count changes), or its splats (as points of their
  // sphere's size: the SPLATS variant). A count outside [coarsest, whole] is clamped; a mesh
  // without splats draws nothing as splats.
  void setDraw(const GlFunctions& gl, const hlod::NodeDraw& draw);
  bool drawsSplats() const { return drawSplats_; }
  std::uint64_t splats() const { return drawSplats_ ? splatCount_ : 0; }

  const glm::dvec3& centre() const { return centre_; }
  const glm::vec4& baseColor() const { return baseColor_; }
  bool textured() const { return static_cast<bool>(texture_); }
  bool oneSided() const { return oneSided_; }  // back faces may be culled
  GLuint texture() const { return texture_ ? texture_->object.id() : 0; }
  const std::shared_ptr<const GpuTexture>& gpuTexture() const { return texture_; }
  std::uint64_t triangles() const { return drawSplats_ ? 0 : indexCount_ / 3; }
  std::uint64_t gpuBytes() const { return gpuBytes_; }  // buffers only (textures: gpuTexture)

 private:
  GlObject vao_, vbo_, ibo_;
  GlObject splatVao_, splatVbo_;  // points: position, normal, texCoord, radius
  std::uint64_t splatCount_ = 0;
  bool drawSplats_ = false;
  // The payload's indices and progression, kept to draw fewer triangles (progressive meshes only).
  std::shared_ptr<const hlod::LocalMesh> progressive_;
  std::uint64_t fullIndexCount_ = 0;
  std::shared_ptr<const GpuTexture> texture_;
  glm::dvec3 centre_{0.0};
  glm::vec4 baseColor_{1.0f};
  bool oneSided_ = false;
  std::uint64_t indexCount_ = 0;
  std::uint64_t gpuBytes_ = 0;
};

}  // namespace renderer
