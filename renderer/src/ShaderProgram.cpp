#include "renderer/ShaderProgram.h"

#include <iterator>
#include <vector>

namespace renderer {
namespace {

// The GLSL names of the Uniform enumerators, in their order.
constexpr const char* kUniformNames[] = {"uModelView",     "uProjection",       "uOffset",
                                         "uBaseColor",     "uTexture",          "uUp",
                                         "uSunDir",        "uSunColour",        "uFogDensity",
                                         "uFogColour",     "uShadowModel",      "uShadowMap",
                                         "uShadowBias",    "uShadowTexel",      "uInvViewProj",
                                         "uHorizon",       "uZenith",           "uGround",
                                         "uDepth",         "uProjectionParams", "uAoRadius",
                                         "uAoStrength",    "uAoSamples",        "uAo",
                                         "uOutlineColour", "uOutlineThickness", "uOutlineThreshold",
                                         "uPointScale"};
static_assert(std::size(kUniformNames) == static_cast<std::size_t>(Uniform::Count));

hlod::Result<GlObject> compile(const GlFunctions& gl, GLenum type, const std::string& source) {
  GlObject shader = GlObject::create(gl, GlKind::Shader, type);
  const char* src = source.c_str();
  gl.ShaderSource(shader.id(), 1, &src, nullptr);
  gl.CompileShader(shader.id());
  GLint ok = 0;
  gl.GetShaderiv(shader.id(), GL_COMPILE_STATUS, &ok);
  if (!ok) {
    std::vector<char> log(4096);
    gl.GetShaderInfoLog(shader.id(), static_cast<GLsizei>(log.size()), nullptr, log.data());
    return hlod::makeError(std::string("shader compile failed: ") + log.data());
  }
  return shader;
}

}  // namespace

hlod::Result<ShaderProgram> ShaderProgram::build(const GlFunctions& gl, const std::string& defines,
                                                 const std::string& vertexSource,
                                                 const std::string& fragmentSource) {
  const std::string header = "#version 450 core\n" + defines;
  auto vs = compile(gl, GL_VERTEX_SHADER, header + vertexSource);
  if (!vs) return vs.error();
  auto fs = compile(gl, GL_FRAGMENT_SHADER, header + fragmentSource);
  if (!fs) return fs.error();
  ShaderProgram p;
  p.program_ = GlObject::create(gl, GlKind::Program);
  gl.AttachShader(p.program_.id(), vs->id());
  gl.AttachShader(p.program_.id(), fs->id());
  gl.LinkProgram(p.program_.id());
  GLint ok = 0;
  gl.GetProgramiv(p.program_.id(), GL_LINK_STATUS, &ok);
  if (!ok) {
    std::vector<char> log(4096);
    gl.GetProgramInfoLog(p.program_.id(), static_cast<GLsizei>(log.size()), nullptr, log.data());
    return hlod::makeError(std::string("shader link failed: ") + log.data());
  }
  for (std::size_t i = 0; i < p.locations_.size(); ++i)
    p.locations_[i] = gl.GetUniformLocation(p.program_.id(), kUniformNames[i]);
  return p;
}

}  // namespace renderer
