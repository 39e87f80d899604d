#include "renderer/IdBuffer.h"

#include <algorithm>
#include <unordered_set>
#include <vector>

namespace renderer {
namespace {

constexpr const char* kIdVertex = R"(
layout(location = 0) in vec3 aPosition;
uniform mat4 uModelView;
uniform mat4 uProjection;
void main() { gl_Position = uProjection * (uModelView * vec4(aPosition, 1.0)); }
)";

constexpr const char* kIdFragment = R"(
uniform uint uMeshId;
out uvec2 id;
void main() { id = uvec2(uMeshId, uint(gl_PrimitiveID) + 1u); }
)";

}  // namespace

hlod::Result<std::unique_ptr<IdBuffer>> IdBuffer::create(const GlFunctions& gl, int width,
                                                         int height) {
  std::unique_ptr<IdBuffer> b(new IdBuffer(gl, width, height));
  auto p = ShaderProgram::build(gl, "", kIdVertex, kIdFragment);
  if (!p) return hlod::makeError("id buffer program: " + p.message());
  b->program_ = std::move(*p);
  b->ids_ = GlObject::create(gl, GlKind::Texture);
  gl.BindTexture(GL_TEXTURE_2D, b->ids_.id());
  gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RG32UI, width, height, 0, GL_RG_INTEGER, GL_UNSIGNED_INT,
                nullptr);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  gl.BindTexture(GL_TEXTURE_2D, 0);
  b->depth_ = GlObject::create(gl, GlKind::Renderbuffer);
  gl.BindRenderbuffer(GL_RENDERBUFFER, b->depth_.id());
  gl.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, width, height);
  b->framebuffer_ = GlObject::create(gl, GlKind::Framebuffer);
  gl.BindFramebuffer(GL_FRAMEBUFFER, b->framebuffer_.id());
  gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, b->ids_.id(), 0);
  gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, b->depth_.id());
  if (gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    return hlod::makeError("id buffer framebuffer incomplete");
  return b;
}

VisibleCount IdBuffer::count(const FrameView& view, std::span<const GpuMesh* const> meshes) {
  const GlFunctions& g = gl_;
  g.ClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  g.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  g.Viewport(0, 0, width_, height_);
  g.ClearColor(0.0f, 0.0f, 0.0f, 0.0f);
  g.ClearDepth(0.0);
  g.DepthMask(GL_TRUE);
  g.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  g.Enable(GL_DEPTH_TEST);
  g.DepthFunc(GL_GREATER);
  g.Disable(GL_CULL_FACE);
  g.UseProgram(program_.id());
  const glm::mat4 projection(view.projection);
  g.UniformMatrix4fv(program_.location(Uniform::Projection), 1, GL_FALSE, &projection[0][0]);
  const GLint meshId = g.GetUniformLocation(program_.id(), "uMeshId");
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    const GpuMesh* m = meshes[i];
    if (!m) continue;
    glm::dmat4 t(1.0);
    t[3] = glm::dvec4(m->centre() - view.eye, 1.0);
    const glm::mat4 modelView(view.rotation * t);
    g.UniformMatrix4fv(program_.location(Uniform::ModelView), 1, GL_FALSE, &modelView[0][0]);
    g.Uniform1ui(meshId, static_cast<GLuint>(i + 1));
    m->draw(g);
  }
  g.Finish();
  std::vector<std::uint32_t> pixels(std::size_t(width_) * height_ * 2);
  g.PixelStorei(GL_PACK_ALIGNMENT, 4);
  g.ReadPixels(0, 0, width_, height_, GL_RG_INTEGER, GL_UNSIGNED_INT, pixels.data());
  std::unordered_set<std::uint64_t> primitives;
  std::vector<std::uint8_t> shown(meshes.size() + 1, 0);
  for (std::size_t p = 0; p < pixels.size(); p += 2) {
    if (pixels[p] == 0) continue;
    primitives.insert(std::uint64_t(pixels[p]) << 32 | pixels[p + 1]);
    if (pixels[p] <= meshes.size()) shown[pixels[p]] = 1;
  }
  VisibleCount c;
  c.primitives = primitives.size();
  for (std::size_t i = 0; i < meshes.size(); ++i)
    if (shown[i + 1] && meshes[i]) {
      ++c.meshes;
      c.meshTriangles += meshes[i]->triangles();
    }
  return c;
}

}  // namespace renderer
