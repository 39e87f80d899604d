#include "renderer/Renderer.h"

#include <algorithm>
#include <chrono>

#include "Shaders.h"

namespace renderer {

hlod::Result<std::unique_ptr<Renderer>> Renderer::create(GlContext& context,
                                                         const RenderOptions& options) {
  if (options.width < 1 || options.height < 1 || options.width > kMaxSize ||
      options.height > kMaxSize)
    return hlod::makeError("frame size " + std::to_string(options.width) + "x" +
                           std::to_string(options.height) + " is outside 1.." +
                           std::to_string(kMaxSize));
  std::unique_ptr<Renderer> r(new Renderer(context, options));
  auto status = r->init();
  if (!status) return status.error();
  return r;
}

hlod::Status Renderer::init() {
  const GlFunctions& g = gl();
  colour_ = GlObject::create(g, GlKind::Renderbuffer);
  g.BindRenderbuffer(GL_RENDERBUFFER, colour_.id());
  g.RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, options_.width, options_.height);
  depth_ = GlObject::create(g, GlKind::Renderbuffer);
  g.BindRenderbuffer(GL_RENDERBUFFER, depth_.id());
  // 32-bit float depth + reversed-Z: near 0.1 m and far 100 km without z-fighting.
  g.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, options_.width, options_.height);
  framebuffer_ = GlObject::create(g, GlKind::Framebuffer);
  g.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  g.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_.id());
  g.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_.id());
  const GLenum status = g.CheckFramebufferStatus(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    return hlod::makeError("framebuffer incomplete (0x" + std::to_string(status) + ") at " +
                           std::to_string(options_.width) + "x" + std::to_string(options_.height));
  if (g.GetError() != GL_NO_ERROR)
    return hlod::makeError("GL error while creating a " + std::to_string(options_.width) + "x" +
                           std::to_string(options_.height) + " framebuffer (out of memory?)");
  geometryQuery_ = GlObject::create(g, GlKind::Query);
  // Compile the variants the effects need now, so the first frame's time is not a compile.
  if (options_.effects.textures && !program(true).id())
    return hlod::makeError("textured shader failed to build");
  if (!program(false).id()) return hlod::makeError("shader failed to build");
  return hlod::Ok{};
}

const ShaderProgram& Renderer::program(bool textured) {
  textured = textured && options_.effects.textures;
  auto it = programs_.find(textured);
  if (it != programs_.end()) return it->second;
  std::string defines;
  if (textured) defines += "#define HAS_TEXTURE\n";
  if (options_.effects.lambert) defines += "#define LAMBERT\n";
  if (options_.effects.fog) defines += "#define FOG\n";
  auto built = ShaderProgram::build(gl(), defines, shaders::kMeshVertex, shaders::kMeshFragment);
  // Shader sources are ours: a failure is a programmer error, reported by init() as empty id.
  return programs_.emplace(textured, built ? std::move(*built) : ShaderProgram{}).first->second;
}

FrameTiming Renderer::drawFrame(const FrameView& view, std::span<const GpuMesh* const> meshes) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const GlFunctions& g = gl();
  FrameTiming timing;

  g.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  g.Viewport(0, 0, options_.width, options_.height);
  g.BeginQuery(GL_TIME_ELAPSED, geometryQuery_.id());
  g.ClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  g.Enable(GL_DEPTH_TEST);
  g.DepthFunc(GL_GREATER);
  g.DepthMask(GL_TRUE);
  g.Disable(GL_CULL_FACE);
  const glm::vec3 bg = options_.effects.background;
  g.ClearColor(bg.r, bg.g, bg.b, 1.0f);
  g.ClearDepth(0.0);
  g.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

  const glm::mat4 projection(view.projection);
  const glm::vec3 sun(glm::normalize(options_.sunDirection));
  const glm::vec3 up(glm::normalize(options_.up));
  double fogDensity = options_.effects.fogDensity;
  GLuint current = 0;
  bool culling = false;
  for (const GpuMesh* mesh : meshes) {
    if (!mesh) continue;
    // Back faces of one-sided meshes are culled: half the triangles never reach the rasteriser.
    if (mesh->oneSided() != culling) {
      culling = mesh->oneSided();
      if (culling) {
        g.Enable(GL_CULL_FACE);
        g.CullFace(GL_BACK);
      } else {
        g.Disable(GL_CULL_FACE);
      }
    }
    const ShaderProgram& p = program(mesh->textured());
    if (p.id() != current) {
      current = p.id();
      g.UseProgram(current);
      g.UniformMatrix4fv(p.uniform(g, "uProjection"), 1, GL_FALSE, &projection[0][0]);
      g.Uniform3fv(p.uniform(g, "uSunDir"), 1, &sun[0]);
      g.Uniform3fv(p.uniform(g, "uUp"), 1, &up[0]);
      g.Uniform3fv(p.uniform(g, "uBackground"), 1, &bg[0]);
      g.Uniform1f(p.uniform(g, "uFogDensity"), static_cast<float>(fogDensity));
      g.Uniform1i(p.uniform(g, "uTexture"), 0);
    }
    // Camera-relative in double, then float: precision stays where the camera is.
    glm::dmat4 translate(1.0);
    translate[3] = glm::dvec4(mesh->centre() - view.eye, 1.0);
    const glm::mat4 modelView(view.rotation * translate);
    g.UniformMatrix4fv(p.uniform(g, "uModelView"), 1, GL_FALSE, &modelView[0][0]);
    g.Uniform4fv(p.uniform(g, "uBaseColor"), 1, &mesh->baseColor()[0]);
    if (mesh->textured() && options_.effects.textures) {
      g.ActiveTexture(GL_TEXTURE0);
      g.BindTexture(GL_TEXTURE_2D, mesh->texture());
    }
    mesh->draw(g);
    timing.triangles += mesh->triangles();
    ++timing.drawCalls;
  }
  g.BindVertexArray(0);
  g.Disable(GL_CULL_FACE);
  g.EndQuery(GL_TIME_ELAPSED);
  g.Finish();
  timing.cpuMs = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  GLuint64 ns = 0;
  g.GetQueryObjectui64v(geometryQuery_.id(), GL_QUERY_RESULT, &ns);
  timing.passes.push_back({"geometry", static_cast<double>(ns) * 1e-6});
  for (const auto& pass : timing.passes) timing.gpuMs += pass.gpuMs;
  return timing;
}

hlod::Image Renderer::readback() {
  const GlFunctions& g = gl();
  hlod::Image img;
  img.width = options_.width;
  img.height = options_.height;
  img.pixels.resize(static_cast<std::size_t>(img.width) * img.height * 4);
  std::vector<std::uint8_t> raw(img.pixels.size());
  g.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  g.PixelStorei(GL_PACK_ALIGNMENT, 1);
  g.ReadPixels(0, 0, img.width, img.height, GL_RGBA, GL_UNSIGNED_BYTE, raw.data());
  // GL's row 0 is the bottom; images are top-down.
  const std::size_t row = static_cast<std::size_t>(img.width) * 4;
  for (int y = 0; y < img.height; ++y)
    std::copy_n(&raw[(img.height - 1 - y) * row], row, &img.pixels[y * row]);
  return img;
}

hlod::metrics::Mask Renderer::coverage() {
  const GlFunctions& g = gl();
  const int w = options_.width, h = options_.height;
  std::vector<float> depth(static_cast<std::size_t>(w) * h);
  g.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  g.PixelStorei(GL_PACK_ALIGNMENT, 4);
  g.ReadPixels(0, 0, w, h, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
  hlod::metrics::Mask mask{w, h, std::vector<std::uint8_t>(depth.size(), 0)};
  // Reversed z: the depth buffer is cleared to 0 (the far plane), any geometry is above it.
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      mask.covered[static_cast<std::size_t>(y) * w + x] =
          depth[static_cast<std::size_t>(h - 1 - y) * w + x] > 0.0f ? 1 : 0;
  return mask;
}

}  // namespace renderer
