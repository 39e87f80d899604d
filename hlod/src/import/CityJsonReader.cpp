// CityJSON reader (0.x, 1.x, 2.0; https://www.cityjson.org/specs/): the surfaces of every city
// object at the chosen level of detail, triangulated by earClip, one Mesh per colour (material
// diffuseColor, else the semantic palette of CityJsonPalette.h).
//
// Versions: 1.1 and 2.0 require "transform" {scale, translate} and integer vertices; 1.0 and
// 0.x may have float vertices without it. 0.x writes semantics as an array parallel to the
// boundaries ([{"type": ...}] per surface), later versions as {surfaces, values}. "lod" is a
// number in 0.x and 1.0, a string ("2.2") since 1.1.
//
// Coordinates: projected ones are kept (doubles); geographic ones (EPSG latitude, longitude,
// height) and geocentric ones go into an east-north-up frame at the centre of the data.
//
// Every boundary array is checked for its nesting and every vertex index for its range before it
// is used; an error names the file and the JSON path of the problem.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <set>

#include <nlohmann/json.hpp>

#include "hlod/JsonDepth.h"
#include "hlod/geodesy/Epsg.h"
#include "hlod/geodesy/Geodesy.h"
#include "hlod/import/CityJsonPalette.h"
#include "hlod/import/EarClip.h"
#include "hlod/import/Import.h"
#include "import/CityJsonFrame.h"
#include "import/ImportUtil.h"

namespace hlod::import {
namespace {

using nlohmann::json;

// The deepest CityJSON nests is about 10 (a MultiSolid's rings); attributes may go deeper, but
// not this deep.
constexpr std::size_t kMaxCityJsonDepth = 128;

enum class GeomType { MultiSurface, CompositeSurface, Solid, MultiSolid, CompositeSolid };

// Levels of boundary nesting above a surface: MultiSurface [surface], Solid [shell][surface],
// MultiSolid [solid][shell][surface].
int levelsAbove(GeomType t) {
  switch (t) {
    case GeomType::MultiSurface:
    case GeomType::CompositeSurface:
      return 1;
    case GeomType::Solid:
      return 2;
    default:
      return 3;
  }
}

std::optional<GeomType> surfaceType(const std::string& type) {
  if (type == "MultiSurface") return GeomType::MultiSurface;
  if (type == "CompositeSurface") return GeomType::CompositeSurface;
  if (type == "Solid") return GeomType::Solid;
  if (type == "MultiSolid") return GeomType::MultiSolid;
  if (type == "CompositeSolid") return GeomType::CompositeSolid;
  return std::nullopt;
}

std::string kindOf(const json& j) {
  switch (j.type()) {
    case json::value_t::null:
      return "null";
    case json::value_t::object:
      return "an object";
    case json::value_t::array:
      return "an array";
    case json::value_t::string:
      return "a string";
    case json::value_t::boolean:
      return "a boolean";
    default:
      return "a number";
  }
}

std::string fmtNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.15g", v);
  return buf;
}

// A city object's id as it appears in an error: printable, quoted, at most 60 characters.
std::string objectPath(const std::string& id) {
  std::string safe;
  for (unsigned char c : id.substr(0, 60)) safe += (c < 0x20 || c == '"' || c == 0x7f) ? '?' : c;
  return "CityObjects[\"" + safe + (id.size() > 60 ? "...\"]" : "\"]");
}

// A level of detail: its text as the file writes it, and its value for ordering.
struct Lod {
  std::string text;
  double value = -1.0;
};

std::optional<Lod> readLod(const json& g) {
  const auto it = g.find("lod");
  if (it == g.end()) return std::nullopt;
  Lod lod;
  if (it->is_number()) {
    lod.value = it->get<double>();
    lod.text = fmtNumber(lod.value);
  } else if (it->is_string()) {
    lod.text = it->get<std::string>();
    char* end = nullptr;
    lod.value = std::strtod(lod.text.c_str(), &end);
    if (end == lod.text.c_str()) lod.value = -1.0;
  } else {
    return std::nullopt;
  }
  return lod;
}

bool lodMatches(const Lod& lod, const std::string& wanted) {
  if (lod.text == wanted) return true;
  char* end = nullptr;
  const double v = std::strtod(wanted.c_str(), &end);
  return end != wanted.c_str() && *end == '\0' && v == lod.value;
}

// One triangulated polygon before it joins its mesh: a shell is flipped as a whole when its
// volume says it is wound inwards.
struct Polygon {
  std::array<std::size_t, 3> at{};  // solid, shell, surface: where semantics and materials are
  std::size_t bucket = 0;
  glm::dvec3 normal{0.0};
  std::vector<glm::dvec3> points;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

struct Bucket {
  std::string key;  // in Reader::bucketIndex_
  std::string name;
  glm::vec4 colour{1.0f};
  bool oneSided = false;
};

// How the vertices of one geometry are found: the file's vertices, or a template's placed by an
// instance (transformationMatrix, then the reference point).
struct VertexSource {
  std::size_t count = 0;
  std::function<glm::dvec3(std::uint32_t)> at;
};

class Reader {
 public:
  Reader(const std::filesystem::path& path, const json& root, const ImportOptions& options)
      : path_(path), root_(root), options_(options) {}

  Result<Model> run();

 private:
  Error fail(const std::string& where, const std::string& what) const {
    return fileError(path_, where + ": " + what);
  }
  Status readVersion();
  Status readVertices();
  Status readCrs();
  Status readMaterials();
  Status readObject(const std::string& id, const json& object);
  Status readGeometry(const std::string& where, const json& g, const VertexSource& vertices);
  Status readInstance(const std::string& where, const json& g);
  Result<std::vector<std::vector<std::uint32_t>>> readSurface(const std::string& where,
                                                              const json& surface,
                                                              std::size_t vertexCount);
  std::size_t bucketFor(const json& g, const std::array<std::size_t, 3>& at, int levels,
                        const glm::dvec3& normal);
  std::size_t oneSidedTwin(std::size_t bucket);
  Status readTemplateVertices();
  void emit(std::vector<Polygon>& polygons);

  const std::filesystem::path& path_;
  const json& root_;
  const ImportOptions& options_;
  Model model_;
  int major_ = 0, minor_ = 0;
  std::vector<glm::dvec3> sourceVertices_;  // as the file means them (transform applied)
  std::vector<glm::dvec3> vertices_;        // in the model's frame
  std::optional<std::vector<glm::dvec3>> templateVertices_;  // read at the first instance
  CityJsonFrame frame_;
  std::vector<glm::vec4> materialColours_;  // per appearance material; alpha 0: none given
  std::vector<std::string> materialNames_;
  std::vector<Bucket> buckets_;
  std::map<std::string, std::size_t> bucketIndex_;
  std::vector<std::size_t> meshOf_;   // bucket -> mesh in model_
  std::uint32_t object_ = 0;          // the city object being read (its number in objectRuns)
  std::vector<std::size_t> lastRun_;  // mesh -> its last entry in model_.objectRuns
  std::uint64_t triangles_ = 0;
  std::size_t degenerate_ = 0, partial_ = 0, droppedHoles_ = 0, openShells_ = 0, flipped_ = 0;
  std::size_t textured_ = 0, skippedTypes_ = 0, relabelled_ = 0;
  std::set<std::string> lodsChosen_;
};

Status Reader::readVersion() {
  const auto v = root_.find("version");
  if (v == root_.end() || !v->is_string()) return fail("version", "missing (or not a string)");
  std::string text = v->get<std::string>();
  // 0.x wrote a URL: "http://www.cityjson.org/version/0.2".
  const std::size_t slash = text.rfind('/');
  if (slash != std::string::npos) text = text.substr(slash + 1);
  char* end = nullptr;
  const long major = std::strtol(text.c_str(), &end, 10);
  if (end == text.c_str() || *end != '.' || major < 0 || major > 2)
    return fail("version", "unsupported CityJSON version \"" + v->get<std::string>().substr(0, 40) +
                               "\" (0.x, 1.x and 2.0 are read)");
  major_ = int(major);
  minor_ = int(std::strtol(end + 1, nullptr, 10));
  model_.format = "CityJSON " + text;
  return Ok{};
}

Status Reader::readVertices() {
  glm::dvec3 scale(1.0), translate(0.0);
  const auto t = root_.find("transform");
  const bool required = major_ > 1 || (major_ == 1 && minor_ >= 1);
  if (t == root_.end()) {
    if (required)
      return fail("transform", "missing (CityJSON " + std::to_string(major_) + "." +
                                   std::to_string(minor_) + " requires it)");
  } else {
    if (!t->is_object()) return fail("transform", "expected an object, found " + kindOf(*t));
    for (const char* key : {"scale", "translate"}) {
      const auto a = t->find(key);
      if (a == t->end() || !a->is_array() || a->size() != 3)
        return fail(std::string("transform.") + key, "expected an array of 3 numbers");
      for (int c = 0; c < 3; ++c) {
        const json& x = (*a)[std::size_t(c)];
        if (!x.is_number() || !std::isfinite(x.get<double>()))
          return fail(std::string("transform.") + key + "[" + std::to_string(c) + "]",
                      "not a finite number");
        (key[0] == 's' ? scale : translate)[c] = x.get<double>();
      }
    }
  }
  const auto v = root_.find("vertices");
  if (v == root_.end() || !v->is_array()) return fail("vertices", "missing (or not an array)");
  if (v->size() > 0xfffffff0u)
    return fail("vertices", std::to_string(v->size()) + " vertices, more than hlodr indexes");
  sourceVertices_.resize(v->size());
  for (std::size_t i = 0; i < v->size(); ++i) {
    const json& p = (*v)[i];
    if (!p.is_array() || p.size() != 3)
      return fail("vertices[" + std::to_string(i) + "]", "expected an array of 3 numbers");
    for (int c = 0; c < 3; ++c) {
      const json& x = p[std::size_t(c)];
      if (!x.is_number())
        return fail("vertices[" + std::to_string(i) + "][" + std::to_string(c) + "]",
                    "expected a number, found " + kindOf(x));
      const double value = x.get<double>() * scale[c] + translate[c];
      if (!std::isfinite(value))
        return fail("vertices[" + std::to_string(i) + "][" + std::to_string(c) + "]",
                    "coordinate is not finite");
      sourceVertices_[i][c] = value;
    }
  }
  return Ok{};
}

Status Reader::readCrs() {
  int epsg = 0;
  if (const auto m = root_.find("metadata"); m != root_.end() && m->is_object()) {
    if (const auto r = m->find("referenceSystem"); r != m->end() && r->is_string()) {
      epsg = epsgFromReference(r->get<std::string>());
      if (epsg == 0)
        warn(path_, "metadata.referenceSystem \"" + r->get<std::string>().substr(0, 80) +
                        "\" names no EPSG code: coordinates kept as they are");
    } else if (const auto c = m->find("crs"); c != m->end() && c->is_object()) {
      // 0.x: "crs": {"epsg": 7415}
      if (const auto e = c->find("epsg"); e != c->end() && e->is_number_integer())
        epsg = int(std::clamp<std::int64_t>(e->get<std::int64_t>(), 0, 999999));
    }
  }
  Aabb box;
  for (const auto& p : sourceVertices_) box.extend(p);
  auto frame = CityJsonFrame::make(epsg, box, model_.crs);
  if (!frame) return frame.error();
  frame_ = std::move(*frame);
  if (frame_.lonLat())
    warn(path_, "coordinates read as longitude, latitude: the first one goes past 90 degrees");
  vertices_.resize(sourceVertices_.size());
  for (std::size_t i = 0; i < sourceVertices_.size(); ++i) {
    const auto v = frame_.toModel(sourceVertices_[i]);
    if (!v)
      return fail("vertices[" + std::to_string(i) + "]",
                  "latitude past 90 degrees in geographic " + describeEpsg(epsg));
    vertices_[i] = *v;
  }
  return Ok{};
}

Status Reader::readMaterials() {
  const auto a = root_.find("appearance");
  if (a == root_.end() || !a->is_object()) return Ok{};
  const auto m = a->find("materials");
  if (m == a->end() || !m->is_array()) return Ok{};
  for (std::size_t i = 0; i < m->size(); ++i) {
    const json& mat = (*m)[i];
    glm::vec4 colour(0.0f);  // alpha 0: the material gives no colour, semantics decide
    std::string name = "material " + std::to_string(i);
    if (mat.is_object()) {
      if (auto n = mat.find("name"); n != mat.end() && n->is_string())
        name = "material " + n->get<std::string>().substr(0, 60);
      if (auto d = mat.find("diffuseColor"); d != mat.end() && d->is_array() && d->size() == 3) {
        bool ok = true;
        for (const auto& c : *d) ok = ok && c.is_number() && std::isfinite(c.get<double>());
        if (ok) {
          for (int c = 0; c < 3; ++c)
            colour[c] = float(std::clamp((*d)[std::size_t(c)].get<double>(), 0.0, 1.0));
          colour.a = 1.0f;
          if (auto t = mat.find("transparency"); t != mat.end() && t->is_number())
            colour.a = float(1.0 - std::clamp(t->get<double>(), 0.0, 1.0));
        }
      }
    }
    materialColours_.push_back(colour);
    materialNames_.push_back(name);
  }
  return Ok{};
}

// The element of a nested semantics/material array at surface position `at` (solid, shell,
// surface; the first 3 - levels unused); null when any level is missing or null.
const json* nestedAt(const json* node, const std::array<std::size_t, 3>& at, int levels) {
  for (int l = 3 - levels; l < 3 && node; ++l) {
    if (!node->is_array() || at[std::size_t(l)] >= node->size()) return nullptr;
    node = &(*node)[at[std::size_t(l)]];
  }
  return node && !node->is_null() ? node : nullptr;
}

std::size_t Reader::bucketFor(const json& g, const std::array<std::size_t, 3>& at, int levels,
                              const glm::dvec3& normal) {
  std::string key, name;
  glm::vec4 colour(0.0f);
  // A material's diffuse colour first (the first theme, by name).
  if (const auto m = g.find("material"); m != g.end() && m->is_object() && !m->empty()) {
    const json& theme = m->begin().value();
    const json* idx = nullptr;
    if (theme.is_object()) {
      if (auto v = theme.find("value"); v != theme.end())
        idx = &*v;
      else if (auto vs = theme.find("values"); vs != theme.end())
        idx = nestedAt(&*vs, at, levels);
    }
    if (idx && idx->is_number_unsigned() && idx->get<std::uint64_t>() < materialColours_.size()) {
      const std::size_t i = std::size_t(idx->get<std::uint64_t>());
      if (materialColours_[i].a > 0.0f) {
        key = "m" + std::to_string(i);
        name = materialNames_[i];
        colour = materialColours_[i];
      }
    }
  }
  if (key.empty()) {
    SurfaceClass c = SurfaceClass::Other;
    bool labelled = false;
    if (const auto s = g.find("semantics"); s != g.end()) {
      const json* surface = nullptr;
      if (s->is_array()) {
        surface = nestedAt(&*s, at, levels);  // 0.x: parallel to the boundaries
      } else if (s->is_object()) {
        const auto surfaces = s->find("surfaces");
        const auto values = s->find("values");
        if (surfaces != s->end() && surfaces->is_array() && values != s->end()) {
          const json* idx = nestedAt(&*values, at, levels);
          if (idx && idx->is_number_unsigned() && idx->get<std::uint64_t>() < surfaces->size())
            surface = &(*surfaces)[std::size_t(idx->get<std::uint64_t>())];
        }
      }
      if (surface && surface->is_object())
        if (auto t = surface->find("type"); t != surface->end() && t->is_string()) {
          c = surfaceClass(t->get_ref<const std::string&>());
          labelled = true;
        }
    }
    // Without semantics, and where a "wall" is tilted more than 30 degrees from vertical (some
    // data, Rotterdam's 0.2 example among it, labels every surface a wall), the normal as wound
    // tells a roof from the ground.
    if ((!labelled || c == SurfaceClass::Wall) && std::abs(normal.z) > 0.5) {
      if (labelled) ++relabelled_;
      c = normal.z > 0.0 ? SurfaceClass::Roof : SurfaceClass::Ground;
    } else if (!labelled && c == SurfaceClass::Other) {
      c = SurfaceClass::Wall;
    }
    key = std::string("s") + surfaceClassName(c);
    name = surfaceClassName(c);
    colour = surfaceColour(c);
  }
  const auto [it, inserted] = bucketIndex_.emplace(key, buckets_.size());
  if (inserted) buckets_.push_back({key, name, colour, false});
  return it->second;
}

// The same colour in a mesh of its own whose back faces may be culled.
std::size_t Reader::oneSidedTwin(std::size_t bucket) {
  const Bucket two = buckets_[bucket];
  const auto [it, inserted] = bucketIndex_.emplace(two.key + "+1", buckets_.size());
  if (inserted) buckets_.push_back({two.key + "+1", two.name, two.colour, true});
  return it->second;
}

Result<std::vector<std::vector<std::uint32_t>>> Reader::readSurface(const std::string& where,
                                                                    const json& surface,
                                                                    std::size_t vertexCount) {
  if (!surface.is_array() || surface.empty())
    return fail(where, "expected a surface (an array of rings), found " +
                           (surface.is_array() ? std::string("an empty array") : kindOf(surface)));
  std::vector<std::vector<std::uint32_t>> rings(surface.size());
  for (std::size_t r = 0; r < surface.size(); ++r) {
    const json& ring = surface[r];
    const std::string at = where + "[" + std::to_string(r) + "]";
    if (!ring.is_array())
      return fail(at, "expected a ring (an array of vertex indices), found " + kindOf(ring));
    rings[r].reserve(ring.size());
    for (const json& i : ring) {
      if (!i.is_number_integer() || i.is_number_float())
        return fail(at, i.is_number() ? "vertex index " + fmtNumber(i.get<double>()) +
                                            " is not a whole number"
                                      : "expected a vertex index, found " + kindOf(i) +
                                            " (boundaries nested too deep for this type?)");
      const std::int64_t v = i.get<std::int64_t>();
      if (v < 0 || std::uint64_t(v) >= vertexCount)
        return fail(at, "vertex index " + std::to_string(v) + " out of range (" +
                            std::to_string(vertexCount) + " vertices)");
      rings[r].push_back(std::uint32_t(v));
    }
  }
  return rings;
}

// Directed ring edges; a shell is closed and consistently wound when each edge a->b meets its
// twin b->a as often as itself. Only then may its back faces be culled.
bool closedShell(std::vector<std::uint64_t> edges) {
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    const std::uint64_t twin = (edges[i] << 32) | (edges[i] >> 32);
    const auto range = std::equal_range(edges.begin(), edges.end(), twin);
    if (std::size_t(range.second - range.first) != j - i) return false;
    i = j;
  }
  return !edges.empty();
}

Status Reader::readGeometry(const std::string& where, const json& g, const VertexSource& vertices) {
  const auto typeIt = g.find("type");
  const std::string type =
      typeIt != g.end() && typeIt->is_string() ? typeIt->get<std::string>() : std::string();
  const auto t = surfaceType(type);
  if (!t) {
    if (type != "MultiPoint" && type != "MultiLineString") ++skippedTypes_;
    return Ok{};
  }
  if (g.contains("texture")) ++textured_;
  const auto b = g.find("boundaries");
  if (b == g.end() || !b->is_array())
    return fail(where + ".boundaries", "missing (or not an array)");
  const int levels = levelsAbove(*t);
  const bool solids = levels >= 2;
  // Shells: the unit of orientation. A MultiSurface is one "shell" that is never flipped.
  std::vector<std::pair<std::array<std::size_t, 2>, const json*>> shells;
  if (levels == 1) {
    shells.push_back({{0, 0}, &*b});
  } else if (levels == 2) {
    for (std::size_t h = 0; h < b->size(); ++h) shells.push_back({{0, h}, &(*b)[h]});
  } else {
    for (std::size_t s = 0; s < b->size(); ++s) {
      const json& solid = (*b)[s];
      if (!solid.is_array())
        return fail(where + ".boundaries[" + std::to_string(s) + "]",
                    "expected a solid (an array of shells), found " + kindOf(solid));
      for (std::size_t h = 0; h < solid.size(); ++h) shells.push_back({{s, h}, &solid[h]});
    }
  }
  std::vector<Polygon> polygons;
  std::vector<std::uint64_t> edges;
  for (const auto& [index, shellJson] : shells) {
    std::string shellWhere = where + ".boundaries";
    if (levels == 3) shellWhere += "[" + std::to_string(index[0]) + "]";
    if (levels >= 2) shellWhere += "[" + std::to_string(index[1]) + "]";
    const json& shell = *shellJson;
    if (!shell.is_array())
      return fail(shellWhere, "expected " +
                                  std::string(levels == 1 ? "an array of surfaces"
                                                          : "a shell (an array of "
                                                            "surfaces)") +
                                  ", found " + kindOf(shell));
    polygons.clear();
    edges.clear();
    for (std::size_t k = 0; k < shell.size(); ++k) {
      const std::string surfaceWhere = shellWhere + "[" + std::to_string(k) + "]";
      auto rings = readSurface(surfaceWhere, shell[k], vertices.count);
      if (!rings) return rings.error();
      std::vector<std::vector<glm::dvec3>> points(rings->size());
      for (std::size_t r = 0; r < rings->size(); ++r) {
        const auto& ring = (*rings)[r];
        for (std::size_t i = 0; i < ring.size(); ++i) {
          points[r].push_back(vertices.at(ring[i]));
          const std::uint32_t next = ring[(i + 1) % ring.size()];
          if (solids && ring[i] != next) edges.push_back((std::uint64_t(ring[i]) << 32) | next);
        }
      }
      EarClipResult tri = earClip(points);
      droppedHoles_ += tri.droppedHoles;
      if (tri.status == EarClipStatus::Degenerate) {
        ++degenerate_;
        continue;
      }
      if (tri.status == EarClipStatus::Partial) ++partial_;
      triangles_ += tri.triangles.size();
      if (triangles_ > kMaxCityJsonTriangles)
        return fail(surfaceWhere, "more than " + std::to_string(kMaxCityJsonTriangles) +
                                      " triangles in the model");
      Polygon poly;
      poly.normal = newellNormal(points[0]);
      const double len = glm::length(poly.normal);
      poly.normal = len > 0.0 ? poly.normal / len : glm::dvec3(0, 0, 1);
      for (auto& ring : points) poly.points.insert(poly.points.end(), ring.begin(), ring.end());
      poly.triangles = std::move(tri.triangles);
      poly.at = {index[0], index[1], k};
      polygons.push_back(std::move(poly));
    }
    bool closed = false;
    if (solids && !polygons.empty()) {
      // The exterior shell (the first) should enclose positive volume, interior shells
      // (cavities) negative; real data gets this wrong often enough to check.
      const glm::dvec3 o = polygons[0].points[0];
      double volume = 0.0;
      for (const auto& p : polygons)
        for (const auto& tr : p.triangles)
          volume +=
              glm::dot(p.points[tr[0]] - o, glm::cross(p.points[tr[1]] - o, p.points[tr[2]] - o));
      const bool exterior = index[1] == 0;
      if ((exterior && volume < 0.0) || (!exterior && volume > 0.0)) {
        ++flipped_;
        for (auto& p : polygons) {
          p.normal = -p.normal;
          for (auto& tr : p.triangles) std::swap(tr[1], tr[2]);
        }
      }
      closed = closedShell(edges);
      if (!closed) ++openShells_;
    }
    // Coloured once the winding is settled: the normal may decide between roof and ground.
    for (auto& p : polygons) {
      p.bucket = bucketFor(g, p.at, levels, p.normal);
      if (closed) p.bucket = oneSidedTwin(p.bucket);
    }
    emit(polygons);
  }
  return Ok{};
}

void Reader::emit(std::vector<Polygon>& polygons) {
  for (auto& p : polygons) {
    if (meshOf_.size() < buckets_.size()) meshOf_.resize(buckets_.size(), SIZE_MAX);
    std::size_t& m = meshOf_[p.bucket];
    if (m == SIZE_MAX) {
      m = model_.meshes.size();
      Mesh mesh;
      const Bucket& b = buckets_[p.bucket];
      mesh.name = b.name + (b.oneSided ? " (closed solids)" : "");
      mesh.baseColor = b.colour;
      mesh.oneSided = b.oneSided;
      model_.meshes.push_back(std::move(mesh));
    }
    Mesh& mesh = model_.meshes[m];
    // The object's triangles in this mesh are one run: objects are read one after another.
    if (lastRun_.size() <= m) lastRun_.resize(m + 1, SIZE_MAX);
    if (lastRun_[m] == SIZE_MAX || model_.objectRuns[lastRun_[m]].object != object_) {
      lastRun_[m] = model_.objectRuns.size();
      model_.objectRuns.push_back(
          {object_, std::uint32_t(m), std::uint32_t(mesh.triangleCount()), 0});
    }
    model_.objectRuns[lastRun_[m]].triangleCount += std::uint32_t(p.triangles.size());
    // Vertices of their own per polygon: faces of a building meet at sharp edges, and a vertex
    // shared across them would smooth its normal.
    const auto base = std::uint32_t(mesh.positions.size());
    const glm::vec3 n(p.normal);
    for (const auto& q : p.points) {
      mesh.positions.push_back(q);
      mesh.normals.push_back(n);
    }
    for (const auto& tr : p.triangles)
      for (auto i : tr) mesh.indices.push_back(base + i);
  }
}

// Template vertices are real coordinates (no transform), read once.
Status Reader::readTemplateVertices() {
  if (templateVertices_) return Ok{};
  const json& tv = root_.at("geometry-templates").at("vertices-templates");
  std::vector<glm::dvec3> local(tv.size());
  for (std::size_t i = 0; i < tv.size(); ++i) {
    const json& p = tv[i];
    if (!p.is_array() || p.size() != 3 || !p[0].is_number() || !p[1].is_number() ||
        !p[2].is_number())
      return fail("geometry-templates.vertices-templates[" + std::to_string(i) + "]",
                  "expected an array of 3 numbers");
    local[i] = {p[0].get<double>(), p[1].get<double>(), p[2].get<double>()};
    if (!std::isfinite(local[i].x) || !std::isfinite(local[i].y) || !std::isfinite(local[i].z))
      return fail("geometry-templates.vertices-templates[" + std::to_string(i) + "]",
                  "coordinate is not finite");
  }
  templateVertices_ = std::move(local);
  return Ok{};
}

Status Reader::readInstance(const std::string& where, const json& g) {
  const auto templates = root_.find("geometry-templates");
  if (templates == root_.end() || !templates->is_object())
    return fail(where, "a GeometryInstance, but the file has no \"geometry-templates\"");
  const auto list = templates->find("templates");
  const auto tv = templates->find("vertices-templates");
  if (list == templates->end() || !list->is_array())
    return fail("geometry-templates.templates", "missing (or not an array)");
  if (tv == templates->end() || !tv->is_array())
    return fail("geometry-templates.vertices-templates", "missing (or not an array)");
  const auto ti = g.find("template");
  if (ti == g.end() || !ti->is_number_unsigned() || ti->get<std::uint64_t>() >= list->size())
    return fail(where + ".template",
                "not the index of one of the " + std::to_string(list->size()) + " templates");
  const json& tmpl = (*list)[std::size_t(ti->get<std::uint64_t>())];
  if (!tmpl.is_object()) return fail(where + ".template", "the template is not an object");
  const auto b = g.find("boundaries");
  if (b == g.end() || !b->is_array() || b->size() != 1 || !(*b)[0].is_number_unsigned())
    return fail(where + ".boundaries", "expected [reference point vertex index]");
  const std::uint64_t ref = (*b)[0].get<std::uint64_t>();
  if (ref >= sourceVertices_.size())
    return fail(where + ".boundaries", "vertex index " + std::to_string(ref) + " out of range (" +
                                           std::to_string(sourceVertices_.size()) + " vertices)");
  const auto mIt = g.find("transformationMatrix");
  if (mIt == g.end() || !mIt->is_array() || mIt->size() != 16)
    return fail(where + ".transformationMatrix", "expected an array of 16 numbers");
  glm::dmat4 matrix(1.0);
  for (std::size_t i = 0; i < 16; ++i) {
    const json& x = (*mIt)[i];
    if (!x.is_number() || !std::isfinite(x.get<double>()))
      return fail(where + ".transformationMatrix[" + std::to_string(i) + "]",
                  "not a finite number");
    matrix[int(i % 4)][int(i / 4)] = x.get<double>();  // the file is row-major, glm column-major
  }
  if (auto st = readTemplateVertices(); !st) return st;
  const std::vector<glm::dvec3>& local = *templateVertices_;
  const glm::dvec3 origin = sourceVertices_[ref];
  VertexSource source;
  source.count = local.size();
  source.at = [&](std::uint32_t i) {
    const glm::dvec4 q = matrix * glm::dvec4(local[i], 1.0);
    // Past the poles or not finite: NaN, which makes the surface one without area (skipped).
    return frame_.toModel(origin + glm::dvec3(q))
        .value_or(glm::dvec3(std::numeric_limits<double>::quiet_NaN()));
  };
  return readGeometry("geometry-templates.templates[" + std::to_string(ti->get<std::uint64_t>()) +
                          "] (placed by " + where + ")",
                      tmpl, source);
}

Status Reader::readObject(const std::string& id, const json& object) {
  const std::string where = objectPath(id);
  if (!object.is_object()) return fail(where, "expected an object, found " + kindOf(object));
  const auto geometry = object.find("geometry");
  if (geometry == object.end()) return Ok{};
  if (!geometry->is_array())
    return fail(where + ".geometry", "expected an array, found " + kindOf(*geometry));
  // The LoD of each geometry with surfaces (an instance has its template's, when it says none).
  std::vector<std::optional<Lod>> lods(geometry->size());
  const json* templates = nullptr;
  if (auto gt = root_.find("geometry-templates"); gt != root_.end() && gt->is_object())
    if (auto l = gt->find("templates"); l != gt->end() && l->is_array()) templates = &*l;
  std::optional<double> highest;
  for (std::size_t i = 0; i < geometry->size(); ++i) {
    const json& g = (*geometry)[i];
    if (!g.is_object())
      return fail(where + ".geometry[" + std::to_string(i) + "]",
                  "expected an object, found " + kindOf(g));
    const auto type = g.find("type");
    if (type == g.end() || !type->is_string())
      return fail(where + ".geometry[" + std::to_string(i) + "].type", "missing");
    const json* surfaces = &g;
    if (*type == "GeometryInstance") {
      const auto ti = g.find("template");
      if (!templates || ti == g.end() || !ti->is_number_unsigned() ||
          ti->get<std::uint64_t>() >= templates->size())
        return fail(where + ".geometry[" + std::to_string(i) + "].template",
                    "not the index of a geometry template");
      surfaces = &(*templates)[std::size_t(ti->get<std::uint64_t>())];
      if (!surfaces->is_object()) continue;
    }
    const auto st = surfaces->find("type");
    if (st == surfaces->end() || !st->is_string() || !surfaceType(st->get<std::string>())) continue;
    lods[i] = readLod(g);
    if (!lods[i]) lods[i] = readLod(*surfaces);
    if (!lods[i]) lods[i] = Lod{};
    if (!highest || lods[i]->value > *highest) highest = lods[i]->value;
  }
  bool any = false;
  for (std::size_t i = 0; i < geometry->size(); ++i) {
    if (!lods[i]) continue;
    const bool chosen =
        options_.lod.empty() ? lods[i]->value == *highest : lodMatches(*lods[i], options_.lod);
    if (!chosen) continue;
    any = true;
    lodsChosen_.insert(lods[i]->text.empty() ? "(none given)" : lods[i]->text);
    const json& g = (*geometry)[i];
    const std::string gWhere = where + ".geometry[" + std::to_string(i) + "]";
    Status s = g["type"] == "GeometryInstance"
                   ? readInstance(gWhere, g)
                   : readGeometry(gWhere, g, VertexSource{vertices_.size(), [&](std::uint32_t v) {
                                                            return vertices_[v];
                                                          }});
    if (!s) return s;
  }
  if (any) ++model_.cityObjects;
  object_ = std::uint32_t(model_.cityObjects);
  return Ok{};
}

Result<Model> Reader::run() {
  if (!root_.is_object()) return fileError(path_, "not a CityJSON file (not a JSON object)");
  const auto type = root_.find("type");
  // CityJSON 0.2 wrote "CityModel".
  if (type == root_.end() || (*type != "CityJSON" && *type != "CityModel"))
    return fileError(path_, "not a CityJSON file (no \"type\": \"CityJSON\")");
  if (auto s = readVersion(); !s) return s.error();
  if (auto s = readVertices(); !s) return s.error();
  if (auto s = readCrs(); !s) return s.error();
  if (auto s = readMaterials(); !s) return s.error();
  const auto objects = root_.find("CityObjects");
  if (objects == root_.end() || !objects->is_object())
    return fail("CityObjects", "missing (or not an object)");
  for (auto it = objects->begin(); it != objects->end(); ++it)
    if (auto s = readObject(it.key(), it.value()); !s) return s.error();
  if (degenerate_) warn(path_, std::to_string(degenerate_) + " surfaces without area skipped");
  if (partial_)
    warn(path_, std::to_string(partial_) + " self-intersecting surfaces triangulated in part");
  if (droppedHoles_)
    warn(path_, std::to_string(droppedHoles_) +
                    " holes without area or outside their surface "
                    "skipped");
  if (openShells_)
    warn(path_, std::to_string(openShells_) + " solid shells not closed: drawn two-sided");
  if (textured_)
    warn(path_, "textures are not imported (" + std::to_string(textured_) +
                    " geometries have them): surfaces coloured by material or semantics");
  if (relabelled_)
    warn(path_, std::to_string(relabelled_) +
                    " surfaces labelled WallSurface face up or down: coloured as roof or ground");
  if (skippedTypes_)
    warn(path_, std::to_string(skippedTypes_) + " geometries of unknown type skipped");
  if (!options_.lod.empty() && model_.cityObjects == 0 && !objects->empty())
    return fileError(path_, "no city object has geometry at LoD " + options_.lod);
  if (triangles_ == 0 && degenerate_ > 0)
    return fileError(path_, "no triangles: all " + std::to_string(degenerate_) +
                                " surfaces have no area (collinear or repeated vertices)");
  if (triangles_ == 0)
    return fileError(path_, "no surfaces to triangulate (" + std::to_string(objects->size()) +
                                " city objects, " + std::to_string(vertices_.size()) +
                                " vertices; points and lines are not imported)");
  std::string lods;
  for (const auto& l : lodsChosen_) lods += (lods.empty() ? "" : ", ") + l;
  model_.lod = options_.lod.empty() ? "highest of each object (" + lods + ")" : options_.lod;
  model_.zUp = true;
  if (flipped_)
    warn(path_, std::to_string(flipped_) + " solid shells wound inwards: turned outwards");
  return std::move(model_);
}

}  // namespace

bool looksLikeCityJson(std::string_view bytes) {
  // "type": "CityJSON" may come after megabytes of CityObjects (JSON objects are unordered).
  // 0.2 wrote "CityModel", a name too common to trust without "CityObjects" beside it.
  auto hasType = [&](std::string_view marker) {
    for (std::size_t at = bytes.find(marker); at != std::string_view::npos;
         at = bytes.find(marker, at + 1)) {
      std::size_t i = at;
      while (i > 0 && TextScanner::isSpace(bytes[i - 1])) --i;
      if (i == 0 || bytes[i - 1] != ':') continue;
      --i;
      while (i > 0 && TextScanner::isSpace(bytes[i - 1])) --i;
      if (i >= 6 && bytes.substr(i - 6, 6) == "\"type\"") return true;
    }
    return false;
  };
  return hasType("\"CityJSON\"") ||
         (hasType("\"CityModel\"") && bytes.find("\"CityObjects\"") != std::string_view::npos);
}

Result<Model> readCityJson(const std::filesystem::path& path, const std::string& bytes,
                           const ImportOptions& options) {
  if (jsonDepth(bytes.data(), bytes.size(), kMaxCityJsonDepth) > kMaxCityJsonDepth)
    return fileError(path,
                     "JSON nested deeper than " + std::to_string(kMaxCityJsonDepth) + " levels");
  json root;
  try {
    root = json::parse(bytes);
  } catch (const json::exception& e) {
    // "[json.exception.parse_error.101] parse error at line 1, column 7: ..." without the tag;
    // a number past double's range is out_of_range.406.
    std::string what = e.what();
    if (const auto close = what.find("] "); close != std::string::npos)
      what = what.substr(close + 2);
    return fileError(path, "not valid JSON: " + what);
  }
  Reader reader(path, root, options);
  return reader.run();
}

}  // namespace hlod::import
