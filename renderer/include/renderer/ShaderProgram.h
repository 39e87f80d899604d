#pragma once
// A linked GLSL program for one shader variant, with the locations of its uniforms looked up
// once at link time: drawing a mesh sets uniforms by index, never by name.
#include <array>
#include <string>

#include "hlod/Result.h"
#include "renderer/GlObject.h"

namespace renderer {

// Every uniform any of hlodr's programs uses; a program holds -1 for those it lacks.
enum class Uniform {
  ModelView,
  Projection,
  Offset,
  BaseColor,
  Texture,
  Up,
  SunDir,
  SunColour,
  FogDensity,
  FogColour,
  ShadowModel,
  ShadowMap,
  ShadowBias,
  ShadowTexel,
  InvViewProj,
  Horizon,
  Zenith,
  Ground,
  Depth,
  ProjectionParams,
  AoRadius,
  AoStrength,
  AoSamples,
  Ao,
  OutlineColour,
  OutlineThickness,
  OutlineThreshold,
  PointScale,
  Count
};

class ShaderProgram {
 public:
  // Compiles vertex + fragment sources, each prefixed with `#version 450 core` and the defines,
  // links them and looks up every Uniform.
  static hlod::Result<ShaderProgram> build(const GlFunctions& gl, const std::string& defines,
                                           const std::string& vertexSource,
                                           const std::string& fragmentSource);
  GLuint id() const { return program_.id(); }
  GLint location(Uniform u) const { return locations_[static_cast<std::size_t>(u)]; }

 private:
  GlObject program_;
  std::array<GLint, static_cast<std::size_t>(Uniform::Count)> locations_{};
};

}  // namespace renderer
