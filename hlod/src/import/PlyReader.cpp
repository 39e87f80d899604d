// PLY reader: ascii, binary_little_endian and binary_big_endian; float or double vertex
// coordinates (doubles kept exactly), optional normals and texture coordinates, polygon faces
// fan-triangulated, unknown properties and elements skipped by their declared types.
#include <algorithm>
#include <array>
#include <cmath>

#include "import/ImportUtil.h"

namespace hlod::import {
namespace {

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

std::size_t sizeOf(PlyType t) {
  switch (t) {
    case PlyType::Int8:
    case PlyType::UInt8:
      return 1;
    case PlyType::Int16:
    case PlyType::UInt16:
      return 2;
    case PlyType::Int32:
    case PlyType::UInt32:
    case PlyType::Float32:
      return 4;
    case PlyType::Float64:
      return 8;
  }
  return 1;
}

bool parseType(std::string_view s, PlyType& t) {
  static const std::array<std::pair<std::string_view, PlyType>, 16> names{{
      {"char", PlyType::Int8},
      {"int8", PlyType::Int8},
      {"uchar", PlyType::UInt8},
      {"uint8", PlyType::UInt8},
      {"short", PlyType::Int16},
      {"int16", PlyType::Int16},
      {"ushort", PlyType::UInt16},
      {"uint16", PlyType::UInt16},
      {"int", PlyType::Int32},
      {"int32", PlyType::Int32},
      {"uint", PlyType::UInt32},
      {"uint32", PlyType::UInt32},
      {"float", PlyType::Float32},
      {"float32", PlyType::Float32},
      {"double", PlyType::Float64},
      {"float64", PlyType::Float64},
  }};
  for (const auto& [n, v] : names)
    if (n == s) {
      t = v;
      return true;
    }
  return false;
}

// What a property feeds: a vertex component, the face index list, or nothing (skipped).
enum class Role { None, X, Y, Z, NX, NY, NZ, U, V, FaceIndices };

struct PlyProperty {
  std::string name;
  bool isList = false;
  PlyType type = PlyType::Float32;
  PlyType countType = PlyType::UInt8;
  Role role = Role::None;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> props;
};

enum class Format { Ascii, BinaryLittle, BinaryBig };

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && TextScanner::isSpace(line[i])) ++i;
    std::size_t j = i;
    while (j < line.size() && !TextScanner::isSpace(line[j])) ++j;
    if (j > i) out.push_back(line.substr(i, j - i));
    i = j;
  }
  return out;
}

Role vertexRole(std::string_view n) {
  if (n == "x") return Role::X;
  if (n == "y") return Role::Y;
  if (n == "z") return Role::Z;
  if (n == "nx") return Role::NX;
  if (n == "ny") return Role::NY;
  if (n == "nz") return Role::NZ;
  if (n == "u" || n == "s" || n == "texture_u" || n == "texture_s") return Role::U;
  if (n == "v" || n == "t" || n == "texture_v" || n == "texture_t") return Role::V;
  return Role::None;
}

double loadAsDouble(const char* p, PlyType t, bool big) {
  switch (t) {
    case PlyType::Int8:
      return static_cast<double>(static_cast<std::int8_t>(*p));
    case PlyType::UInt8:
      return static_cast<double>(static_cast<std::uint8_t>(*p));
    case PlyType::Int16:
      return loadScalar<std::int16_t>(p, big);
    case PlyType::UInt16:
      return loadScalar<std::uint16_t>(p, big);
    case PlyType::Int32:
      return loadScalar<std::int32_t>(p, big);
    case PlyType::UInt32:
      return loadScalar<std::uint32_t>(p, big);
    case PlyType::Float32:
      return loadScalar<float>(p, big);
    case PlyType::Float64:
      return loadScalar<double>(p, big);
  }
  return 0.0;
}

long long loadAsInteger(const char* p, PlyType t, bool big) {
  // Every PLY integer type fits a double exactly, so one reader serves both; a float count or
  // index that is not finite or does not fit is -1 (rejected by the caller).
  const double d = loadAsDouble(p, t, big);
  return std::isfinite(d) && std::fabs(d) < 9e18 ? static_cast<long long>(d) : -1;
}

class PlyParser {
 public:
  PlyParser(const std::filesystem::path& path, const std::string& bytes)
      : path_(path), bytes_(bytes), scan_(bytes) {}

  Result<Model> run() {
    if (auto s = parseHeader(); !s.ok()) return s.error();
    if (auto s = checkCounts(); !s.ok()) return s.error();
    for (const auto& element : elements_) {
      Status s = format_ == Format::Ascii ? readAscii(element) : readBinary(element);
      if (!s.ok()) return s.error();
    }
    if (!sawVertices_) return fileError(path_, "no 'vertex' element");
    // Faces may precede vertices in exotic files: check indices once everything is read.
    const std::size_t n = mesh_.positions.size();
    for (std::uint32_t idx : mesh_.indices)
      if (idx >= n)
        return fileError(path_, "face index " + std::to_string(idx) + " out of range (" +
                                    std::to_string(n) + " vertices)");
    if (!textureName_.empty()) mesh_.texture = textures_.load(path_, textureName_);
    Model model;
    model.meshes.push_back(std::move(mesh_));
    return model;
  }

 private:
  Status parseHeader() {
    std::string_view first = scan_.restOfLine();
    if (first != "ply") return fileError(path_, "not a PLY file (missing 'ply' magic)");
    bool haveFormat = false;
    while (true) {
      if (scan_.atEnd()) return fileError(path_, "truncated header (no end_header)");
      const std::size_t line = scan_.line();
      std::string_view text = scan_.restOfLine();
      auto tok = split(text);
      if (tok.empty()) continue;
      if (tok[0] == "end_header") break;
      if (tok[0] == "comment") {
        // "comment TextureFile NAME" (MeshLab convention) names the texture.
        if (tok.size() >= 3 && tok[1] == "TextureFile") {
          std::size_t at = text.find("TextureFile") + 11;
          std::string_view name = text.substr(at);
          while (!name.empty() && TextScanner::isSpace(name.front())) name.remove_prefix(1);
          textureName_ = std::string(name);
        }
        continue;
      }
      if (tok[0] == "obj_info") continue;
      if (tok[0] == "format") {
        if (tok.size() < 2) return lineError(path_, line, "bad format line");
        if (tok[1] == "ascii")
          format_ = Format::Ascii;
        else if (tok[1] == "binary_little_endian")
          format_ = Format::BinaryLittle;
        else if (tok[1] == "binary_big_endian")
          format_ = Format::BinaryBig;
        else
          return lineError(path_, line, "unknown format '" + std::string(tok[1]) + "'");
        haveFormat = true;
        continue;
      }
      if (tok[0] == "element") {
        if (tok.size() < 3) return lineError(path_, line, "bad element line");
        PlyElement e;
        e.name = std::string(tok[1]);
        auto [ptr, ec] = std::from_chars(tok[2].data(), tok[2].data() + tok[2].size(), e.count);
        if (ec != std::errc() || ptr != tok[2].data() + tok[2].size())
          return lineError(path_, line, "bad element count '" + std::string(tok[2]) + "'");
        elements_.push_back(std::move(e));
        continue;
      }
      if (tok[0] == "property") {
        if (elements_.empty()) return lineError(path_, line, "property before any element");
        PlyProperty p;
        if (tok.size() >= 5 && tok[1] == "list") {
          p.isList = true;
          if (!parseType(tok[2], p.countType) || !parseType(tok[3], p.type))
            return lineError(path_, line, "unknown property type");
          p.name = std::string(tok[4]);
        } else if (tok.size() >= 3 && tok[1] != "list") {
          if (!parseType(tok[1], p.type))
            return lineError(path_, line, "unknown property type '" + std::string(tok[1]) + "'");
          p.name = std::string(tok[2]);
        } else {
          return lineError(path_, line, "bad property line");
        }
        const std::string& en = elements_.back().name;
        if (en == "vertex" && !p.isList)
          p.role = vertexRole(p.name);
        else if (en == "face" && p.isList &&
                 (p.name == "vertex_indices" || p.name == "vertex_index"))
          p.role = Role::FaceIndices;
        elements_.back().props.push_back(std::move(p));
        continue;
      }
      return lineError(path_, line, "unknown header keyword '" + std::string(tok[0]) + "'");
    }
    if (!haveFormat) return fileError(path_, "header has no format line");
    dataStart_ = static_cast<std::size_t>(scan_.position() - bytes_.data());
    return Ok{};
  }

  // Rejects absurd counts against the bytes present, before anything is allocated.
  Status checkCounts() {
    const std::size_t remaining = bytes_.size() - dataStart_;
    // Every value takes at least one byte in binary and a character plus a separator in ascii.
    const std::uint64_t perValue = format_ == Format::Ascii ? 2 : 1;
    std::uint64_t need = 0;
    for (const auto& e : elements_) {
      std::uint64_t minSize = 0;
      for (const auto& p : e.props)
        minSize += format_ == Format::Ascii ? perValue : sizeOf(p.isList ? p.countType : p.type);
      if (minSize == 0) {
        if (e.count > (1ULL << 32))
          return fileError(path_, "element '" + e.name + "' count absurd");
        continue;
      }
      if (e.count > (remaining + 1) / minSize || need + e.count * minSize > remaining + 1)
        return fileError(path_, "header claims " + std::to_string(e.count) + " '" + e.name +
                                    "' items but only " + std::to_string(remaining) +
                                    " bytes of data follow (truncated or corrupt file)");
      need += e.count * minSize;
      if (e.name == "vertex" && e.count > 0xffffffffULL)
        return fileError(path_, "too many vertices for 32-bit indices");
    }
    return Ok{};
  }

  // Prepares the mesh arrays for the vertex element; returns which optional parts exist.
  Status beginVertices(const PlyElement& e) {
    bool has[10] = {};
    for (const auto& p : e.props) has[static_cast<int>(p.role)] = true;
    if (!has[(int)Role::X] || !has[(int)Role::Y] || !has[(int)Role::Z])
      return fileError(path_, "vertex element lacks x, y or z");
    hasNormals_ = has[(int)Role::NX] && has[(int)Role::NY] && has[(int)Role::NZ];
    hasUv_ = has[(int)Role::U] && has[(int)Role::V];
    mesh_.positions.resize(e.count);
    if (hasNormals_) mesh_.normals.resize(e.count);
    if (hasUv_) mesh_.texCoords.resize(e.count);
    sawVertices_ = true;
    return Ok{};
  }

  void store(Role role, std::size_t i, double v) {
    switch (role) {
      case Role::X:
        mesh_.positions[i].x = v;
        break;
      case Role::Y:
        mesh_.positions[i].y = v;
        break;
      case Role::Z:
        mesh_.positions[i].z = v;
        break;
      case Role::NX:
        if (hasNormals_) mesh_.normals[i].x = static_cast<float>(v);
        break;
      case Role::NY:
        if (hasNormals_) mesh_.normals[i].y = static_cast<float>(v);
        break;
      case Role::NZ:
        if (hasNormals_) mesh_.normals[i].z = static_cast<float>(v);
        break;
      case Role::U:
        if (hasUv_) mesh_.texCoords[i].x = static_cast<float>(v);
        break;
      case Role::V:  // PLY has v up; glTF convention (ours) has v down.
        if (hasUv_) mesh_.texCoords[i].y = static_cast<float>(1.0 - v);
        break;
      default:
        break;
    }
  }

  // Fan-triangulates one polygon; index range is checked when the vertex count is known.
  Status addPolygon(std::size_t face, std::size_t line) {
    const std::size_t n = polygon_.size();
    if (n < 3) return Ok{};  // points and edges carry no surface
    const bool known = sawVertices_;
    const std::size_t vcount = mesh_.positions.size();
    for (long long idx : polygon_) {
      if (idx < 0 || idx > 0xffffffffLL || (known && static_cast<std::size_t>(idx) >= vcount)) {
        std::string what = "face " + std::to_string(face) + ": face index " + std::to_string(idx) +
                           " out of range (" + std::to_string(vcount) + " vertices)";
        return line ? lineError(path_, line, what) : fileError(path_, what);
      }
    }
    for (std::size_t k = 1; k + 1 < n; ++k) {
      mesh_.indices.push_back(static_cast<std::uint32_t>(polygon_[0]));
      mesh_.indices.push_back(static_cast<std::uint32_t>(polygon_[k]));
      mesh_.indices.push_back(static_cast<std::uint32_t>(polygon_[k + 1]));
    }
    return Ok{};
  }

  Error truncated(const PlyElement& e, std::uint64_t i) {
    return fileError(path_, "unexpected end of file in element '" + e.name + "' (item " +
                                std::to_string(i) + " of " + std::to_string(e.count) + ")");
  }

  // Room for the face element's triangles, as many as its count claims but no more than the
  // bytes left could hold: a triangle takes at least 4 bytes (binary: a count and three 1-byte
  // indices; ascii: more). checkCounts bounds counts only for elements whose items take bytes,
  // so a propertyless "element face 4294967295" once reserved 48 GB here.
  void reserveFaces(const PlyElement& e) {
    const std::uint64_t most = (bytes_.size() - dataStart_) / 4;
    mesh_.indices.reserve(mesh_.indices.size() + std::min<std::uint64_t>(e.count, most) * 3);
  }

  Status readBinary(const PlyElement& e) {
    const bool big = format_ == Format::BinaryBig;
    const bool isVertex = e.name == "vertex" && !sawVertices_;
    const bool isFace = e.name == "face";
    if (isVertex)
      if (auto s = beginVertices(e); !s.ok()) return s;
    if (e.props.empty()) return Ok{};  // its items take no bytes: nothing to read
    if (isFace) reserveFaces(e);
    const char* data = bytes_.data();
    const std::size_t size = bytes_.size();
    std::size_t& at = dataStart_;
    for (std::uint64_t i = 0; i < e.count; ++i) {
      bool havePolygon = false;
      for (const auto& p : e.props) {
        if (!p.isList) {
          const std::size_t s = sizeOf(p.type);
          if (size - at < s) return truncated(e, i);
          if (isVertex && p.role != Role::None)
            store(p.role, i, loadAsDouble(data + at, p.type, big));
          at += s;
          continue;
        }
        const std::size_t cs = sizeOf(p.countType);
        if (size - at < cs) return truncated(e, i);
        const long long n = loadAsInteger(data + at, p.countType, big);
        at += cs;
        if (n < 0) return fileError(path_, "negative list length in element '" + e.name + "'");
        const std::size_t s = sizeOf(p.type);
        if (static_cast<std::uint64_t>(n) > (size - at) / s) return truncated(e, i);
        if (isFace && p.role == Role::FaceIndices && !havePolygon) {
          polygon_.resize(static_cast<std::size_t>(n));
          for (long long k = 0; k < n; ++k)
            polygon_[k] = loadAsInteger(data + at + k * s, p.type, big);
          havePolygon = true;
        }
        at += static_cast<std::size_t>(n) * s;
      }
      if (havePolygon)
        if (auto s = addPolygon(i, 0); !s.ok()) return s;
    }
    return Ok{};
  }

  Status readAscii(const PlyElement& e) {
    const bool isVertex = e.name == "vertex" && !sawVertices_;
    const bool isFace = e.name == "face";
    if (isVertex)
      if (auto s = beginVertices(e); !s.ok()) return s;
    if (e.props.empty()) return Ok{};  // its items take no characters: nothing to read
    if (isFace) reserveFaces(e);
    for (std::uint64_t i = 0; i < e.count; ++i) {
      bool havePolygon = false;
      scan_.skipSpace();
      const std::size_t line = scan_.line();
      for (const auto& p : e.props) {
        if (!p.isList) {
          double v;
          if (!scan_.numberAcrossLines(v)) return asciiError(e, i);
          if (isVertex && p.role != Role::None) store(p.role, i, v);
          continue;
        }
        long long n;
        if (!scan_.integerAcrossLines(n) || n < 0) return asciiError(e, i);
        const bool keep = isFace && p.role == Role::FaceIndices && !havePolygon;
        if (static_cast<std::uint64_t>(n) > scan_.remaining()) return truncated(e, i);
        // Grown as values arrive: a lying count cannot force a huge allocation.
        if (keep) polygon_.clear();
        for (long long k = 0; k < n; ++k) {
          if (p.type == PlyType::Float32 || p.type == PlyType::Float64 || !keep) {
            double v;
            if (!scan_.numberAcrossLines(v)) return asciiError(e, i);
            if (keep) polygon_.push_back(std::fabs(v) < 9e18 ? static_cast<long long>(v) : -1);
          } else {
            long long v;
            if (!scan_.integerAcrossLines(v)) return asciiError(e, i);
            polygon_.push_back(v);
          }
        }
        havePolygon = havePolygon || keep;
      }
      if (havePolygon)
        if (auto s = addPolygon(i, line); !s.ok()) return s;
    }
    return Ok{};
  }

  Error asciiError(const PlyElement& e, std::uint64_t i) {
    if (scan_.atEnd()) return truncated(e, i);
    return lineError(path_, scan_.line(),
                     "expected a number in element '" + e.name + "' item " + std::to_string(i));
  }

  const std::filesystem::path& path_;
  const std::string& bytes_;
  TextScanner scan_;
  Format format_ = Format::Ascii;
  std::vector<PlyElement> elements_;
  std::size_t dataStart_ = 0;
  std::string textureName_;
  TextureCache textures_;
  Mesh mesh_;
  bool sawVertices_ = false;
  bool hasNormals_ = false;
  bool hasUv_ = false;
  std::vector<long long> polygon_;
};

}  // namespace

Result<Model> readPly(const std::filesystem::path& path, const std::string& bytes) {
  return PlyParser(path, bytes).run();
}

}  // namespace hlod::import
