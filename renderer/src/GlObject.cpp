#include "renderer/GlObject.h"

namespace renderer {

GlObject GlObject::create(const GlFunctions& gl, GlKind kind, GLenum shaderType) {
  GLuint id = 0;
  switch (kind) {
    case GlKind::Buffer:
      gl.GenBuffers(1, &id);
      break;
    case GlKind::VertexArray:
      gl.GenVertexArrays(1, &id);
      break;
    case GlKind::Texture:
      gl.GenTextures(1, &id);
      break;
    case GlKind::Framebuffer:
      gl.GenFramebuffers(1, &id);
      break;
    case GlKind::Renderbuffer:
      gl.GenRenderbuffers(1, &id);
      break;
    case GlKind::Program:
      id = gl.CreateProgram();
      break;
    case GlKind::Shader:
      id = gl.CreateShader(shaderType);
      break;
    case GlKind::Query:
      gl.GenQueries(1, &id);
      break;
  }
  return GlObject(gl, kind, id);
}

void GlObject::reset() {
  if (!id_ || !gl_) return;
  switch (kind_) {
    case GlKind::Buffer:
      gl_->DeleteBuffers(1, &id_);
      break;
    case GlKind::VertexArray:
      gl_->DeleteVertexArrays(1, &id_);
      break;
    case GlKind::Texture:
      gl_->DeleteTextures(1, &id_);
      break;
    case GlKind::Framebuffer:
      gl_->DeleteFramebuffers(1, &id_);
      break;
    case GlKind::Renderbuffer:
      gl_->DeleteRenderbuffers(1, &id_);
      break;
    case GlKind::Program:
      gl_->DeleteProgram(id_);
      break;
    case GlKind::Shader:
      gl_->DeleteShader(id_);
      break;
    case GlKind::Query:
      gl_->DeleteQueries(1, &id_);
      break;
  }
  id_ = 0;
}

}  // namespace renderer
