// OFF reader: OFF with the optional ST/C/N/4/n prefixes (COFF, NOFF, STOFF, ...), '#' comments,
// polygons fan-triangulated. Vertex colours are skipped; normals (N) are kept.
#include <cmath>

#include "import/ImportUtil.h"

namespace hlod::import {

Result<Model> readOff(const std::filesystem::path& path, const std::string& bytes) {
  TextScanner scan(bytes);
  scan.skipSpace('#');
  std::string_view magic = scan.token();
  // Keyword: [ST][C][N][4][n]OFF, optionally followed by counts on the same line.
  if (magic.size() < 3 || magic.substr(magic.size() - 3) != "OFF")
    return lineError(path, scan.line(), "not an OFF file (missing OFF keyword)");
  std::string_view prefix = magic.substr(0, magic.size() - 3);
  bool hasTexCoords = false, hasNormals = false;
  if (prefix.substr(0, 2) == "ST") {
    hasTexCoords = true;
    prefix.remove_prefix(2);
  }
  if (!prefix.empty() && prefix.front() == 'C') prefix.remove_prefix(1);
  if (!prefix.empty() && prefix.front() == 'N') {
    hasNormals = true;
    prefix.remove_prefix(1);
  }
  if (!prefix.empty())
    return lineError(path, scan.line(),
                     "unsupported OFF variant '" + std::string(magic) + "' (4D/nD)");
  long long nv = 0, nf = 0, ne = 0;
  // The counts may follow the keyword on the same line.
  if (!scan.atEol()) {
    if (!scan.integer(nv)) {
      std::string_view next = scan.token();
      if (next == "BINARY") return lineError(path, scan.line(), "binary OFF is not supported");
      return lineError(path, scan.line(), "unexpected '" + std::string(next) + "' after OFF");
    }
  } else if (!scan.integerAcrossLines(nv, '#')) {
    return lineError(path, scan.line(), "expected vertex and face counts");
  }
  if (!scan.integerAcrossLines(nf, '#'))
    return lineError(path, scan.line(), "expected vertex and face counts");
  if (!scan.integer(ne)) ne = 0;
  scan.skipLine();
  // A vertex needs at least "0 0 0\n" and a face "3 0 0 0\n": reject absurd counts up front.
  const std::size_t left = scan.remaining();
  if (nv < 0 || nf < 0 || static_cast<unsigned long long>(nv) > left / 6 ||
      static_cast<unsigned long long>(nf) > left / 8 ||
      static_cast<unsigned long long>(nv) * 6 + static_cast<unsigned long long>(nf) * 8 > left + 1)
    return fileError(path, "header claims " + std::to_string(nv) + " vertices and " +
                               std::to_string(nf) + " faces but only " + std::to_string(left) +
                               " bytes follow (truncated or corrupt file)");

  Mesh mesh;
  mesh.positions.resize(static_cast<std::size_t>(nv));
  if (hasNormals) mesh.normals.resize(static_cast<std::size_t>(nv));
  if (hasTexCoords) mesh.texCoords.resize(static_cast<std::size_t>(nv));
  auto fail = [&](const std::string& what) -> Error {
    if (scan.atEnd()) return fileError(path, "unexpected end of file (" + what + ")");
    return lineError(path, scan.line(), what);
  };
  for (long long i = 0; i < nv; ++i) {
    glm::dvec3& p = mesh.positions[static_cast<std::size_t>(i)];
    if (!scan.numberAcrossLines(p.x, '#') || !scan.number(p.y) || !scan.number(p.z))
      return fail("expected coordinates of vertex " + std::to_string(i));
    if (hasNormals) {
      double n[3];
      if (!scan.number(n[0]) || !scan.number(n[1]) || !scan.number(n[2]))
        return fail("expected normal of vertex " + std::to_string(i));
      mesh.normals[static_cast<std::size_t>(i)] = glm::vec3(glm::dvec3(n[0], n[1], n[2]));
    }
    if (hasTexCoords) {
      // Colours (3 or 4 values) may precede s t: the texture coordinates are the last two.
      double vals[8];
      int count = 0;
      double v;
      while (scan.number(v)) vals[count++ % 8] = v;
      if (count < 2) return fail("expected texture coordinates of vertex " + std::to_string(i));
      mesh.texCoords[static_cast<std::size_t>(i)] =
          glm::vec2(static_cast<float>(vals[(count - 2) % 8]),
                    static_cast<float>(1.0 - vals[(count - 1) % 8]));  // v up -> v down
    }
    scan.skipLine();  // colours and anything else on the line
  }
  mesh.indices.reserve(static_cast<std::size_t>(nf) * 3);
  std::vector<std::uint32_t> polygon;
  for (long long f = 0; f < nf; ++f) {
    long long n;
    if (!scan.integerAcrossLines(n, '#')) return fail("expected face " + std::to_string(f));
    const std::size_t line = scan.line();
    if (n < 0 || static_cast<unsigned long long>(n) > scan.remaining())
      return fail("bad vertex count " + std::to_string(n) + " in face " + std::to_string(f));
    polygon.clear();
    for (long long k = 0; k < n; ++k) {
      long long idx;
      if (!scan.integerAcrossLines(idx, '#'))
        return fail("expected vertex index in face " + std::to_string(f));
      if (idx < 0 || idx >= nv)
        return lineError(path, line,
                         "face index " + std::to_string(idx) + " out of range (" +
                             std::to_string(nv) + " vertices)");
      polygon.push_back(static_cast<std::uint32_t>(idx));
    }
    for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
      mesh.indices.push_back(polygon[0]);
      mesh.indices.push_back(polygon[k]);
      mesh.indices.push_back(polygon[k + 1]);
    }
    scan.skipLine();  // optional face colour
  }
  Model model;
  model.meshes.push_back(std::move(mesh));
  return model;
}

}  // namespace hlod::import
