#pragma once
// A linked GLSL program for one combination of effects (only declared effects are compiled).
#include <string>

#include "hlod/Result.h"
#include "renderer/GlObject.h"

namespace renderer {

class ShaderProgram {
 public:
  // Compiles vertex + fragment sources, each prefixed with `#version 450 core` and the defines.
  static hlod::Result<ShaderProgram> build(const GlFunctions& gl, const std::string& defines,
                                           const char* vertexSource, const char* fragmentSource);
  GLuint id() const { return program_.id(); }
  GLint uniform(const GlFunctions& gl, const char* name) const {
    return gl.GetUniformLocation(program_.id(), name);
  }

 private:
  GlObject program_;
};

}  // namespace renderer
