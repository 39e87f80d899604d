#pragma once
// A LocalMesh uploaded to GL buffers (and its texture, if any). Move-only; lives with its context.
#include <cstdint>
#include <memory>

#include "hlod/Mesh.h"
#include "hlod/Result.h"
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
  // with mipmaps (or takes `texture`, the GPU copy of mesh.texture uploaded before). The context
  // must be current. Returns when the GL work is done, mipmaps included, so that the time spent
  // in it is the upload's whole cost.
  static hlod::Result<GpuMesh> upload(const GlFunctions& gl, const hlod::LocalMesh& mesh,
                                      std::shared_ptr<const GpuTexture> texture = nullptr);

  void draw(const GlFunctions& gl) const;

  const glm::dvec3& centre() const { return centre_; }
  const glm::vec4& baseColor() const { return baseColor_; }
  bool textured() const { return static_cast<bool>(texture_); }
  bool oneSided() const { return oneSided_; }  // back faces may be culled
  GLuint texture() const { return texture_ ? texture_->object.id() : 0; }
  const std::shared_ptr<const GpuTexture>& gpuTexture() const { return texture_; }
  std::uint64_t triangles() const { return indexCount_ / 3; }
  std::uint64_t gpuBytes() const { return gpuBytes_; }  // buffers only (textures: gpuTexture)

 private:
  GlObject vao_, vbo_, ibo_;
  std::shared_ptr<const GpuTexture> texture_;
  glm::dvec3 centre_{0.0};
  glm::vec4 baseColor_{1.0f};
  bool oneSided_ = false;
  std::uint64_t indexCount_ = 0;
  std::uint64_t gpuBytes_ = 0;
};

}  // namespace renderer
