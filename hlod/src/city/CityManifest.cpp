// Reading a city folder: city.json validation and block loading through importModel.
#include <cmath>
#include <fstream>
#include <sstream>
#include <system_error>

#include <nlohmann/json.hpp>

#include "hlod/city/City.h"
#include "hlod/import/Import.h"
#include "hlod/import/InsideFolder.h"

namespace hlod {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// A file named by the manifest: relative, no "..", no root, no link out of the folder.
Result<fs::path> insidePath(const fs::path& dir, const std::string& where, const json& v,
                            bool required) {
  if (!v.is_string()) return makeError(where + " is not a string");
  const std::string s = v.get<std::string>();
  if (s.empty()) {
    if (required) return makeError(where + " is empty");
    return fs::path();
  }
  const fs::path p(s);
  if (p.is_absolute() || p.has_root_name() || p.has_root_directory() || s.front() == '/' ||
      s.front() == '\\')
    return makeError(where + " '" + s + "' is an absolute path; block files must be inside " +
                     dir.string());
  for (const auto& part : p)
    if (part == "..")
      return makeError(where + " '" + s + "' escapes the city folder " + dir.string());
  // Lexically inside (no ".." at all, so dir / p opens what insideFolder checked); a symbolic
  // link may still lead out.
  if (auto resolved = insideFolder(dir, s); !resolved)
    return makeError(where + ": " + resolved.message());
  const fs::path full = dir / p;
  std::error_code ec;
  if (!fs::is_regular_file(full, ec))
    return makeError(where + ": file " + full.string() + " is missing");
  return full;
}

Result<double> finiteNumber(const json& v, const std::string& where) {
  if (!v.is_number()) return makeError(where + " is not a number");
  const double x = v.get<double>();
  if (!std::isfinite(x)) return makeError(where + " is not finite");
  return x;
}

// {"lat": degrees, "lon": degrees, "height": metres above the WGS84 ellipsoid (optional, 0)}.
Result<LatLon> latLon(const json& v, const std::string& where) {
  if (!v.is_object()) return makeError(where + " is not an object with lat and lon");
  if (!v.contains("lat") || !v.contains("lon")) return makeError(where + " lacks lat or lon");
  auto lat = finiteNumber(v["lat"], where + ".lat");
  if (!lat) return lat.error();
  auto lon = finiteNumber(v["lon"], where + ".lon");
  if (!lon) return lon.error();
  if (std::abs(*lat) > 90.0 || std::abs(*lon) > 180.0) return makeError(where + " is out of range");
  double height = 0.0;
  if (v.contains("height")) {
    auto h = finiteNumber(v["height"], where + ".height");
    if (!h) return h.error();
    // Beyond the geostationary orbit nothing is a city; within it the conversions are exact.
    if (std::abs(*h) > 1e8) return makeError(where + ".height is out of range (|h| <= 1e8 m)");
    height = *h;
  }
  return LatLon{*lat, *lon, height};
}

// The axis-aligned box, in `to`'s coordinates, that holds `box` given in `from`'s.
Aabb moveBox(const Aabb& box, const EnuToEnu& fromTo) {
  Aabb out;
  for (int k = 0; k < 8; ++k) {
    const glm::dvec3 corner{k & 1 ? box.max.x : box.min.x, k & 2 ? box.max.y : box.min.y,
                            k & 4 ? box.max.z : box.min.z};
    out.extend(fromTo.point(corner));
  }
  return out;
}

Result<CityBlockInfo> blockInfo(const fs::path& dir, const json& b, std::size_t i,
                                const EnuFrame& city) {
  const std::string where = "city.json blocks[" + std::to_string(i) + "]";
  if (!b.is_object()) return makeError(where + " is not an object");
  for (const char* key : {"name", "mesh", "triangles", "bounds"})
    if (!b.contains(key)) return makeError(where + " lacks \"" + key + "\"");
  CityBlockInfo info;
  if (!b["name"].is_string()) return makeError(where + ".name is not a string");
  info.name = b["name"].get<std::string>();
  auto mesh = insidePath(dir, where + ".mesh", b["mesh"], true);
  if (!mesh) return mesh.error();
  info.mesh = *mesh;
  if (b.contains("texture")) {
    auto texture = insidePath(dir, where + ".texture", b["texture"], false);
    if (!texture) return texture.error();
    info.texture = *texture;
  }
  if (!b["triangles"].is_number_unsigned())
    return makeError(where + ".triangles is not a non-negative integer");
  info.triangles = b["triangles"].get<std::size_t>();
  const json& bounds = b["bounds"];
  if (!bounds.is_array() || bounds.size() != 2 || !bounds[0].is_array() || bounds[0].size() != 3 ||
      !bounds[1].is_array() || bounds[1].size() != 3)
    return makeError(where + ".bounds is not [[minx,miny,minz],[maxx,maxy,maxz]]");
  for (int c = 0; c < 3; ++c) {
    auto lo = finiteNumber(bounds[0][c], where + ".bounds");
    if (!lo) return lo.error();
    auto hi = finiteNumber(bounds[1][c], where + ".bounds");
    if (!hi) return hi.error();
    if (*lo > *hi) return makeError(where + ".bounds has min > max");
    info.bounds.min[c] = *lo;
    info.bounds.max[c] = *hi;
  }
  if (b.contains("frame")) {
    if (b["frame"] == "city") {
      info.frame = BlockFrame::City;
    } else if (b["frame"] == "anchor") {
      info.frame = BlockFrame::Anchor;
    } else {
      return makeError(where + ".frame is not \"city\" or \"anchor\"");
    }
  }
  if (b.contains("anchor")) {
    auto anchor = latLon(b["anchor"], where + ".anchor");
    if (!anchor) return anchor.error();
    info.anchor = *anchor;
  } else if (info.frame == BlockFrame::Anchor) {
    return makeError(where + " has frame \"anchor\" but no anchor");
  } else {
    info.anchor = city.toGeodetic(info.bounds.centre());
  }
  // The bounds of an anchored block are those of its file: move them into the city's frame.
  if (info.frame == BlockFrame::Anchor)
    info.bounds = moveBox(info.bounds, EnuToEnu(EnuFrame(info.anchor), city));
  return info;
}

}  // namespace

bool isCityFolder(const fs::path& dir) {
  std::error_code ec;
  return fs::is_directory(dir, ec) && fs::is_regular_file(dir / "city.json", ec);
}

Result<CityManifest> readCityManifest(const fs::path& dir) {
  const fs::path file = dir / "city.json";
  std::ifstream in(file, std::ios::binary);
  if (!in) return makeError("cannot open " + file.string());
  const json doc = json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (doc.is_discarded()) return makeError(file.string() + " is not valid JSON");
  if (!doc.is_object()) return makeError(file.string() + " is not a JSON object");
  if (!doc.contains("format") || doc["format"] != "hlodr-city")
    return makeError(file.string() + ": \"format\" is not \"hlodr-city\"");
  if (!doc.contains("version") || doc["version"] != 1)
    return makeError(file.string() + ": unsupported \"version\" (expected 1)");
  if (!doc.contains("blocks") || !doc["blocks"].is_array())
    return makeError(file.string() + ": \"blocks\" is missing or not an array");

  CityManifest m;
  m.dir = dir;
  if (doc.contains("seed")) {
    if (!doc["seed"].is_number_unsigned()) return makeError(file.string() + ": bad \"seed\"");
    m.seed = doc["seed"].get<std::uint64_t>();
  }
  m.origin = LatLon{kCityOriginLat, kCityOriginLon};
  if (doc.contains("origin")) {
    auto origin = latLon(doc["origin"], "city.json origin");
    if (!origin) return makeError(file.string() + ": " + origin.message());
    m.origin = *origin;
  }
  const EnuFrame cityFrame(m.origin);
  const json& blocks = doc["blocks"];
  m.blocks.reserve(blocks.size());
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    auto info = blockInfo(dir, blocks[i], i, cityFrame);
    if (!info) return makeError(file.string() + ": " + info.message());
    m.triangles += info->triangles;
    m.blocks.push_back(std::move(*info));
  }
  return m;
}

Result<Mesh> loadCityBlock(const CityManifest& manifest, std::size_t i) {
  if (i >= manifest.blocks.size())
    return makeError("block " + std::to_string(i) + " is out of range (the city has " +
                     std::to_string(manifest.blocks.size()) + ")");
  const CityBlockInfo& info = manifest.blocks[i];
  auto model = importModel(info.mesh);
  if (!model) return makeError("block " + info.name + ": " + model.message());
  if (model->meshes.empty())
    return makeError("block " + info.name + ": no mesh in " + info.mesh.string());

  // One mesh per block: merge groups should an importer have split the file.
  Mesh mesh = std::move(model->meshes.front());
  for (std::size_t k = 1; k < model->meshes.size(); ++k) {
    Mesh& other = model->meshes[k];
    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    const bool normals = !mesh.normals.empty() && !other.normals.empty();
    const bool uvs = !mesh.texCoords.empty() && !other.texCoords.empty();
    mesh.positions.insert(mesh.positions.end(), other.positions.begin(), other.positions.end());
    if (normals)
      mesh.normals.insert(mesh.normals.end(), other.normals.begin(), other.normals.end());
    else
      mesh.normals.clear();
    if (uvs)
      mesh.texCoords.insert(mesh.texCoords.end(), other.texCoords.begin(), other.texCoords.end());
    else
      mesh.texCoords.clear();
    for (auto idx : other.indices) mesh.indices.push_back(idx + base);
  }
  if (info.frame == BlockFrame::Anchor) {
    // From the anchor's ENU frame into the city's, in double: one rotation and offset per block.
    const EnuToEnu toCity(EnuFrame(info.anchor), EnuFrame(manifest.origin));
    for (auto& p : mesh.positions) p = toCity.point(p);
    for (auto& n : mesh.normals) n = glm::vec3(toCity.direction(glm::dvec3(n)));
  }
  mesh.name = info.name;
  mesh.oneSided = true;  // hlodr's own city geometry (generateBlock): wound outwards
  if (!mesh.texture && !info.texture.empty()) {
    auto image = loadImage(info.texture);
    if (!image) return makeError("block " + info.name + ": " + image.message());
    mesh.texture = std::make_shared<const Image>(std::move(*image));
  }
  return mesh;
}

Result<Model> loadCity(const fs::path& dir) {
  auto manifest = readCityManifest(dir);
  if (!manifest) return manifest.error();
  Model model;
  model.meshes.reserve(manifest->blocks.size());
  for (std::size_t i = 0; i < manifest->blocks.size(); ++i) {
    auto mesh = loadCityBlock(*manifest, i);
    if (!mesh) return mesh.error();
    model.meshes.push_back(std::move(*mesh));
  }
  return model;
}

}  // namespace hlod
