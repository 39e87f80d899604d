// STL reader: binary (recognised by its exact size 84 + 50 n, since many binary files also begin
// with "solid") and ASCII. STL stores three corners per triangle; identical corners are merged so
// that the mesh is indexed and the HLOD builder sees connectivity.
#include <cmath>
#include <cstring>

#include "import/ImportUtil.h"

namespace hlod::import {
namespace {

struct VertexKey {
  double x, y, z;
  bool operator==(const VertexKey& o) const { return x == o.x && y == o.y && z == o.z; }
};

struct VertexKeyHash {
  std::size_t operator()(const VertexKey& k) const {
    auto bits = [](double d) {
      std::uint64_t b;
      std::memcpy(&b, &d, sizeof(b));
      return b;
    };
    return static_cast<std::size_t>(mixBits(bits(k.x) ^ mixBits(bits(k.y) ^ mixBits(bits(k.z)))));
  }
};

// Collects corners and merges identical positions.
class Welder {
 public:
  explicit Welder(std::size_t triangles) : map_(triangles / 2 + 16) {
    mesh_.indices.reserve(triangles * 3);
    mesh_.positions.reserve(triangles / 2 + 16);
  }
  void add(double x, double y, double z) {
    // +0.0 turns -0.0 into +0.0 so both hash alike; NaN never merges and is caught later.
    VertexKey key{x + 0.0, y + 0.0, z + 0.0};
    auto [index, inserted] = map_.insert(key, static_cast<std::uint32_t>(mesh_.positions.size()));
    if (inserted) mesh_.positions.emplace_back(x, y, z);
    mesh_.indices.push_back(index);
  }
  Mesh take() { return std::move(mesh_); }

 private:
  FlatIndexMap<VertexKey, VertexKeyHash> map_;
  Mesh mesh_;
};

Result<Model> readBinary(const std::string& bytes, std::size_t count) {
  Welder welder(count);
  const char* p = bytes.data() + 84;
  for (std::size_t t = 0; t < count; ++t, p += 50) {
    // 12 bytes normal (recomputed later from the geometry), 3 x 12 bytes corners, 2 attribute.
    for (int c = 0; c < 3; ++c) {
      const char* v = p + 12 + c * 12;
      welder.add(loadScalar<float>(v, false), loadScalar<float>(v + 4, false),
                 loadScalar<float>(v + 8, false));
    }
  }
  Model model;
  model.meshes.push_back(welder.take());
  return model;
}

Result<Model> readAscii(const std::filesystem::path& path, const std::string& bytes) {
  TextScanner scan(bytes);
  Welder welder(bytes.size() / 250);  // an ASCII facet takes about 250 bytes
  double corner[16][3];
  int corners = 0;
  bool inLoop = false, ended = false;
  while (true) {
    scan.skipSpace();
    if (scan.atEnd()) break;
    const std::size_t line = scan.line();
    std::string_view tok = scan.token();
    if (tok == "vertex") {
      double x, y, z;
      if (!inLoop) return lineError(path, line, "'vertex' outside 'outer loop'");
      if (!scan.number(x) || !scan.number(y) || !scan.number(z))
        return lineError(path, line, "expected three vertex coordinates");
      if (corners == 16) return lineError(path, line, "facet with more than 16 corners");
      corner[corners][0] = x;
      corner[corners][1] = y;
      corner[corners][2] = z;
      ++corners;
    } else if (tok == "outer") {
      if (scan.token() != "loop") return lineError(path, line, "expected 'outer loop'");
      inLoop = true;
      corners = 0;
    } else if (tok == "endloop") {
      if (!inLoop) return lineError(path, line, "'endloop' without 'outer loop'");
      if (corners < 3) return lineError(path, line, "facet with fewer than 3 vertices");
      for (int k = 1; k + 1 < corners; ++k)
        for (int c : {0, k, k + 1}) welder.add(corner[c][0], corner[c][1], corner[c][2]);
      inLoop = false;
    } else if (tok == "facet") {
      if (inLoop) return lineError(path, line, "'facet' inside a loop (truncated facet?)");
      // "facet normal nx ny nz": the normal is recomputed from geometry.
      scan.restOfLine();
    } else if (tok == "endfacet") {
      if (inLoop) return lineError(path, line, "'endfacet' before 'endloop'");
    } else if (tok == "solid") {
      ended = false;
      scan.restOfLine();
    } else if (tok == "endsolid") {
      if (inLoop) return lineError(path, line, "'endsolid' inside a facet");
      ended = true;
      scan.restOfLine();
    } else {
      return lineError(path, line, "unexpected '" + std::string(tok.substr(0, 40)) + "'");
    }
  }
  if (!ended) return fileError(path, "unexpected end of file (truncated ASCII STL, no endsolid)");
  Model model;
  model.meshes.push_back(welder.take());
  return model;
}

}  // namespace

Result<Model> readStl(const std::filesystem::path& path, const std::string& bytes) {
  const std::size_t size = bytes.size();
  std::uint64_t count = size >= 84 ? loadScalar<std::uint32_t>(bytes.data() + 80, false) : 0;
  if (size >= 84 && size == 84 + 50 * count) return readBinary(bytes, count);
  std::size_t first = 0;
  while (first < size && TextScanner::isSpace(bytes[first])) ++first;
  const bool saysSolid = bytes.compare(first, 5, "solid") == 0;
  // A binary file (NUL bytes in it) whose size does not match its count is truncated or padded.
  const bool looksBinary = std::memchr(bytes.data(), '\0', std::min<std::size_t>(size, 4096));
  if (size >= 84 && (!saysSolid || looksBinary))
    return fileError(path, "binary STL header claims " + std::to_string(count) + " triangles (" +
                               std::to_string(84 + 50 * count) + " bytes) but the file has " +
                               std::to_string(size) + " bytes (truncated or corrupt)");
  if (!saysSolid) return fileError(path, "not an STL file (too short for binary, no 'solid')");
  return readAscii(path, bytes);
}

}  // namespace hlod::import
