#include "renderer/Renderer.h"

#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>

#include "Shaders.h"

namespace renderer {

const char* passName(Pass pass) {
  switch (pass) {
    case Pass::Shadow:
      return "shadow";
    case Pass::Geometry:
      return "geometry";
    case Pass::Sky:
      return "sky";
    case Pass::Ssao:
      return "ssao";
    case Pass::SsaoBlur:
      return "ssao-blur";
    case Pass::Composite:
      return "composite";
    case Pass::Outline:
      return "outline";
  }
  return "?";
}

std::vector<Pass> passesFor(const Effects& e) {
  std::vector<Pass> passes;
  if (e.shadows && e.sun && e.lit()) passes.push_back(Pass::Shadow);
  passes.push_back(Pass::Geometry);
  if (e.background.sky) passes.push_back(Pass::Sky);
  if (e.ssao) {
    passes.push_back(Pass::Ssao);
    passes.push_back(Pass::SsaoBlur);
    passes.push_back(Pass::Composite);
  }
  if (e.outline) passes.push_back(Pass::Outline);
  return passes;
}

namespace {

// A texture of one level with nearest sampling, clamped: the render targets' storage.
GlObject targetTexture(const GlFunctions& g, GLenum internal, GLenum format, GLenum type, int w,
                       int h) {
  GlObject t = GlObject::create(g, GlKind::Texture);
  g.BindTexture(GL_TEXTURE_2D, t.id());
  g.TexImage2D(GL_TEXTURE_2D, 0, static_cast<GLint>(internal), w, h, 0, format, type, nullptr);
  g.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  g.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  g.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  g.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  g.BindTexture(GL_TEXTURE_2D, 0);
  return t;
}

hlod::Status complete(const GlFunctions& g, const char* what) {
  const GLenum status = g.CheckFramebufferStatus(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    return hlod::makeError(std::string(what) + " framebuffer incomplete (0x" +
                           std::to_string(status) + ")");
  return hlod::Ok{};
}

// Orthographic projection for clip depth [0, 1] (glClipControl ZERO_TO_ONE), standard depth.
glm::dmat4 orthoZeroToOne(double halfWidth, double zNear, double zFar) {
  glm::dmat4 p(1.0);
  p[0][0] = 1.0 / halfWidth;
  p[1][1] = 1.0 / halfWidth;
  p[2][2] = -1.0 / (zFar - zNear);
  p[3][2] = -zNear / (zFar - zNear);
  return p;
}

glm::dmat4 lookAt(const glm::dvec3& eye, const glm::dvec3& target, glm::dvec3 up) {
  const glm::dvec3 f = glm::normalize(target - eye);
  if (glm::length(glm::cross(f, up)) < 1e-6)
    up = std::abs(f.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 1, 0);
  const glm::dvec3 s = glm::normalize(glm::cross(f, up));
  const glm::dvec3 u = glm::cross(s, f);
  glm::dmat4 m(1.0);
  m[0][0] = s.x, m[1][0] = s.y, m[2][0] = s.z;
  m[0][1] = u.x, m[1][1] = u.y, m[2][1] = u.z;
  m[0][2] = -f.x, m[1][2] = -f.y, m[2][2] = -f.z;
  m[3][0] = -glm::dot(s, eye), m[3][1] = -glm::dot(u, eye), m[3][2] = glm::dot(f, eye);
  return m;
}

glm::dmat4 translation(const glm::dvec3& t) {
  glm::dmat4 m(1.0);
  m[3] = glm::dvec4(t, 1.0);
  return m;
}

}  // namespace

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

bool Renderer::has(Pass pass) const {
  return std::find(passes_.begin(), passes_.end(), pass) != passes_.end();
}

hlod::Status Renderer::init() {
  const GlFunctions& g = gl();
  const int w = options_.width, h = options_.height;
  // A post pass (SSAO, outline) reads the depth: then it is a texture, otherwise a renderbuffer.
  const bool depthRead = has(Pass::Ssao) || has(Pass::Outline);
  colour_ = GlObject::create(g, GlKind::Renderbuffer);
  g.BindRenderbuffer(GL_RENDERBUFFER, colour_.id());
  g.RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
  framebuffer_ = GlObject::create(g, GlKind::Framebuffer);
  g.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  g.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_.id());
  // 32-bit float depth + reversed-Z: near 0.1 m and far 100 km without z-fighting.
  if (depthRead) {
    depthTexture_ = targetTexture(g, GL_DEPTH_COMPONENT32F, GL_DEPTH_COMPONENT, GL_FLOAT, w, h);
    g.FramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, depthTexture_.id(),
                           0);
  } else {
    depth_ = GlObject::create(g, GlKind::Renderbuffer);
    g.BindRenderbuffer(GL_RENDERBUFFER, depth_.id());
    g.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, w, h);
    g.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_.id());
  }
  const GLenum status = g.CheckFramebufferStatus(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    return hlod::makeError("framebuffer incomplete (0x" + std::to_string(status) + ") at " +
                           std::to_string(w) + "x" + std::to_string(h));
  if (g.GetError() != GL_NO_ERROR)
    return hlod::makeError("GL error while creating a " + std::to_string(w) + "x" +
                           std::to_string(h) + " framebuffer (out of memory?)");
  for (std::size_t i = 0; i < passes_.size(); ++i)
    queries_.push_back(GlObject::create(g, GlKind::Query));
  if (has(Pass::Shadow))
    if (auto st = initShadows(); !st) return st;
  if (depthRead || has(Pass::Sky))
    if (auto st = initPostTargets(); !st) return st;
  g.BindFramebuffer(GL_FRAMEBUFFER, 0);

  // Compile the variants the effects need now, so the first frame's time is not a compile.
  std::vector<VariantKey> keys = {meshVariant(options_.effects, false)};
  if (options_.effects.textures) keys.push_back(meshVariant(options_.effects, true));
  if (has(Pass::Shadow)) keys.push_back({ProgramKind::ShadowDepth, 0});
  if (has(Pass::Sky))
    keys.push_back({ProgramKind::Sky, options_.effects.sun ? variant::kSunDisc : 0});
  if (has(Pass::Ssao)) keys.push_back({ProgramKind::Ssao, 0});
  if (has(Pass::SsaoBlur)) keys.push_back({ProgramKind::SsaoBlur, 0});
  if (has(Pass::Composite)) keys.push_back({ProgramKind::Composite, 0});
  if (has(Pass::Outline)) keys.push_back({ProgramKind::Outline, 0});
  for (const VariantKey& k : keys)
    if (!program(k))
      return hlod::makeError("shader variant 0x" + std::to_string(k.packed()) + " failed to build");
  return hlod::Ok{};
}

hlod::Status Renderer::initShadows() {
  const GlFunctions& g = gl();
  const int res = options_.effects.shadows->resolution;
  shadowTexture_ = targetTexture(g, GL_DEPTH_COMPONENT32F, GL_DEPTH_COMPONENT, GL_FLOAT, res, res);
  g.BindTexture(GL_TEXTURE_2D, shadowTexture_.id());
  // Hardware depth comparison, bilinear: sampler2DShadow gives filtered visibility.
  g.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  g.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  g.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  g.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
  g.BindTexture(GL_TEXTURE_2D, 0);
  shadowFramebuffer_ = GlObject::create(g, GlKind::Framebuffer);
  g.BindFramebuffer(GL_FRAMEBUFFER, shadowFramebuffer_.id());
  g.FramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, shadowTexture_.id(),
                         0);
  const GLenum none = GL_NONE;
  g.DrawBuffers(1, &none);
  g.ReadBuffer(GL_NONE);
  return complete(g, "shadow map");
}

hlod::Status Renderer::initPostTargets() {
  const GlFunctions& g = gl();
  const int w = options_.width, h = options_.height;
  fullscreenVao_ = GlObject::create(g, GlKind::VertexArray);  // core profile: a VAO to draw
  if (!has(Pass::Ssao) && !has(Pass::Outline)) return hlod::Ok{};
  postFramebuffer_ = GlObject::create(g, GlKind::Framebuffer);
  g.BindFramebuffer(GL_FRAMEBUFFER, postFramebuffer_.id());
  g.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_.id());
  if (auto st = complete(g, "post"); !st) return st;
  if (!has(Pass::Ssao)) return hlod::Ok{};
  aoTexture_ = targetTexture(g, GL_R8, GL_RED, GL_UNSIGNED_BYTE, w, h);
  aoFramebuffer_ = GlObject::create(g, GlKind::Framebuffer);
  g.BindFramebuffer(GL_FRAMEBUFFER, aoFramebuffer_.id());
  g.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, aoTexture_.id(), 0);
  if (auto st = complete(g, "ssao"); !st) return st;
  blurTexture_ = targetTexture(g, GL_R8, GL_RED, GL_UNSIGNED_BYTE, w, h);
  // The blurred occlusion is read at the same pixel centres: bilinear costs nothing there.
  blurFramebuffer_ = GlObject::create(g, GlKind::Framebuffer);
  g.BindFramebuffer(GL_FRAMEBUFFER, blurFramebuffer_.id());
  g.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, blurTexture_.id(), 0);
  return complete(g, "ssao blur");
}

std::uint64_t Renderer::targetBytes(const RenderOptions& options) {
  const auto pixels =
      std::uint64_t(std::max(0, options.width)) * std::uint64_t(std::max(0, options.height));
  const std::vector<Pass> passes = passesFor(options.effects);
  const auto has = [&](Pass p) {
    return std::find(passes.begin(), passes.end(), p) != passes.end();
  };
  std::uint64_t bytes = pixels * (4 + 4);          // RGBA8 colour, 32-bit float depth
  if (has(Pass::Ssao)) bytes += pixels * (1 + 1);  // R8 occlusion and its blur
  if (has(Pass::Shadow)) {
    const auto res = std::uint64_t(std::max(0, options.effects.shadows->resolution));
    bytes += res * res * 4;  // 32-bit float shadow map
  }
  return bytes;
}

ResourceCounts Renderer::resources() const {
  ResourceCounts c;
  for (const GlObject* o :
       {&framebuffer_, &shadowFramebuffer_, &aoFramebuffer_, &blurFramebuffer_, &postFramebuffer_})
    c.framebuffers += static_cast<bool>(*o);
  for (const GlObject* o : {&colour_, &depth_}) c.renderbuffers += static_cast<bool>(*o);
  for (const GlObject* o : {&depthTexture_, &shadowTexture_, &aoTexture_, &blurTexture_})
    c.textures += static_cast<bool>(*o);
  for (const auto& [key, p] : programs_) c.programs += p.id() != 0;
  for (const GlObject& q : queries_) c.queries += static_cast<bool>(q);
  if (occlusion_) c.queries += occlusion_->queryObjects() + 1;  // made only by culling
  c.vertexArrays += static_cast<bool>(fullscreenVao_);
  return c;
}

const ShaderProgram* Renderer::program(const VariantKey& key) {
  auto it = programs_.find(key);
  if (it != programs_.end()) return it->second.id() ? &it->second : nullptr;
  const std::string view = shaders::kViewPosition;
  std::string vs = shaders::kFullscreenVertex, fs;
  switch (key.kind) {
    case ProgramKind::Mesh:
      vs = shaders::kMeshVertex, fs = shaders::kMeshFragment;
      break;
    case ProgramKind::ShadowDepth:
      vs = shaders::kShadowVertex, fs = shaders::kShadowFragment;
      break;
    case ProgramKind::Sky:
      fs = shaders::kSkyFragment;
      break;
    case ProgramKind::Ssao:
      fs = view + shaders::kSsaoFragment;
      break;
    case ProgramKind::SsaoBlur:
      fs = shaders::kBlurFragment;
      break;
    case ProgramKind::Composite:
      fs = shaders::kCompositeFragment;
      break;
    case ProgramKind::Outline:
      fs = view + shaders::kOutlineFragment;
      break;
  }
  ++compiles_;
  auto built = ShaderProgram::build(gl(), definesFor(key), vs, fs);
  // Shader sources are ours: a failure is a programmer error, reported by init() as nullptr.
  auto& p = programs_.emplace(key, built ? std::move(*built) : ShaderProgram{}).first->second;
  return p.id() ? &p : nullptr;
}

FrameTiming Renderer::drawFrame(const FrameView& view, std::span<const GpuMesh* const> meshes,
                                const OcclusionDraw* occlusion) {
  const auto start = std::chrono::steady_clock::now();
  const GlFunctions& g = gl();
  FrameTiming timing;
  timing.gpuTimed = context_.info().gpuTimers;
  g.ClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  queriedMeshes_.clear();
  occlusionPass_ = false;
  prepareOcclusion(occlusion);
  if (!occlusion_) occlusion = nullptr;

  if (has(Pass::Shadow)) fitShadow(view, meshes);
  for (std::size_t i = 0; i < passes_.size(); ++i) {
    g.BeginQuery(GL_TIME_ELAPSED, queries_[i].id());
    runPass(passes_[i], view, meshes, timing, occlusion);
    g.EndQuery(GL_TIME_ELAPSED);
    // The hidden nodes' boxes, against the depth of the whole front (Manocha sec. 4.2's HC),
    // before any pass that changes the framebuffer further.
    if (passes_[i] == Pass::Geometry && occlusion && !occlusion->boxBatches.empty()) {
      g.BeginQuery(GL_TIME_ELAPSED, occlusionTimer_.id());
      occlusion_->queryBoxes(view, occlusion->boxBatches);
      g.EndQuery(GL_TIME_ELAPSED);
      occlusionPass_ = true;
    }
  }
  if (occlusion && !occlusion->tint.empty()) {
    g.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
    g.Viewport(0, 0, options_.width, options_.height);
    occlusion_->drawTinted(view, occlusion->tint, glm::vec4(1.0f, 0.85f, 0.1f, 0.3f));
  }
  finishFrame(start, timing);
  return timing;
}

FrameTiming Renderer::drawFrameInParts(const FrameView& view, std::size_t parts,
                                       const FramePart& part) {
  assert((!has(Pass::Shadow) || view.sceneRadius > 0.0) && "the shadow fit needs the scene");
  const auto start = std::chrono::steady_clock::now();
  const GlFunctions& g = gl();
  FrameTiming timing;
  timing.gpuTimed = context_.info().gpuTimers;
  g.ClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  queriedMeshes_.clear();
  occlusionPass_ = false;
  if (has(Pass::Shadow)) fitShadow(view, {});
  for (std::size_t i = 0; i < passes_.size(); ++i) {
    g.BeginQuery(GL_TIME_ELAPSED, queries_[i].id());
    const Pass pass = passes_[i];
    if (pass == Pass::Shadow || pass == Pass::Geometry) {
      // Every part into the same targets, cleared before the first (or once without parts).
      for (std::size_t k = 0; k < std::max<std::size_t>(parts, 1); ++k) {
        const std::vector<const GpuMesh*> meshes =
            parts > 0 ? part(k) : std::vector<const GpuMesh*>{};
        if (pass == Pass::Shadow) {
          shadowPass(meshes, {}, k == 0);
        } else {
          if (k == 0) clearGeometry();
          drawMeshes(view, meshes, timing, {}, 0);
        }
      }
    } else {
      runPass(pass, view, {}, timing, nullptr);
    }
    g.EndQuery(GL_TIME_ELAPSED);
  }
  finishFrame(start, timing);
  return timing;
}

void Renderer::fitShadow(const FrameView& view, std::span<const GpuMesh* const> meshes) {
  // The sun's orthographic view, fitted to the sphere that holds what is drawn (the front),
  // relative to its centre: the matrices stay small far from the origin.
  glm::dvec3 centre = view.sceneCentre;
  double radius = view.sceneRadius;
  if (!(radius > 0.0)) {
    centre = glm::dvec3(0.0);
    std::size_t n = 0;
    for (const GpuMesh* m : meshes)
      if (m) centre += m->centre(), ++n;
    if (n) centre /= static_cast<double>(n);
    for (const GpuMesh* m : meshes)
      if (m) radius = std::max(radius, glm::length(m->centre() - centre));
    radius = std::max(radius * 1.2, 1.0);
  }
  const glm::dvec3 sun = glm::normalize(options_.effects.sun->direction);
  shadowCentre_ = centre;
  shadowViewProjection_ =
      orthoZeroToOne(radius, radius, 3.0 * radius) * lookAt(sun * 2.0 * radius, {}, options_.up);
}

void Renderer::finishFrame(std::chrono::steady_clock::time_point start, FrameTiming& timing,
                           const std::vector<std::size_t>* timed) {
  const GlFunctions& g = gl();
  g.BindVertexArray(0);
  g.Disable(GL_CULL_FACE);
  g.Disable(GL_BLEND);
  g.Finish();
  timing.cpuMs +=
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  auto read = [&](const GlObject& query, const char* name) {
    GLuint64 ns = 0;
    g.GetQueryObjectui64v(query.id(), GL_QUERY_RESULT, &ns);
    timing.passes.push_back({name, static_cast<double>(ns) * 1e-6});
    timing.gpuMs += timing.passes.back().gpuMs;
  };
  for (std::size_t i = 0; i < passes_.size(); ++i)
    if (!timed || std::find(timed->begin(), timed->end(), i) != timed->end())
      read(queries_[i], passName(passes_[i]));
  if (occlusionPass_) read(occlusionTimer_, "occlusion");
}

void Renderer::beginParts(const FrameView& view, const OcclusionDraw* occlusion) {
  assert(canDrawInParts());
  const GlFunctions& g = gl();
  g.ClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  queriedMeshes_.clear();
  occlusionPass_ = false;
  prepareOcclusion(occlusion);
  parts_ = FrameTiming{};
  partsMeshes_ = 0;
  partsOcclusion_ = occlusion_ && occlusion ? *occlusion : OcclusionDraw{};
  partsHaveOcclusion_ = occlusion_ && occlusion;
  (void)view;
  const auto start = std::chrono::steady_clock::now();
  clearGeometry();
  g.Finish();
  parts_.cpuMs +=
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

double Renderer::drawPart(const FrameView& view, std::span<const GpuMesh* const> meshes,
                          std::span<const std::uint8_t> queryMesh) {
  const auto start = std::chrono::steady_clock::now();
  drawMeshes(view, meshes, parts_, queryMesh, partsMeshes_);
  partsMeshes_ += meshes.size();
  gl().Finish();
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  parts_.cpuMs += ms;
  geometryPartsMs_ += ms;
  return ms;
}

FrameTiming Renderer::endParts(const FrameView& view) {
  const auto start = std::chrono::steady_clock::now();
  const GlFunctions& g = gl();
  FrameTiming timing = parts_;
  // The geometry's parts were timed through their glFinish (a timer query around them would
  // count the waits for the loader between them).
  timing.passes.push_back({passName(Pass::Geometry), geometryPartsMs_});
  timing.gpuMs += geometryPartsMs_;
  geometryPartsMs_ = 0.0;
  const OcclusionDraw* occlusion = partsHaveOcclusion_ ? &partsOcclusion_ : nullptr;
  if (occlusion && !occlusion->boxBatches.empty()) {
    g.BeginQuery(GL_TIME_ELAPSED, occlusionTimer_.id());
    occlusion_->queryBoxes(view, occlusion->boxBatches);
    g.EndQuery(GL_TIME_ELAPSED);
    occlusionPass_ = true;
  }
  std::vector<std::size_t> after;
  for (std::size_t i = 0; i < passes_.size(); ++i) {
    if (passes_[i] == Pass::Geometry || passes_[i] == Pass::Shadow) continue;
    g.BeginQuery(GL_TIME_ELAPSED, queries_[i].id());
    runPass(passes_[i], view, {}, timing, nullptr);
    g.EndQuery(GL_TIME_ELAPSED);
    after.push_back(i);
  }
  if (occlusion && !occlusion->tint.empty()) {
    g.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
    g.Viewport(0, 0, options_.width, options_.height);
    occlusion_->drawTinted(view, occlusion->tint, glm::vec4(1.0f, 0.85f, 0.1f, 0.3f));
  }
  finishFrame(start, timing, &after);
  partsOcclusion_ = {};
  partsHaveOcclusion_ = false;
  return timing;
}

void Renderer::prepareOcclusion(const OcclusionDraw* occlusion) {
  if (occlusion && !occlusion_) {
    auto q = OcclusionQueries::create(gl());
    // The program is ours: a failure is a programmer error. The frame is drawn without queries.
    assert(q && "occlusion box program");
    if (q) occlusion_ = std::move(*q);
    occlusionTimer_ = GlObject::create(gl(), GlKind::Query);
  }
  if (occlusion && occlusion_) occlusion_->beginFrame();
}

std::vector<std::optional<std::uint64_t>> Renderer::queryBoxesOnLastFrame(
    const FrameView& view, std::span<const std::vector<hlod::Aabb>> batches) {
  const OcclusionDraw queries;
  prepareOcclusion(&queries);
  if (!occlusion_) return std::vector<std::optional<std::uint64_t>>(batches.size());
  const GlFunctions& g = gl();
  g.ClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  g.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  g.Viewport(0, 0, options_.width, options_.height);
  occlusion_->queryBoxes(view, batches);
  g.Finish();
  return occlusion_->boxSamples();
}

Renderer::OcclusionAnswers Renderer::occlusionAnswers() const {
  OcclusionAnswers a;
  if (!occlusion_) return a;
  a.queriedMeshes = queriedMeshes_;
  a.meshSamples = occlusion_->drawSamples();
  if (occlusionPass_) a.boxSamples = occlusion_->boxSamples();
  return a;
}

void Renderer::runPass(Pass pass, const FrameView& view, std::span<const GpuMesh* const> meshes,
                       FrameTiming& timing, const OcclusionDraw* occlusion) {
  switch (pass) {
    case Pass::Shadow:
      shadowPass(meshes, occlusion ? occlusion->shadowCasters : std::span<const GpuMesh* const>{});
      break;
    case Pass::Geometry:
      geometryPass(view, meshes, timing,
                   occlusion ? occlusion->queryMesh : std::span<const std::uint8_t>{});
      break;
    case Pass::Sky:
      skyPass(view);
      break;
    case Pass::Ssao:
      fullscreenPass(ProgramKind::Ssao, aoFramebuffer_.id(), depthTexture_.id(), view);
      break;
    case Pass::SsaoBlur:
      fullscreenPass(ProgramKind::SsaoBlur, blurFramebuffer_.id(), aoTexture_.id(), view);
      break;
    case Pass::Composite:
      fullscreenPass(ProgramKind::Composite, postFramebuffer_.id(), blurTexture_.id(), view);
      break;
    case Pass::Outline:
      fullscreenPass(ProgramKind::Outline, postFramebuffer_.id(), depthTexture_.id(), view);
      break;
  }
}

void Renderer::shadowPass(std::span<const GpuMesh* const> meshes,
                          std::span<const GpuMesh* const> moreCasters, bool clear) {
  const GlFunctions& g = gl();
  const int res = options_.effects.shadows->resolution;
  g.BindFramebuffer(GL_FRAMEBUFFER, shadowFramebuffer_.id());
  g.Viewport(0, 0, res, res);
  g.Enable(GL_DEPTH_TEST);
  g.DepthFunc(GL_LESS);
  g.DepthMask(GL_TRUE);
  g.Disable(GL_CULL_FACE);
  if (clear) {
    g.ClearDepth(1.0);
    g.Clear(GL_DEPTH_BUFFER_BIT);
  }
  const ShaderProgram* p = program({ProgramKind::ShadowDepth, 0});
  assert(p && "compiled in init()");
  g.UseProgram(p->id());
  for (auto list : {meshes, moreCasters})
    for (const GpuMesh* mesh : list) {
      if (!mesh) continue;
      const glm::mat4 m(shadowViewProjection_ * translation(mesh->centre() - shadowCentre_));
      g.UniformMatrix4fv(p->location(Uniform::ShadowModel), 1, GL_FALSE, &m[0][0]);
      mesh->draw(g);
    }
}

void Renderer::geometryPass(const FrameView& view, std::span<const GpuMesh* const> meshes,
                            FrameTiming& timing, std::span<const std::uint8_t> queryMesh) {
  clearGeometry();
  drawMeshes(view, meshes, timing, queryMesh, 0);
}

void Renderer::clearGeometry() {
  const GlFunctions& g = gl();
  g.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  g.Viewport(0, 0, options_.width, options_.height);
  const glm::vec3 bg = options_.effects.background.colour;
  g.ClearColor(bg.r, bg.g, bg.b, 1.0f);
  g.ClearDepth(0.0);
  g.DepthMask(GL_TRUE);
  g.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

void Renderer::drawMeshes(const FrameView& view, std::span<const GpuMesh* const> meshes,
                          FrameTiming& timing, std::span<const std::uint8_t> queryMesh,
                          std::size_t firstIndex) {
  assert(queryMesh.empty() || queryMesh.size() == meshes.size());
  const GlFunctions& g = gl();
  const Effects& e = options_.effects;
  const glm::vec3 bg = e.background.colour;
  g.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  g.Viewport(0, 0, options_.width, options_.height);
  g.Enable(GL_DEPTH_TEST);
  g.DepthFunc(GL_GREATER);
  g.DepthMask(GL_TRUE);
  g.Disable(GL_CULL_FACE);

  const glm::mat4 projection(view.projection);
  const glm::vec3 up(glm::normalize(options_.up));
  const glm::vec3 sun = e.sun ? glm::vec3(glm::normalize(e.sun->direction)) : glm::vec3(0.0f);
  const glm::vec3 sunColour = e.sun ? e.sun->colour * e.sun->intensity : glm::vec3(0.0f);
  const float fogDensity =
      e.fog ? static_cast<float>(hlod::fogDensityFor(*e.fog, view.farDistance)) : 0.0f;
  if (has(Pass::Shadow)) {
    g.ActiveTexture(GL_TEXTURE1);
    g.BindTexture(GL_TEXTURE_2D, shadowTexture_.id());
    g.ActiveTexture(GL_TEXTURE0);
  }
  const float shadowTexel = e.shadows ? 1.0f / static_cast<float>(e.shadows->resolution) : 0.0f;
  const ShaderProgram* current = nullptr;
  bool culling = false;
  // Splats: gl_PointSize from the shader, a radius at w = 1 times this is the diameter in pixels.
  const float pointScale = projection[1][1] * float(options_.height);
  g.Enable(GL_PROGRAM_POINT_SIZE);
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    const GpuMesh* mesh = meshes[i];
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
    const ShaderProgram* p = program(meshVariant(e, mesh->textured(), mesh->drawsSplats()));
    if (!p) continue;  // compiled in init(), or the splats' variant, which failed to build
    if (p != current) {
      // Per-program uniforms, once per switch; a location of -1 (not in this variant) is a no-op.
      current = p;
      g.UseProgram(p->id());
      g.UniformMatrix4fv(p->location(Uniform::Projection), 1, GL_FALSE, &projection[0][0]);
      g.Uniform3fv(p->location(Uniform::Up), 1, &up[0]);
      g.Uniform3fv(p->location(Uniform::SunDir), 1, &sun[0]);
      g.Uniform3fv(p->location(Uniform::SunColour), 1, &sunColour[0]);
      g.Uniform1f(p->location(Uniform::FogDensity), fogDensity);
      g.Uniform3fv(p->location(Uniform::FogColour), 1, &bg[0]);
      g.Uniform1i(p->location(Uniform::Texture), 0);
      g.Uniform1i(p->location(Uniform::ShadowMap), 1);
      g.Uniform1f(p->location(Uniform::ShadowTexel), shadowTexel);
      g.Uniform1f(p->location(Uniform::ShadowBias), 1.5f * shadowTexel);
      g.Uniform1f(p->location(Uniform::PointScale), pointScale);
    }
    // Camera-relative in double, then float: precision stays where the camera is.
    const glm::dvec3 offset = mesh->centre() - view.eye;
    const glm::mat4 modelView(view.rotation * translation(offset));
    const glm::vec3 offsetF(offset);
    g.UniformMatrix4fv(p->location(Uniform::ModelView), 1, GL_FALSE, &modelView[0][0]);
    g.Uniform3fv(p->location(Uniform::Offset), 1, &offsetF[0]);
    g.Uniform4fv(p->location(Uniform::BaseColor), 1, &mesh->baseColor()[0]);
    if (p->location(Uniform::ShadowModel) >= 0) {
      const glm::mat4 m(shadowViewProjection_ * translation(mesh->centre() - shadowCentre_));
      g.UniformMatrix4fv(p->location(Uniform::ShadowModel), 1, GL_FALSE, &m[0][0]);
    }
    if (mesh->textured() && e.textures) g.BindTexture(GL_TEXTURE_2D, mesh->texture());
    // A visible node due for a re-test is queried with its own draw: it is drawn anyway.
    const bool query = !queryMesh.empty() && queryMesh[i] && occlusion_;
    if (query) {
      queriedMeshes_.push_back(firstIndex + i);
      occlusion_->beginDraw();
    }
    mesh->draw(g);
    if (query) occlusion_->endDraw();
    timing.triangles += mesh->triangles();
    ++timing.drawCalls;
  }
  g.Disable(GL_CULL_FACE);
  g.Disable(GL_PROGRAM_POINT_SIZE);
}

void Renderer::skyPass(const FrameView& view) {
  const GlFunctions& g = gl();
  const Effects& e = options_.effects;
  // Only where nothing was drawn: the depth is still the clear value 0 (far, reversed-Z).
  g.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  g.Enable(GL_DEPTH_TEST);
  g.DepthFunc(GL_GEQUAL);
  g.DepthMask(GL_FALSE);
  const ShaderProgram* p = program({ProgramKind::Sky, e.sun ? variant::kSunDisc : 0});
  assert(p && "compiled in init()");
  g.UseProgram(p->id());
  const glm::mat4 inv(glm::inverse(view.projection * view.rotation));
  const glm::vec3 up(glm::normalize(options_.up));
  g.UniformMatrix4fv(p->location(Uniform::InvViewProj), 1, GL_FALSE, &inv[0][0]);
  g.Uniform3fv(p->location(Uniform::Up), 1, &up[0]);
  g.Uniform3fv(p->location(Uniform::Horizon), 1, &e.background.colour[0]);
  g.Uniform3fv(p->location(Uniform::Zenith), 1, &e.background.zenith[0]);
  g.Uniform3fv(p->location(Uniform::Ground), 1, &e.background.ground[0]);
  if (e.sun) {
    const glm::vec3 sun(glm::normalize(e.sun->direction));
    const glm::vec3 colour = e.sun->colour * e.sun->intensity;
    g.Uniform3fv(p->location(Uniform::SunDir), 1, &sun[0]);
    g.Uniform3fv(p->location(Uniform::SunColour), 1, &colour[0]);
  }
  g.BindVertexArray(fullscreenVao_.id());
  g.DrawArrays(GL_TRIANGLES, 0, 3);
  g.DepthMask(GL_TRUE);
}

void Renderer::fullscreenPass(ProgramKind kind, GLuint target, GLuint input,
                              const FrameView& view) {
  const GlFunctions& g = gl();
  const Effects& e = options_.effects;
  g.BindFramebuffer(GL_FRAMEBUFFER, target);
  g.Viewport(0, 0, options_.width, options_.height);
  g.Disable(GL_DEPTH_TEST);
  g.DepthMask(GL_FALSE);
  const ShaderProgram* p = program({kind, 0});
  assert(p && "compiled in init()");
  g.UseProgram(p->id());
  g.ActiveTexture(GL_TEXTURE0);
  g.BindTexture(GL_TEXTURE_2D, input);
  g.Uniform1i(p->location(Uniform::Depth), 0);
  g.Uniform1i(p->location(Uniform::Ao), 0);
  const glm::vec4 proj(view.projection[0][0], view.projection[1][1], view.projection[2][2],
                       view.projection[3][2]);
  g.Uniform4fv(p->location(Uniform::ProjectionParams), 1, &proj[0]);
  if (kind == ProgramKind::Ssao) {
    g.Uniform1f(p->location(Uniform::AoRadius), static_cast<float>(e.ssao->radius));
    g.Uniform1f(p->location(Uniform::AoStrength), e.ssao->strength);
    g.Uniform1i(p->location(Uniform::AoSamples), e.ssao->samples);
  }
  if (kind == ProgramKind::Composite) {
    g.Enable(GL_BLEND);
    g.BlendFunc(GL_DST_COLOR, GL_ZERO);  // colour x occlusion
  } else if (kind == ProgramKind::Outline) {
    g.Enable(GL_BLEND);
    g.BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    g.Uniform3fv(p->location(Uniform::OutlineColour), 1, &e.outline->colour[0]);
    g.Uniform1f(p->location(Uniform::OutlineThickness), e.outline->thickness);
    g.Uniform1f(p->location(Uniform::OutlineThreshold), e.outline->threshold);
  } else {
    g.Disable(GL_BLEND);
  }
  g.BindVertexArray(fullscreenVao_.id());
  g.DrawArrays(GL_TRIANGLES, 0, 3);
  g.Disable(GL_BLEND);
  g.DepthMask(GL_TRUE);
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
