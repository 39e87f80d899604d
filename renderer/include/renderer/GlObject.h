#pragma once
// Move-only owner of one GL object name; deletes it through its context's function table.
// Must be destroyed while its context is current (renderer objects live inside the session that
// owns the context, and die before it).
#include <utility>

#include "renderer/GlFunctions.h"

namespace renderer {

enum class GlKind {
  Buffer,
  VertexArray,
  Texture,
  Framebuffer,
  Renderbuffer,
  Program,
  Shader,
  Query
};

class GlObject {
 public:
  GlObject() = default;
  GlObject(const GlFunctions& gl, GlKind kind, GLuint id) : gl_(&gl), kind_(kind), id_(id) {}
  ~GlObject() { reset(); }
  GlObject(GlObject&& o) noexcept : gl_(o.gl_), kind_(o.kind_), id_(std::exchange(o.id_, 0)) {}
  GlObject& operator=(GlObject&& o) noexcept {
    if (this != &o) {
      reset();
      gl_ = o.gl_;
      kind_ = o.kind_;
      id_ = std::exchange(o.id_, 0);
    }
    return *this;
  }
  GlObject(const GlObject&) = delete;
  GlObject& operator=(const GlObject&) = delete;

  GLuint id() const { return id_; }
  explicit operator bool() const { return id_ != 0; }

  // Creates one object of the kind (Shader needs create(gl, GlKind::Shader, type)).
  static GlObject create(const GlFunctions& gl, GlKind kind, GLenum shaderType = 0);

 private:
  void reset();

  const GlFunctions* gl_ = nullptr;
  GlKind kind_ = GlKind::Buffer;
  GLuint id_ = 0;
};

}  // namespace renderer
