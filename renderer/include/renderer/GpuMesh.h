#pragma once
// A LocalMesh uploaded to GL buffers (and its texture, if any). Move-only; lives with its context.
#include <cstdint>

#include "hlod/Mesh.h"
#include "hlod/Result.h"
#include "renderer/GlObject.h"

namespace renderer {

class GpuMesh {
 public:
  // Uploads interleaved position/normal/texCoord vertices, 32-bit indices and an RGBA8 texture
  // with mipmaps. The context must be current. Returns when the GL work is done, mipmaps
  // included, so that the time spent in it is the upload's whole cost.
  static hlod::Result<GpuMesh> upload(const GlFunctions& gl, const hlod::LocalMesh& mesh);

  void draw(const GlFunctions& gl) const;

  const glm::dvec3& centre() const { return centre_; }
  const glm::vec4& baseColor() const { return baseColor_; }
  bool textured() const { return static_cast<bool>(texture_); }
  bool oneSided() const { return oneSided_; }  // back faces may be culled
  GLuint texture() const { return texture_.id(); }
  std::uint64_t triangles() const { return indexCount_ / 3; }
  std::uint64_t gpuBytes() const { return gpuBytes_; }

 private:
  GlObject vao_, vbo_, ibo_, texture_;
  glm::dvec3 centre_{0.0};
  glm::vec4 baseColor_{1.0f};
  bool oneSided_ = false;
  std::uint64_t indexCount_ = 0;
  std::uint64_t gpuBytes_ = 0;
};

}  // namespace renderer
