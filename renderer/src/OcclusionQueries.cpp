#include "renderer/OcclusionQueries.h"

#include <array>
#include <cassert>

namespace renderer {
namespace {

constexpr const char* kBoxVertex = R"(
layout(location = 0) in vec3 aPosition;  // the unit cube
uniform mat4 uModelView;   // cube -> camera-relative box, formed in double on the CPU
uniform mat4 uProjection;  // reversed-Z
void main() { gl_Position = uProjection * (uModelView * vec4(aPosition, 1.0)); }
)";

constexpr const char* kBoxFragment = R"(
uniform vec4 uBaseColor;
out vec4 fragColor;
void main() { fragColor = uBaseColor; }
)";

// The unit cube: 8 corners, 12 triangles (36 indices, counter-clockwise seen from outside), then
// its 12 edges (24 indices).
constexpr std::array<float, 24> kCorners = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0,
                                            0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
constexpr std::array<std::uint32_t, 60> kIndices = {
    0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4, 1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6,
    3, 0, 4, 3, 4, 7, 0, 1, 1, 2, 2, 3, 3, 0, 4, 5, 5, 6, 6, 7, 7, 4, 0, 4, 1, 5, 2, 6, 3, 7};
constexpr GLsizei kFaceIndices = 36, kEdgeIndices = 24;

}  // namespace

hlod::Result<std::unique_ptr<OcclusionQueries>> OcclusionQueries::create(const GlFunctions& gl) {
  std::unique_ptr<OcclusionQueries> q(new OcclusionQueries(gl));
  auto program = ShaderProgram::build(gl, "", kBoxVertex, kBoxFragment);
  if (!program) return hlod::makeError("occlusion box program: " + program.message());
  q->program_ = std::move(*program);
  q->vao_ = GlObject::create(gl, GlKind::VertexArray);
  q->vbo_ = GlObject::create(gl, GlKind::Buffer);
  q->ibo_ = GlObject::create(gl, GlKind::Buffer);
  gl.BindVertexArray(q->vao_.id());
  gl.BindBuffer(GL_ARRAY_BUFFER, q->vbo_.id());
  gl.BufferData(GL_ARRAY_BUFFER, sizeof(kCorners), kCorners.data(), GL_STATIC_DRAW);
  gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, q->ibo_.id());
  gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, sizeof(kIndices), kIndices.data(), GL_STATIC_DRAW);
  gl.EnableVertexAttribArray(0);
  gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
  gl.BindVertexArray(0);
  return q;
}

void OcclusionQueries::beginFrame() {
  used_ = 0;
  drawIds_.clear();
  boxIds_.clear();
}

GLuint OcclusionQueries::nextQuery() {
  if (used_ == pool_.size()) pool_.push_back(GlObject::create(gl_, GlKind::Query));
  return pool_[used_++].id();
}

void OcclusionQueries::beginDraw() {
  const GLuint id = nextQuery();
  drawIds_.push_back(id);
  gl_.BeginQuery(GL_SAMPLES_PASSED, id);
}

void OcclusionQueries::endDraw() {
  gl_.EndQuery(GL_SAMPLES_PASSED);
}

void OcclusionQueries::drawBox(const FrameView& view, const hlod::Aabb& box, GLenum mode,
                               GLsizei count, const void* offset) {
  // Camera-relative in double, then float, as the meshes are drawn.
  const glm::dvec3 size = glm::max(box.max - box.min, glm::dvec3(0.0));
  glm::dmat4 m(1.0);
  m[0][0] = size.x, m[1][1] = size.y, m[2][2] = size.z;
  m[3] = glm::dvec4(box.min - view.eye, 1.0);
  const glm::mat4 modelView(view.rotation * m);
  gl_.UniformMatrix4fv(program_.location(Uniform::ModelView), 1, GL_FALSE, &modelView[0][0]);
  gl_.DrawElements(mode, count, GL_UNSIGNED_INT, offset);
}

void OcclusionQueries::queryBoxes(const FrameView& view,
                                  std::span<const std::vector<hlod::Aabb>> batches) {
  if (batches.empty()) return;
  const glm::mat4 projection(view.projection);
  gl_.UseProgram(program_.id());
  gl_.UniformMatrix4fv(program_.location(Uniform::Projection), 1, GL_FALSE, &projection[0][0]);
  gl_.BindVertexArray(vao_.id());
  // Tested against the occluders' depth, changing nothing.
  gl_.Enable(GL_DEPTH_TEST);
  gl_.DepthFunc(GL_GREATER);
  gl_.DepthMask(GL_FALSE);
  gl_.ColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  // Front faces only (the cube's triangles wind outwards): no queried box holds the camera, so a
  // back face that passes the depth test lies behind a front face that passes too. Half the
  // fragments, the same answers.
  gl_.Enable(GL_CULL_FACE);
  gl_.CullFace(GL_BACK);
  for (const auto& batch : batches) {
    const GLuint id = nextQuery();
    boxIds_.push_back(id);
    gl_.BeginQuery(GL_SAMPLES_PASSED, id);
    for (const hlod::Aabb& box : batch) drawBox(view, box, GL_TRIANGLES, kFaceIndices, nullptr);
    gl_.EndQuery(GL_SAMPLES_PASSED);
  }
  gl_.Disable(GL_CULL_FACE);
  gl_.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  gl_.DepthMask(GL_TRUE);
  gl_.BindVertexArray(0);
}

std::vector<std::optional<std::uint64_t>> OcclusionQueries::read(
    std::span<const GLuint> ids) const {
  std::vector<std::optional<std::uint64_t>> out;
  out.reserve(ids.size());
  for (GLuint id : ids) {
    GLuint64 available = 0;
    gl_.GetQueryObjectui64v(id, GL_QUERY_RESULT_AVAILABLE, &available);
    if (!available) {
      out.push_back(std::nullopt);
      continue;
    }
    GLuint64 samples = 0;
    gl_.GetQueryObjectui64v(id, GL_QUERY_RESULT, &samples);
    out.push_back(samples);
  }
  return out;
}

std::vector<std::optional<std::uint64_t>> OcclusionQueries::drawSamples() const {
  return read(drawIds_);
}

std::vector<std::optional<std::uint64_t>> OcclusionQueries::boxSamples() const {
  return read(boxIds_);
}

void OcclusionQueries::drawTinted(const FrameView& view, std::span<const hlod::Aabb> boxes,
                                  glm::vec4 colour) {
  if (boxes.empty()) return;
  const glm::mat4 projection(view.projection);
  gl_.UseProgram(program_.id());
  gl_.UniformMatrix4fv(program_.location(Uniform::Projection), 1, GL_FALSE, &projection[0][0]);
  gl_.BindVertexArray(vao_.id());
  gl_.Disable(GL_DEPTH_TEST);
  gl_.Disable(GL_CULL_FACE);
  gl_.Enable(GL_BLEND);
  gl_.BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  gl_.Uniform4fv(program_.location(Uniform::BaseColor), 1, &colour[0]);
  for (const hlod::Aabb& box : boxes) drawBox(view, box, GL_TRIANGLES, kFaceIndices, nullptr);
  const glm::vec4 edge(glm::vec3(colour), 1.0f);
  gl_.Uniform4fv(program_.location(Uniform::BaseColor), 1, &edge[0]);
  const void* edges = reinterpret_cast<const void*>(kFaceIndices * sizeof(std::uint32_t));
  for (const hlod::Aabb& box : boxes) drawBox(view, box, GL_LINES, kEdgeIndices, edges);
  gl_.Disable(GL_BLEND);
  gl_.BindVertexArray(0);
}

}  // namespace renderer
