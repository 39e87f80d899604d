// writePly: binary little-endian PLY with double positions, the exchange format between the city
// generator and the importer (import/PlyReader.cpp reads it back).
#include "hlod/export/PlyWriter.h"

#include <bit>
#include <cstdio>
#include <cstring>

namespace hlod {
namespace {

// "PATH: what", as the readers' errors: the file first.
Error fileError(const std::filesystem::path& path, const std::string& what) {
  return makeError(path.string() + ": " + what);
}

template <class T>
void put(std::string& out, T value) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  if constexpr (std::endian::native == std::endian::big)
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
  out.append(reinterpret_cast<const char*>(b), sizeof(T));
}

}  // namespace

Status writePly(const std::filesystem::path& path, const Mesh& mesh,
                const std::string& textureFileName) {
  const std::size_t n = mesh.positions.size();
  const bool normals = !mesh.normals.empty();
  const bool uvs = !mesh.texCoords.empty();
  if (normals && mesh.normals.size() != n)
    return fileError(path, "cannot write PLY: normal count differs from vertex count");
  if (uvs && mesh.texCoords.size() != n)
    return fileError(path, "cannot write PLY: texture coordinate count differs from vertex count");
  if (mesh.indices.size() % 3 != 0)
    return fileError(path, "cannot write PLY: index count is not a multiple of 3");
  if (textureFileName.find('\n') != std::string::npos)
    return fileError(path, "cannot write PLY: texture name contains a newline");

  std::string header = "ply\nformat binary_little_endian 1.0\ncomment written by hlodr\n";
  if (!textureFileName.empty()) header += "comment TextureFile " + textureFileName + "\n";
  header += "element vertex " + std::to_string(n) + "\n";
  header += "property double x\nproperty double y\nproperty double z\n";
  if (normals) header += "property float nx\nproperty float ny\nproperty float nz\n";
  if (uvs) header += "property float u\nproperty float v\n";
  header += "element face " + std::to_string(mesh.indices.size() / 3) + "\n";
  header += "property list uchar uint vertex_indices\nend_header\n";

  std::string out;
  const std::size_t vertexSize = 24 + (normals ? 12 : 0) + (uvs ? 8 : 0);
  out.reserve(header.size() + n * vertexSize + mesh.indices.size() / 3 * 13);
  out += header;
  for (std::size_t i = 0; i < n; ++i) {
    put(out, mesh.positions[i].x);
    put(out, mesh.positions[i].y);
    put(out, mesh.positions[i].z);
    if (normals) {
      put(out, mesh.normals[i].x);
      put(out, mesh.normals[i].y);
      put(out, mesh.normals[i].z);
    }
    if (uvs) {
      put(out, mesh.texCoords[i].x);
      put(out, 1.0f - mesh.texCoords[i].y);  // glTF v down -> PLY v up
    }
  }
  for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
    put(out, static_cast<std::uint8_t>(3));
    put(out, mesh.indices[t]);
    put(out, mesh.indices[t + 1]);
    put(out, mesh.indices[t + 2]);
  }

  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return fileError(path, "cannot open for writing");
  const bool wrote = std::fwrite(out.data(), 1, out.size(), f) == out.size();
  const bool closed = std::fclose(f) == 0;
  if (!wrote || !closed) {
    std::error_code ec;
    std::filesystem::remove(path, ec);
    return fileError(path, "write failed");
  }
  return Ok{};
}

}  // namespace hlod
