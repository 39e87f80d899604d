#include "renderer/GpuMesh.h"

#include <algorithm>
#include <vector>

namespace renderer {

hlod::Result<GpuMesh> GpuMesh::upload(const GlFunctions& gl, const hlod::LocalMesh& mesh,
                                      std::shared_ptr<const GpuTexture> texture) {
  const std::size_t n = mesh.positions.size();
  if (mesh.normals.size() != n) return hlod::makeError("mesh normals do not match its vertices");
  for (const auto i : mesh.indices)
    if (i >= n) return hlod::makeError("mesh index out of range");
  const bool hasUv = mesh.texCoords.size() == n;
  // A texture given stands for the mesh's own (which a load that shares it leaves out).
  const bool textured = hasUv && ((mesh.texture && !mesh.texture->empty()) || texture);

  // Interleaved: position (3f), normal (3f), texCoord (2f) = 32 bytes a vertex.
  std::vector<float> interleaved(n * 8);
  for (std::size_t i = 0; i < n; ++i) {
    float* v = &interleaved[i * 8];
    v[0] = mesh.positions[i].x, v[1] = mesh.positions[i].y, v[2] = mesh.positions[i].z;
    v[3] = mesh.normals[i].x, v[4] = mesh.normals[i].y, v[5] = mesh.normals[i].z;
    v[6] = hasUv ? mesh.texCoords[i].x : 0.0f, v[7] = hasUv ? mesh.texCoords[i].y : 0.0f;
  }

  GpuMesh out;
  out.centre_ = mesh.centre;
  out.baseColor_ = mesh.baseColor;
  out.oneSided_ = mesh.oneSided;
  out.indexCount_ = mesh.indices.size();
  out.vao_ = GlObject::create(gl, GlKind::VertexArray);
  out.vbo_ = GlObject::create(gl, GlKind::Buffer);
  out.ibo_ = GlObject::create(gl, GlKind::Buffer);
  gl.BindVertexArray(out.vao_.id());
  gl.BindBuffer(GL_ARRAY_BUFFER, out.vbo_.id());
  gl.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(interleaved.size() * sizeof(float)),
                interleaved.data(), GL_STATIC_DRAW);
  gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, out.ibo_.id());
  gl.BufferData(GL_ELEMENT_ARRAY_BUFFER,
                static_cast<GLsizeiptr>(mesh.indices.size() * sizeof(std::uint32_t)),
                mesh.indices.data(), GL_STATIC_DRAW);
  constexpr GLsizei stride = 8 * sizeof(float);
  gl.EnableVertexAttribArray(0);
  gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, nullptr);
  gl.EnableVertexAttribArray(1);
  gl.VertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride,
                         reinterpret_cast<const void*>(3 * sizeof(float)));
  gl.EnableVertexAttribArray(2);
  gl.VertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, stride,
                         reinterpret_cast<const void*>(6 * sizeof(float)));
  gl.BindVertexArray(0);
  out.gpuBytes_ = interleaved.size() * sizeof(float) + mesh.indices.size() * sizeof(std::uint32_t);
  out.fullIndexCount_ = out.indexCount_;

  if (!mesh.splats.empty()) {
    // Splats as points: position, radius, normal, texCoord, 36 bytes each (hlod::Splat).
    static_assert(sizeof(hlod::Splat) == 9 * sizeof(float));
    out.splatCount_ = mesh.splats.size();
    out.splatVao_ = GlObject::create(gl, GlKind::VertexArray);
    out.splatVbo_ = GlObject::create(gl, GlKind::Buffer);
    gl.BindVertexArray(out.splatVao_.id());
    gl.BindBuffer(GL_ARRAY_BUFFER, out.splatVbo_.id());
    gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(mesh.splats.size() * sizeof(hlod::Splat)),
                  mesh.splats.data(), GL_STATIC_DRAW);
    constexpr GLsizei s = sizeof(hlod::Splat);
    const auto at = [](std::size_t floats) {
      return reinterpret_cast<const void*>(floats * sizeof(float));
    };
    gl.EnableVertexAttribArray(0);
    gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, s, at(0));
    gl.EnableVertexAttribArray(3);
    gl.VertexAttribPointer(3, 1, GL_FLOAT, GL_FALSE, s, at(3));
    gl.EnableVertexAttribArray(1);
    gl.VertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, s, at(4));
    gl.EnableVertexAttribArray(2);
    gl.VertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, s, at(7));
    gl.BindVertexArray(0);
    out.gpuBytes_ += mesh.splats.size() * sizeof(hlod::Splat);
  }

  if (textured && texture) {
    out.texture_ = std::move(texture);
  } else if (textured) {
    const hlod::Image& img = *mesh.texture;
    auto t = std::make_shared<GpuTexture>();
    t->object = GlObject::create(gl, GlKind::Texture);
    gl.BindTexture(GL_TEXTURE_2D, t->object.id());
    gl.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    // Image row 0 is the top and v = 0 is the top (glTF convention): rows go up as they are.
    gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, img.width, img.height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                  img.pixels.data());
    gl.GenerateMipmap(GL_TEXTURE_2D);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    gl.BindTexture(GL_TEXTURE_2D, 0);
    // Mesa queues the mipmap generation (a blit per level) until the next flush, which would be
    // the frame's draw: its cost would land there unannounced. Finished here, it counts as
    // upload time, which the frame's selection already knows about (View::spentMs).
    gl.Finish();
    t->gpuBytes = static_cast<std::uint64_t>(img.width) * img.height * 4 * 4 / 3;
    out.texture_ = std::move(t);
  }
  return out;
}

hlod::Result<GpuMesh> GpuMesh::upload(const GlFunctions& gl,
                                      std::shared_ptr<const hlod::LocalMesh> mesh,
                                      std::shared_ptr<const GpuTexture> texture) {
  auto out = upload(gl, *mesh, std::move(texture));
  if (out && !mesh->progression.empty()) out->progressive_ = std::move(mesh);
  return out;
}

void GpuMesh::setDraw(const GlFunctions& gl, const hlod::NodeDraw& draw) {
  drawSplats_ = draw.splats;
  if (draw.splats || !progressive_) return;
  const std::uint64_t whole = fullIndexCount_ / 3;
  const std::uint64_t coarsest = whole - progressive_->progression.decimated();
  const std::uint64_t count = 3 * std::clamp<std::uint64_t>(draw.triangles, coarsest, whole);
  if (count == indexCount_) return;
  // The last triangles of the decimation order, their corners moved to the vertices they
  // reference there; the buffer was made for the whole mesh, so the fewer fit in its front.
  const std::vector<std::uint32_t> indices = hlod::progressiveIndices(
      progressive_->indices, progressive_->progression, count / 3, progressive_->positions.size());
  gl.BindVertexArray(vao_.id());
  gl.BufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, GLsizeiptr(indices.size() * sizeof(std::uint32_t)),
                   indices.data());
  gl.BindVertexArray(0);
  indexCount_ = count;
}

void GpuMesh::draw(const GlFunctions& gl) const {
  if (drawSplats_) {
    if (splatCount_ == 0) return;
    gl.BindVertexArray(splatVao_.id());
    gl.DrawArrays(GL_POINTS, 0, static_cast<GLsizei>(splatCount_));
    return;
  }
  gl.BindVertexArray(vao_.id());
  gl.DrawElements(GL_TRIANGLES, static_cast<GLsizei>(indexCount_), GL_UNSIGNED_INT, nullptr);
}

}  // namespace renderer
