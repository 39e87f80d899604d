// OBJ reader: v, vt, vn and f with every index form (v, v/t, v//n, v/t/n, negative = relative to
// the end), polygons fan-triangulated, one Mesh per material (usemtl), materials from mtllib (Kd,
// d/Tr, map_Kd relative to the OBJ folder). Vertices are shared per (v, vt, vn) tuple. Material
// libraries and textures are read only from inside the OBJ's folder. Objects (Model::objectRuns):
// each distinct pair of the current `o` and `g` names is one, faces before either belong to the
// first; a file with neither statement has no runs (it is one object).
#include <algorithm>
#include <cassert>
#include <cmath>
#include <map>
#include <tuple>
#include <unordered_map>

#include "hlod/import/InsideFolder.h"
#include "import/ImportUtil.h"

namespace hlod::import {
namespace {

struct Material {
  glm::vec4 baseColor{0.8f, 0.8f, 0.8f, 1.0f};
  std::string texture;
};

struct Corner {
  std::int64_t v = -1, t = -1, n = -1;  // 0-based, -1 when absent
  bool operator==(const Corner& o) const { return v == o.v && t == o.t && n == o.n; }
};

struct CornerHash {
  std::size_t operator()(const Corner& c) const {
    return static_cast<std::size_t>(
        mixBits(static_cast<std::uint64_t>(c.v) ^
                mixBits(static_cast<std::uint64_t>(c.t) * 31 + static_cast<std::uint64_t>(c.n))));
  }
};

struct Group {
  std::string material;
  Mesh mesh;
  FlatIndexMap<Corner, CornerHash> corners;
  bool anyTexCoord = false;
  bool missingNormal = false;
  std::vector<ObjectRun> runs;  // their mesh is set when the group becomes a Mesh
};

// Skips the options of a map_Kd line ("-s 1 1 1", "-clamp on", ...): the rest is the file name.
std::string textureName(std::string_view rest) {
  TextScanner scan(rest);
  while (true) {
    scan.skipBlanks();
    if (scan.atEnd() || *scan.position() != '-') break;
    std::string_view opt = scan.token();
    double d;
    if (opt == "-imfchan" || opt == "-type" || opt == "-clamp" || opt == "-blendu" ||
        opt == "-blendv" || opt == "-cc") {
      scan.token();
    } else {
      while (scan.number(d)) {
      }
    }
  }
  scan.skipBlanks();
  return std::string(scan.restOfLine());
}

void readMtl(const std::filesystem::path& objPath, std::string mtlName,
             std::unordered_map<std::string, Material>& out) {
  std::replace(mtlName.begin(), mtlName.end(), '\\', '/');  // written on Windows
  auto mtlPath = insideFolder(objPath.parent_path(), mtlName);
  if (!mtlPath) {
    warn(objPath, "material library not loaded: " + mtlPath.message());
    return;
  }
  auto bytes = readWholeFile(*mtlPath);
  if (!bytes.ok()) {
    warn(objPath, "material library not loaded (" + bytes.message() + ")");
    return;
  }
  TextScanner scan(*bytes);
  Material* current = nullptr;
  while (true) {
    scan.skipSpace('#');
    if (scan.atEnd()) break;
    std::string_view key = scan.token();
    if (key == "newmtl") {
      current = &out[std::string(scan.restOfLine())];
      continue;
    }
    if (current) {
      if (key == "Kd") {
        double r = 0.8, g = 0.8, b = 0.8;
        if (scan.number(r) && scan.number(g) && scan.number(b))
          current->baseColor = glm::vec4(static_cast<float>(r), static_cast<float>(g),
                                         static_cast<float>(b), current->baseColor.a);
      } else if (key == "d") {
        double d;
        if (scan.number(d)) current->baseColor.a = static_cast<float>(d);
      } else if (key == "Tr") {
        double tr;
        if (scan.number(tr)) current->baseColor.a = static_cast<float>(1.0 - tr);
      } else if (key == "map_Kd") {
        current->texture = textureName(scan.restOfLine());
        continue;
      }
    }
    scan.skipLine();
  }
}

class ObjParser {
 public:
  ObjParser(const std::filesystem::path& path, const std::string& bytes)
      : path_(path), scan_(bytes) {
    // A rough upper bound from the file size keeps reallocations few on big files.
    positions_.reserve(bytes.size() / 64);
    groups_.push_back(Group{});
    groupOf_[""] = 0;
  }

  Result<Model> run() {
    while (true) {
      scan_.skipSpace();
      if (scan_.atEnd()) break;
      const std::size_t line = scan_.line();
      std::string_view key = scan_.token();
      if (key == "v") {
        glm::dvec3 p;
        if (!scan_.number(p.x) || !scan_.number(p.y) || !scan_.number(p.z))
          return lineError(path_, line, "expected three vertex coordinates");
        positions_.push_back(p);
      } else if (key == "vt") {
        double u, v = 0.0;
        if (!scan_.number(u)) return lineError(path_, line, "expected a texture coordinate");
        (void)scan_.number(v);
        // OBJ has v up; glTF (ours) has v down.
        texCoords_.emplace_back(static_cast<float>(u), static_cast<float>(1.0 - v));
      } else if (key == "vn") {
        double x, y, z;
        if (!scan_.number(x) || !scan_.number(y) || !scan_.number(z))
          return lineError(path_, line, "expected three normal components");
        normals_.emplace_back(glm::dvec3(x, y, z));
      } else if (key == "f") {
        if (auto s = face(line); !s.ok()) return s.error();
        continue;
      } else if (key == "usemtl") {
        useMaterial(std::string(scan_.restOfLine()));
        continue;
      } else if (key == "mtllib") {
        readMtl(path_, std::string(scan_.restOfLine()), materials_);
        continue;
      } else if (key == "o" || key == "g") {
        (key == "o" ? objectName_ : groupName_) = std::string(scan_.restOfLine());
        auto [it, fresh] = objectIds_.try_emplace(objectName_ + '\n' + groupName_,
                                                  std::uint32_t(objectIds_.size()));
        object_ = it->second;
        namedObjects_ = true;
        continue;
      }
      // Other statements (s, l, p, comments, ...) carry nothing we draw.
      scan_.skipLine();
    }
    return finish();
  }

 private:
  // By a map from name to group: a search of the groups for each usemtl made 100,000 materials
  // quadratic (47 s to render such a file).
  void useMaterial(const std::string& name) {
    if (auto it = groupOf_.find(name); it != groupOf_.end()) {
      current_ = it->second;
      return;
    }
    // Faces before any usemtl use group 0 with the empty material: reuse it when still unused.
    if (groups_.size() == 1 && groups_[0].material.empty() && groups_[0].mesh.indices.empty()) {
      groupOf_.erase(groups_[0].material);
      groups_[0].material = name;
      groupOf_[name] = 0;
      current_ = 0;
      return;
    }
    groups_.push_back(Group{});
    groups_.back().material = name;
    current_ = groups_.size() - 1;
    groupOf_[name] = current_;
  }

  // Resolves an OBJ index (1-based, or negative from the end) to 0-based; -2 when invalid.
  // Compared without negating: -LLONG_MIN does not exist.
  static std::int64_t resolve(long long idx, std::size_t count) {
    const auto n = static_cast<long long>(count);  // count < 2^63: it counts vectors' elements
    if (idx > 0) return idx <= n ? idx - 1 : -2;
    if (idx < 0) return idx >= -n ? n + idx : -2;
    return -2;
  }

  Status face(std::size_t line) {
    polygon_.clear();
    while (!scan_.atEol()) {
      std::string_view tok = scan_.token();
      const char* p = tok.data();
      const char* end = p + tok.size();
      long long raw[3] = {0, 0, 0};
      bool present[3] = {false, false, false};
      for (int part = 0; part < 3; ++part) {
        if (p < end && *p != '/') {
          if (*p == '+') ++p;
          auto [q, ec] = std::from_chars(p, end, raw[part]);
          if (ec != std::errc())
            return lineError(path_, line, "bad face corner '" + std::string(tok) + "'");
          present[part] = true;
          p = q;
        }
        if (p < end && *p == '/')
          ++p;
        else
          break;
      }
      if (p != end || !present[0])
        return lineError(path_, line, "bad face corner '" + std::string(tok) + "'");
      Corner c;
      c.v = resolve(raw[0], positions_.size());
      if (c.v < 0)
        return lineError(path_, line,
                         "face index " + std::to_string(raw[0]) + " out of range (" +
                             std::to_string(positions_.size()) + " vertices)");
      if (present[1]) {
        c.t = resolve(raw[1], texCoords_.size());
        if (c.t < 0)
          return lineError(path_, line,
                           "texture coordinate index " + std::to_string(raw[1]) +
                               " out of range (" + std::to_string(texCoords_.size()) + ")");
      }
      if (present[2]) {
        c.n = resolve(raw[2], normals_.size());
        if (c.n < 0)
          return lineError(path_, line,
                           "normal index " + std::to_string(raw[2]) + " out of range (" +
                               std::to_string(normals_.size()) + ")");
      }
      polygon_.push_back(vertexOf(c));
    }
    scan_.skipLine();
    // The polygon's triangles extend the group's last run when it is the current object's.
    if (polygon_.size() >= 3) {
      std::vector<ObjectRun>& runs = groups_[current_].runs;
      if (runs.empty() || runs.back().object != object_)
        runs.push_back({object_, 0, std::uint32_t(groups_[current_].mesh.indices.size() / 3), 0});
      runs.back().triangleCount += std::uint32_t(polygon_.size() - 2);
    }
    for (std::size_t k = 1; k + 1 < polygon_.size(); ++k) {
      auto& idx = groups_[current_].mesh.indices;
      idx.push_back(polygon_[0]);
      idx.push_back(polygon_[k]);
      idx.push_back(polygon_[k + 1]);
    }
    return Ok{};
  }

  // c's indices are resolved (face() refused the others).
  std::uint32_t vertexOf(const Corner& c) {
    assert(c.v >= 0 && static_cast<std::size_t>(c.v) < positions_.size());
    assert(c.t < static_cast<std::int64_t>(texCoords_.size()));
    assert(c.n < static_cast<std::int64_t>(normals_.size()));
    Group& g = groups_[current_];
    auto [index, inserted] =
        g.corners.insert(c, static_cast<std::uint32_t>(g.mesh.positions.size()));
    if (inserted) {
      g.mesh.positions.push_back(positions_[static_cast<std::size_t>(c.v)]);
      g.mesh.texCoords.push_back(c.t >= 0 ? texCoords_[static_cast<std::size_t>(c.t)]
                                          : glm::vec2(0.0f));
      g.anyTexCoord = g.anyTexCoord || c.t >= 0;
      g.mesh.normals.push_back(c.n >= 0 ? normals_[static_cast<std::size_t>(c.n)]
                                        : glm::vec3(0.0f));
      g.missingNormal = g.missingNormal || c.n < 0;
    }
    return index;
  }

  Result<Model> finish() {
    Model model;
    TextureCache textures;
    // Materials that draw alike (colour and texture) become one mesh: a file whose 100,000
    // usemtl names repeat three colours drew 100,000 meshes, one draw call each.
    std::map<std::tuple<float, float, float, float, const Image*>, std::size_t> meshOf;
    for (auto& g : groups_) {
      if (g.mesh.indices.empty()) continue;
      if (!g.anyTexCoord) g.mesh.texCoords.clear();
      // Partly missing normals would be zero vectors: let toLocal compute them all instead.
      if (g.missingNormal) g.mesh.normals.clear();
      g.mesh.name = g.material;
      if (auto it = materials_.find(g.material); it != materials_.end()) {
        g.mesh.baseColor = it->second.baseColor;
        if (!it->second.texture.empty()) {
          g.mesh.texture = textures.load(path_, it->second.texture);
          if (g.mesh.texture) g.mesh.baseColor = glm::vec4(1.0f, 1.0f, 1.0f, g.mesh.baseColor.a);
        }
      }
      g.corners.clear();
      const glm::vec4& c = g.mesh.baseColor;
      const auto [at, fresh] =
          meshOf.try_emplace({c.r, c.g, c.b, c.a, g.mesh.texture.get()}, model.meshes.size());
      // An object's runs follow its triangles into the mesh of their material.
      const auto firstTriangle =
          fresh ? 0u : static_cast<std::uint32_t>(model.meshes[at->second].indices.size() / 3);
      if (namedObjects_)
        for (ObjectRun r : g.runs) {
          r.mesh = std::uint32_t(at->second);
          r.firstTriangle += firstTriangle;
          model.objectRuns.push_back(r);
        }
      if (fresh)
        model.meshes.push_back(std::move(g.mesh));
      else
        append(model.meshes[at->second], std::move(g.mesh));
    }
    return model;
  }

  // Appends b's triangles to a (of the same material): attributes one of them lacks are
  // padded (texture coordinates) or left to toLocal (normals).
  static void append(Mesh& a, Mesh b) {
    const auto base = static_cast<std::uint32_t>(a.positions.size());
    const bool texCoords = !a.texCoords.empty() || !b.texCoords.empty();
    if (texCoords) {
      a.texCoords.resize(a.positions.size(), glm::vec2(0.0f));
      b.texCoords.resize(b.positions.size(), glm::vec2(0.0f));
    }
    if (a.normals.empty() || b.normals.empty()) {
      a.normals.clear();
      b.normals.clear();
    }
    a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
    if (texCoords) a.texCoords.insert(a.texCoords.end(), b.texCoords.begin(), b.texCoords.end());
    a.normals.insert(a.normals.end(), b.normals.begin(), b.normals.end());
    a.indices.reserve(a.indices.size() + b.indices.size());
    for (std::uint32_t i : b.indices) a.indices.push_back(base + i);
  }

  const std::filesystem::path& path_;
  TextScanner scan_;
  std::vector<glm::dvec3> positions_;
  std::vector<glm::vec2> texCoords_;
  std::vector<glm::vec3> normals_;
  std::vector<Group> groups_;
  std::unordered_map<std::string, std::size_t> groupOf_;  // material name -> its group
  std::size_t current_ = 0;
  std::vector<std::uint32_t> polygon_;
  std::unordered_map<std::string, Material> materials_;
  // The current object (`o`, `g`): ids by the pair of names, the first for faces before either.
  std::string objectName_, groupName_;
  std::unordered_map<std::string, std::uint32_t> objectIds_{{"\n", 0}};
  std::uint32_t object_ = 0;
  bool namedObjects_ = false;
};

}  // namespace

Result<Model> readObj(const std::filesystem::path& path, const std::string& bytes) {
  return ObjParser(path, bytes).run();
}

}  // namespace hlod::import
