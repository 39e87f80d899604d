#pragma once
// Checks of a tileset JSON written from the 3D Tiles 1.1 JSON schemas (CesiumGS/3d-tiles,
// specification/schema: tileset.schema.json, asset.schema.json, tile.schema.json,
// boundingVolume.schema.json, content.schema.json), independently of hlodr's exporter, plus the
// rule viewers depend on most: a content's bounding box holds every vertex of it
// (3DTilesRendererJS #160, TerriaJS #5567). Each rule has a name; a test per rule feeds a tileset
// that breaks only it. The official 3d-tiles-validator is not on the npm registry reachable here.
#include <cmath>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

namespace tilesetcheck {

struct Violation {
  std::string rule;   // e.g. "tile.geometricError.minimum"
  std::string where;  // JSON path, e.g. "/root/children/0"
};

// The positions of a content (the tile's frame: glTF node transforms and y-up to z-up applied),
// or nothing when it cannot be read (which is a violation of its own).
using ContentPositions =
    std::function<bool(const std::string& uri, std::vector<glm::dvec3>& positions)>;

class Checker {
 public:
  explicit Checker(ContentPositions positions = {}) : positions_(std::move(positions)) {}

  std::vector<Violation> check(const nlohmann::json& t) {
    out_.clear();
    // tileset.schema.json: "required": ["asset", "geometricError", "root"].
    if (!t.is_object()) return {{"tileset.type", ""}};
    for (const char* key : {"asset", "geometricError", "root"})
      if (!t.contains(key)) add(std::string("tileset.required.") + key, "");
    if (t.contains("asset")) asset(t["asset"]);
    if (t.contains("geometricError"))
      nonNegative(t["geometricError"], "tileset.geometricError", "/geometricError");
    for (const char* key : {"extensionsUsed", "extensionsRequired"})
      if (t.contains(key)) stringSet(t[key], std::string("tileset.") + key, std::string("/") + key);
    if (t.contains("root")) tile(t["root"], "/root", true);
    return out_;
  }

 private:
  void add(const std::string& rule, const std::string& where) { out_.push_back({rule, where}); }

  // asset.schema.json: an object, "version" required and a string; tilesetVersion a string.
  void asset(const nlohmann::json& a) {
    if (!a.is_object()) return add("asset.type", "/asset");
    if (!a.contains("version"))
      add("asset.required.version", "/asset");
    else if (!a["version"].is_string())
      add("asset.version.type", "/asset/version");
    if (a.contains("tilesetVersion") && !a["tilesetVersion"].is_string())
      add("asset.tilesetVersion.type", "/asset/tilesetVersion");
  }

  // "type": "number", "minimum": 0.
  void nonNegative(const nlohmann::json& v, const std::string& rule, const std::string& where) {
    if (!v.is_number()) return add(rule + ".type", where);
    if (!(v.get<double>() >= 0.0)) add(rule + ".minimum", where);
  }

  // "type": "array", string items, "uniqueItems": true, "minItems": 1.
  void stringSet(const nlohmann::json& v, const std::string& rule, const std::string& where) {
    if (!v.is_array()) return add(rule + ".type", where);
    if (v.empty()) add(rule + ".minItems", where);
    std::set<std::string> seen;
    for (const auto& s : v) {
      if (!s.is_string()) return add(rule + ".items.type", where);
      if (!seen.insert(s.get<std::string>()).second) add(rule + ".uniqueItems", where);
    }
  }

  static bool numbers(const nlohmann::json& v, std::size_t n) {
    if (!v.is_array() || v.size() != n) return false;
    for (const auto& x : v)
      if (!x.is_number()) return false;
    return true;
  }

  // boundingVolume.schema.json: "minProperties": 1; box 12, region 6, sphere 4 numbers.
  void volume(const nlohmann::json& v, const std::string& where) {
    if (!v.is_object()) return add("boundingVolume.type", where);
    if (v.empty()) add("boundingVolume.minProperties", where);
    if (v.contains("box") && !numbers(v["box"], 12))
      add("boundingVolume.box.items", where + "/box");
    if (v.contains("region") && !numbers(v["region"], 6))
      add("boundingVolume.region.items", where + "/region");
    if (v.contains("sphere") && !numbers(v["sphere"], 4))
      add("boundingVolume.sphere.items", where + "/sphere");
  }

  // content.schema.json: "required": ["uri"], uri a string, boundingVolume as above; and the
  // content's box (its own, else the tile's) holds every vertex of it.
  void content(const nlohmann::json& c, const std::string& where,
               const nlohmann::json* tileVolume) {
    if (!c.is_object()) return add("content.type", where);
    if (!c.contains("uri")) return add("content.required.uri", where);
    if (!c["uri"].is_string()) return add("content.uri.type", where + "/uri");
    if (c.contains("boundingVolume")) volume(c["boundingVolume"], where + "/boundingVolume");
    const nlohmann::json* v = c.contains("boundingVolume") ? &c["boundingVolume"] : tileVolume;
    if (!positions_ || !v || !v->is_object() || !v->contains("box") || !numbers((*v)["box"], 12))
      return;
    std::vector<glm::dvec3> ps;
    if (!positions_(c["uri"].get<std::string>(), ps)) return add("content.readable", where);
    const auto& b = (*v)["box"];
    const glm::dvec3 centre(b[0].get<double>(), b[1].get<double>(), b[2].get<double>());
    glm::dvec3 axes[3];
    for (int k = 0; k < 3; ++k)
      axes[k] = glm::dvec3(b[3 + 3 * k].get<double>(), b[4 + 3 * k].get<double>(),
                           b[5 + 3 * k].get<double>());
    for (const glm::dvec3& p : ps)
      for (int k = 0; k < 3; ++k) {
        // Inside along axis k: |(p - c) . a| <= |a|^2 (a half-axis), to rounding.
        const double a2 = glm::dot(axes[k], axes[k]);
        if (std::abs(glm::dot(p - centre, axes[k])) > a2 * (1.0 + 1e-12) + 1e-9)
          return add("content.box.holdsVertices", where);
      }
  }

  // tile.schema.json.
  void tile(const nlohmann::json& t, const std::string& where, bool root) {
    if (!t.is_object()) return add("tile.type", where);
    // "required": ["boundingVolume", "geometricError"].
    if (!t.contains("boundingVolume"))
      add("tile.required.boundingVolume", where);
    else
      volume(t["boundingVolume"], where + "/boundingVolume");
    if (!t.contains("geometricError"))
      add("tile.required.geometricError", where);
    else
      nonNegative(t["geometricError"], "tile.geometricError", where + "/geometricError");
    // refine: "ADD" or "REPLACE"; "required for the root tile of a tileset".
    if (t.contains("refine")) {
      if (!t["refine"].is_string() || (t["refine"] != "ADD" && t["refine"] != "REPLACE"))
        add("tile.refine.enum", where + "/refine");
    } else if (root) {
      add("tile.refine.requiredAtRoot", where);
    }
    // transform: 16 numbers ("minItems": 16, "maxItems": 16).
    if (t.contains("transform") && !numbers(t["transform"], 16))
      add("tile.transform.items", where + "/transform");
    // "not": {"required": ["content", "contents"]}.
    if (t.contains("content") && t.contains("contents")) add("tile.contentXorContents", where);
    const nlohmann::json* v = t.contains("boundingVolume") ? &t["boundingVolume"] : nullptr;
    if (t.contains("content")) content(t["content"], where + "/content", v);
    if (t.contains("contents")) {
      if (!t["contents"].is_array())
        add("tile.contents.type", where + "/contents");
      else if (t["contents"].empty())
        add("tile.contents.minItems", where + "/contents");
      else
        for (std::size_t k = 0; k < t["contents"].size(); ++k)
          content(t["contents"][k], where + "/contents/" + std::to_string(k), v);
    }
    // children: an array of tiles, "minItems": 1 ("uniqueItems" holds for distinct objects).
    if (t.contains("children")) {
      if (!t["children"].is_array()) return add("tile.children.type", where + "/children");
      if (t["children"].empty()) add("tile.children.minItems", where + "/children");
      for (std::size_t k = 0; k < t["children"].size(); ++k)
        tile(t["children"][k], where + "/children/" + std::to_string(k), false);
    }
  }

  ContentPositions positions_;
  std::vector<Violation> out_;
};

}  // namespace tilesetcheck
