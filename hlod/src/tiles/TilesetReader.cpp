// readTilesetTree: a tileset's tiles from its JSON files (hlod/tiles/TilesetReader.h).
#include "hlod/tiles/TilesetReader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <set>

#include "hlod/JsonDepth.h"
#include "hlod/geodesy/Geodesy.h"
#include "hlod/import/InsideFolder.h"
#include "hlod/tiles/Subtree.h"
#include "hlod/tiles/TileFormats.h"
#include "tiles/TilesetFrame.h"

namespace hlod::tiles {

namespace fs = std::filesystem;

namespace {

// Extensions a tileset may require that change nothing hlodr reads, or that it reads.
const std::set<std::string> kKnownExtensions = {
    "3DTILES_content_gltf",        "3DTILES_metadata",        "3DTILES_bounding_volume_S2",
    "3DTILES_multiple_contents",   "3DTILES_implicit_tiling", "3DTILES_batch_table_hierarchy",
    "3DTILES_content_gltf_vector", "MAXAR_content_geojson"};

Result<std::string> readFileBounded(const fs::path& path, std::uint64_t limit,
                                    const std::string& what) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    return makeError(what + ": " + path.filename().string() + " not found");
  const auto size = fs::file_size(path, ec);
  if (ec) return makeError(what + ": cannot read " + path.filename().string());
  if (size > limit)
    return makeError(what + ": " + path.filename().string() + " holds " + std::to_string(size) +
                     " bytes, more than the " + std::to_string(limit) + " read at most");
  std::string bytes(size, '\0');
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return makeError(what + ": cannot open " + path.filename().string());
  const std::size_t got = std::fread(bytes.data(), 1, bytes.size(), f);
  std::fclose(f);
  if (got != bytes.size()) return makeError(what + ": cannot read " + path.filename().string());
  return bytes;
}

// The first bytes of a file (to tell its format), at most n.
std::string peek(const fs::path& path, std::size_t n) {
  std::string bytes(n, '\0');
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return {};
  bytes.resize(std::fread(bytes.data(), 1, n, f));
  std::fclose(f);
  return bytes;
}

int hexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

bool finiteNumbers(const nlohmann::json& a, std::size_t n) {
  if (!a.is_array() || a.size() != n) return false;
  for (const auto& v : a)
    if (!v.is_number() || !std::isfinite(v.get<double>())) return false;
  return true;
}

std::string upper(std::string s) {
  for (char& c : s) c = char(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

class Reader {
 public:
  Reader(const fs::path& top, const TilesetLimits& limits) : limits_(limits) {
    tree_.folder = top.has_parent_path() ? top.parent_path() : fs::path(".");
  }

  Result<TilesetTree> run(const fs::path& file) {
    std::error_code ec;
    canonicalTop_ = fs::canonical(tree_.folder, ec);
    if (ec) return makeError(file.string() + ": cannot resolve its folder");
    const std::string name = file.filename().string();
    auto s = readTileset(fs::canonical(file, ec), name, TileRecord::kNone, glm::dmat4(1.0),
                         std::nullopt, 0, 0);
    if (ec) return makeError(file.string() + ": not found");
    if (!s) return s.error();
    if (tree_.tiles.empty()) return makeError(file.string() + ": the tileset has no root tile");
    return std::move(tree_);
  }

 private:
  // The file a URI names, relative to the folder of the file that names it, inside the top
  // folder.
  Result<fs::path> resolve(const std::string& uri, const fs::path& referrerDir) const {
    std::string u = uri;
    if (u.rfind("data:", 0) == 0) return makeError("'" + uri + "' is a data URI (not read)");
    if (u.find("://") != std::string::npos)
      return makeError("'" + uri +
                       "' is a remote URL; hlodr reads files inside the tileset's "
                       "folder only");
    u = u.substr(0, u.find_first_of("?#"));
    std::string decoded;
    for (std::size_t i = 0; i < u.size(); ++i) {
      if (u[i] == '%' && i + 2 < u.size() && hexValue(u[i + 1]) >= 0 && hexValue(u[i + 2]) >= 0) {
        decoded.push_back(char(hexValue(u[i + 1]) * 16 + hexValue(u[i + 2])));
        i += 2;
      } else {
        decoded.push_back(u[i]);
      }
    }
    if (decoded.empty()) return makeError("empty URI");
    std::string prefix;
    const fs::path below = referrerDir.lexically_relative(canonicalTop_);
    if (!below.empty() && below != ".") prefix = below.generic_string() + "/";
    auto inside = insideFolder(tree_.folder, prefix + decoded);
    if (!inside) return inside.error();
    return *inside;
  }

  Result<std::uint32_t> newTile(const std::string& name, std::uint32_t parent) {
    if (tree_.tiles.size() >= limits_.maxTiles)
      return makeError(name + ": the tileset has more than " + std::to_string(limits_.maxTiles) +
                       " tiles (the most hlodr reads)");
    const auto index = std::uint32_t(tree_.tiles.size());
    tree_.tiles.emplace_back();
    tree_.tiles.back().name = name;
    tree_.tiles.back().parent = parent;
    if (parent != TileRecord::kNone) tree_.tiles[parent].children.push_back(index);
    return index;
  }

  // A tileset JSON file: its asset, then its root tile under `parent` (TileRecord::kNone for the
  // first tileset).
  Status readTileset(const fs::path& file, const std::string& name, std::uint32_t parent,
                     const glm::dmat4& parentTransform, std::optional<bool> parentAdd,
                     std::uint32_t depth, std::uint32_t nesting) {
    if (nesting > limits_.maxExternalNesting)
      return makeError(name + ": external tilesets nested more than " +
                       std::to_string(limits_.maxExternalNesting) + " deep");
    if (std::find(open_.begin(), open_.end(), file) != open_.end())
      return makeError(name + ": refers back to " + file.filename().string() +
                       ", which contains it (a cycle of external tilesets)");
    auto bytes = readFileBounded(file, limits_.maxJsonBytes, name);
    if (!bytes) return bytes.error();
    const std::string where = file.lexically_relative(canonicalTop_).generic_string();
    // Two JSON levels per tile level (the children array and the tile), and some to spare.
    const std::size_t maxJsonDepth = 2 * std::size_t(limits_.maxDepth) + 16;
    if (jsonDepth(*bytes, maxJsonDepth) > maxJsonDepth)
      return makeError(where + ": JSON nested deeper than " + std::to_string(maxJsonDepth) +
                       " levels");
    const nlohmann::json j = nlohmann::json::parse(*bytes, nullptr, false);
    if (j.is_discarded()) return makeError(where + ": not valid JSON (truncated?)");
    if (!j.is_object()) return makeError(where + ": not a JSON object");
    if (!j.contains("asset") || !j["asset"].is_object())
      return makeError(where + ": no asset (required by 3D Tiles)");
    const nlohmann::json& asset = j["asset"];
    if (!asset.contains("version") || !asset["version"].is_string())
      return makeError(where + ": asset.version missing or not a string");
    const std::string version = asset["version"].get<std::string>();
    if (version != "0.0" && version != "1.0" && version != "1.1")
      tree_.warnings.push_back(where + ": 3D Tiles version " + version + " read as 1.1");
    if (parent == TileRecord::kNone) {
      tree_.version = version;
      if (j.contains("extras") && j["extras"].is_object() && j["extras"].contains("hlodr"))
        tree_.hlodr = j["extras"]["hlodr"];
    }
    if (j.contains("extensionsRequired")) {
      if (!j["extensionsRequired"].is_array())
        return makeError(where + ": extensionsRequired is not an array");
      for (const auto& e : j["extensionsRequired"])
        if (!e.is_string() || !kKnownExtensions.count(e.get<std::string>()))
          return makeError(where + ": requires the extension " + e.dump() +
                           ", which hlodr does not read");
    }
    if (!j.contains("geometricError") || !j["geometricError"].is_number() ||
        !(j["geometricError"].get<double>() >= 0.0))
      return makeError(where + ": geometricError missing or negative (required by 3D Tiles)");
    if (!j.contains("root") || !j["root"].is_object()) return makeError(where + ": no root tile");
    // gltfUpAxis (a 3D Tiles 1.0 asset property CesiumJS honours): the content's up axis.
    AxisMap up = yUpToZUp();
    if (asset.contains("gltfUpAxis") && asset["gltfUpAxis"].is_string()) {
      const std::string axis = upper(asset["gltfUpAxis"].get<std::string>());
      if (axis == "Z")
        up = AxisMap{};
      else if (axis == "X")
        up = xUpToZUp();
      else if (axis != "Y")
        return makeError(where + ": asset.gltfUpAxis is not X, Y or Z");
    }
    open_.push_back(file);
    auto s = readTile(j["root"], file.parent_path(), where + ": tile root", parent, parentTransform,
                      parentAdd, depth, nesting, up);
    open_.pop_back();
    return s;
  }

  Status readTile(const nlohmann::json& t, const fs::path& dir, const std::string& name,
                  std::uint32_t parent, const glm::dmat4& parentTransform,
                  std::optional<bool> parentAdd, std::uint32_t depth, std::uint32_t nesting,
                  const AxisMap& up) {
    if (!t.is_object()) return makeError(name + ": not a JSON object");
    if (depth >= limits_.maxDepth)
      return makeError(name + ": tiles nested more than " + std::to_string(limits_.maxDepth) +
                       " levels deep");
    auto created = newTile(name, parent);
    if (!created) return created.error();
    const std::uint32_t index = *created;
    TileRecord rec;
    rec.name = name;
    rec.parent = parent;
    rec.depth = depth;
    rec.contentUp = up;
    glm::dmat4 local(1.0);
    if (t.contains("transform")) {
      if (!finiteNumbers(t["transform"], 16))
        return makeError(name + ": transform is not 16 finite numbers");
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
          local[c][r] = t["transform"][std::size_t(4 * c + r)].get<double>();
      if (local[0][3] != 0.0 || local[1][3] != 0.0 || local[2][3] != 0.0 || local[3][3] != 1.0)
        return makeError(name + ": transform is not affine (its last row is not 0 0 0 1)");
      if (std::abs(glm::determinant(glm::dmat3(local))) < 1e-12)
        return makeError(name + ": transform is singular");
    }
    rec.transform = parentTransform * local;
    if (!t.contains("geometricError") || !t["geometricError"].is_number() ||
        !(t["geometricError"].get<double>() >= 0.0) ||
        !std::isfinite(t["geometricError"].get<double>()))
      return makeError(name + ": geometricError missing, negative or not finite");
    // "transform scales the geometricError by the largest scaling factor from the matrix".
    const glm::dmat3 linear(rec.transform);
    const double scale =
        std::max({glm::length(linear[0]), glm::length(linear[1]), glm::length(linear[2])});
    rec.geometricError = t["geometricError"].get<double>() * scale;
    if (t.contains("refine")) {
      if (!t["refine"].is_string()) return makeError(name + ": refine is not a string");
      const std::string refine = upper(t["refine"].get<std::string>());
      if (refine == "ADD") {
        rec.add = true;
      } else if (refine != "REPLACE") {
        tree_.warnings.push_back(name + ": refine '" + t["refine"].get<std::string>() +
                                 "' is unknown; read as REPLACE");
      }
    } else if (parentAdd) {
      rec.add = *parentAdd;
    } else {
      tree_.warnings.push_back(name + ": the root has no refine (required); read as REPLACE");
    }
    if (auto s = boundingVolume(t, name, rec); !s) return s;
    if (t.contains("viewerRequestVolume") && !warnedRequestVolume_) {
      warnedRequestVolume_ = true;
      tree_.warnings.push_back(name +
                               ": viewerRequestVolume is not used (hlodr selects by its "
                               "own rules)");
    }
    if (t.contains("extras") && t["extras"].is_object() && t["extras"].contains("hlodr"))
      rec.hlodr = t["extras"]["hlodr"];

    // Contents: content, contents, or 3DTILES_multiple_contents.
    const nlohmann::json* contents = nullptr;
    nlohmann::json single;
    if (t.contains("content") && t.contains("contents"))
      return makeError(name + ": has both content and contents (3D Tiles allows one)");
    if (t.contains("content")) {
      single = nlohmann::json::array({t["content"]});
      contents = &single;
    } else if (t.contains("contents")) {
      contents = &t["contents"];
    } else if (t.contains("extensions") && t["extensions"].is_object() &&
               t["extensions"].contains("3DTILES_multiple_contents")) {
      const nlohmann::json& e = t["extensions"]["3DTILES_multiple_contents"];
      if (e.is_object() && e.contains("contents")) contents = &e["contents"];
    }
    const nlohmann::json* implicit = nullptr;
    if (t.contains("implicitTiling"))
      implicit = &t["implicitTiling"];
    else if (t.contains("extensions") && t["extensions"].is_object() &&
             t["extensions"].contains("3DTILES_implicit_tiling"))
      implicit = &t["extensions"]["3DTILES_implicit_tiling"];
    std::vector<std::string> uris;
    if (contents) {
      if (!contents->is_array()) return makeError(name + ": contents is not an array");
      for (const auto& c : *contents) {
        if (!c.is_object()) return makeError(name + ": a content is not an object");
        // "url" is the pre-1.0 name of "uri", still written by old tools.
        const char* key = c.contains("uri") ? "uri" : c.contains("url") ? "url" : nullptr;
        if (!key || !c[key].is_string()) return makeError(name + ": a content has no uri");
        uris.push_back(c[key].get<std::string>());
      }
    }
    tree_.tiles[index] = rec;

    if (implicit) {
      if (t.contains("children"))
        return makeError(name + ": an implicit root tile must not list children");
      return readImplicit(*implicit, uris, dir, index, depth, up);
    }
    for (const std::string& uri : uris) {
      auto file = resolve(uri, dir);
      if (!file) return makeError(name + ": content " + file.message());
      const std::string head = peek(*file, 64);
      if (head.empty()) {
        std::error_code ec;
        if (!fs::is_regular_file(*file, ec))
          return makeError(name + ": content '" + uri + "' not found");
        return makeError(name + ": content '" + uri + "' is empty");
      }
      const TileFormat quick = detectTileFormat(head);
      if (quick != TileFormat::Unknown && quick != TileFormat::GltfJson &&
          quick != TileFormat::Tileset) {
        tree_.tiles[index].contents.push_back(*file);
        continue;
      }
      auto bytes = readFileBounded(*file, limits_.maxJsonBytes, name);
      if (!bytes) return bytes.error();
      const TileFormat format = detectTileFormat(*bytes);
      if (format == TileFormat::Tileset) {
        if (t.contains("children") && t["children"].is_array() && !t["children"].empty())
          return makeError(name + ": points to an external tileset and has children");
        std::error_code ec;
        // Copies: reading the external tileset adds tiles, which moves tree_.tiles.
        const glm::dmat4 transform = tree_.tiles[index].transform;
        const std::optional<bool> add = tree_.tiles[index].add;
        auto s = readTileset(fs::canonical(*file, ec), name + " -> " + uri, index, transform, add,
                             depth + 1, nesting + 1);
        if (!s) return s;
        continue;
      }
      if (format == TileFormat::Unknown)
        return makeError(name + ": content '" + uri +
                         "' is neither a tile format (glb, b3dm, cmpt, i3dm, pnts) nor JSON of a "
                         "tileset or glTF");
      tree_.tiles[index].contents.push_back(*file);
    }
    if (t.contains("children")) {
      const nlohmann::json& children = t["children"];
      if (!children.is_array()) return makeError(name + ": children is not an array");
      const glm::dmat4 transform = tree_.tiles[index].transform;
      const bool add = tree_.tiles[index].add;
      for (std::size_t k = 0; k < children.size(); ++k) {
        auto s = readTile(children[k], dir, name + "/" + std::to_string(k), index, transform, add,
                          depth + 1, nesting, up);
        if (!s) return s;
      }
    }
    return Ok{};
  }

  // The bounding volume's centre in the tileset's frame (for placing an earth-centred tileset).
  Status boundingVolume(const nlohmann::json& t, const std::string& name, TileRecord& rec) {
    if (!t.contains("boundingVolume") || !t["boundingVolume"].is_object())
      return makeError(name + ": boundingVolume missing (required by 3D Tiles)");
    const nlohmann::json& v = t["boundingVolume"];
    if (v.contains("box")) {
      if (!finiteNumbers(v["box"], 12)) return makeError(name + ": box is not 12 finite numbers");
      const glm::dvec3 c(v["box"][0].get<double>(), v["box"][1].get<double>(),
                         v["box"][2].get<double>());
      rec.volumeCentre = glm::dvec3(rec.transform * glm::dvec4(c, 1.0));
    } else if (v.contains("region")) {
      if (!finiteNumbers(v["region"], 6))
        return makeError(name + ": region is not 6 finite numbers");
      const auto& r = v["region"];
      const double west = r[0].get<double>(), south = r[1].get<double>(), east = r[2].get<double>(),
                   north = r[3].get<double>();
      if (!(south >= -1.5707963267948966 - 1e-9 && north <= 1.5707963267948966 + 1e-9 &&
            south <= north && std::abs(west) <= 3.1415926535897932 + 1e-9 &&
            std::abs(east) <= 3.1415926535897932 + 1e-9))
        return makeError(name + ": region is not west, south, east, north in radians");
      double lon = 0.5 * (west + east);
      if (east < west) lon += 3.141592653589793;  // across the antimeridian
      rec.region = true;
      rec.regionMinHeight = r[4].get<double>();
      rec.volumeCentre = geodeticToEcef({0.5 * (south + north) / kRadPerDeg, lon / kRadPerDeg,
                                         0.5 * (r[4].get<double>() + r[5].get<double>())});
    } else if (v.contains("sphere")) {
      if (!finiteNumbers(v["sphere"], 4) || v["sphere"][3].get<double>() < 0.0)
        return makeError(name + ": sphere is not 4 finite numbers with a radius");
      const glm::dvec3 c(v["sphere"][0].get<double>(), v["sphere"][1].get<double>(),
                         v["sphere"][2].get<double>());
      rec.volumeCentre = glm::dvec3(rec.transform * glm::dvec4(c, 1.0));
    } else if (!v.contains("extensions")) {
      return makeError(name + ": boundingVolume has no box, region or sphere");
    } else {
      rec.volumeCentre = glm::dvec3(rec.transform[3]);
    }
    return Ok{};
  }

  // Implicit tiling below tile `root`: its subtrees, depth first from the root's.
  Status readImplicit(const nlohmann::json& it, const std::vector<std::string>& uris,
                      const fs::path& dir, std::uint32_t root, std::uint32_t depth,
                      const AxisMap& up) {
    const std::string name = tree_.tiles[root].name;  // a copy: tiles are added below
    if (!it.is_object()) return makeError(name + ": implicitTiling is not an object");
    const std::string scheme = it.value("subdivisionScheme", "");
    unsigned branching = 0;
    if (scheme == "QUADTREE")
      branching = 4;
    else if (scheme == "OCTREE")
      branching = 8;
    else
      return makeError(name + ": implicitTiling.subdivisionScheme is not QUADTREE or OCTREE");
    if (!it.contains("subtreeLevels") || !it["subtreeLevels"].is_number_unsigned() ||
        !it.contains("availableLevels") || !it["availableLevels"].is_number_unsigned())
      return makeError(name + ": implicitTiling needs subtreeLevels and availableLevels");
    const auto subtreeLevels = it["subtreeLevels"].get<std::uint64_t>();
    const auto availableLevels = it["availableLevels"].get<std::uint64_t>();
    if (subtreeLevels < 1 || availableLevels < 1 || availableLevels > limits_.maxImplicitLevels)
      return makeError(name + ": implicitTiling levels out of range (availableLevels 1.." +
                       std::to_string(limits_.maxImplicitLevels) + ")");
    if (depth + availableLevels > limits_.maxDepth)
      return makeError(name + ": implicit tiles would lie more than " +
                       std::to_string(limits_.maxDepth) + " levels deep");
    const nlohmann::json& subtrees = it.contains("subtrees") ? it["subtrees"] : nlohmann::json();
    if (!subtrees.is_object() || !subtrees.contains("uri") || !subtrees["uri"].is_string())
      return makeError(name + ": implicitTiling.subtrees.uri missing");
    Implicit im{branching,
                unsigned(subtreeLevels),
                unsigned(availableLevels),
                subtrees["uri"].get<std::string>(),
                uris,
                dir,
                root,
                depth,
                up};
    // The root tile's own content is the template at (0, 0, 0), if available.
    tree_.tiles[root].contents.clear();
    return readSubtree(im, 0, 0, 0, 0, root);
  }

  struct Implicit {
    unsigned branching, subtreeLevels, availableLevels;
    std::string subtreeUri;
    std::vector<std::string> contentUris;
    fs::path dir;
    std::uint32_t root, depth;
    AxisMap up;
  };

  // The subtree whose root tile is at global (level, x, y, z); its root tile is `tile` (created
  // already: the implicit root, or a child made by the subtree above).
  Status readSubtree(const Implicit& im, std::uint32_t level, std::uint32_t x, std::uint32_t y,
                     std::uint32_t z, std::uint32_t tile) {
    const std::string where = tree_.tiles[im.root].name + " (implicit subtree " +
                              std::to_string(level) + "/" + std::to_string(x) + "/" +
                              std::to_string(y) +
                              (im.branching == 8 ? "/" + std::to_string(z) : "") + ")";
    const std::string uri = expandTemplate(im.subtreeUri, level, x, y, z);
    auto file = resolve(uri, im.dir);
    if (!file) return makeError(where + ": subtree " + file.message());
    auto bytes = readFileBounded(*file, limits_.maxJsonBytes, where);
    if (!bytes) return bytes.error();
    const fs::path subtreeDir = file->parent_path();
    auto subtree = parseSubtree(*bytes, im.branching, im.subtreeLevels,
                                [&](const std::string& bufferUri) -> Result<std::string> {
                                  auto buffer = resolve(bufferUri, subtreeDir);
                                  if (!buffer) return buffer.error();
                                  return readFileBounded(*buffer, limits_.maxJsonBytes, where);
                                });
    if (!subtree) return makeError(where + ": " + subtree.message());
    // Depth first over the available tiles: (local level, local Morton index, record).
    struct Pending {
      unsigned localLevel;
      std::uint64_t morton;
      std::uint32_t record;
    };
    std::vector<Pending> stack{{0, 0, tile}};
    const unsigned bits = im.branching == 4 ? 2 : 3;
    while (!stack.empty()) {
      const Pending p = stack.back();
      stack.pop_back();
      // Global coordinates: the subtree root's, then the local path.
      std::uint32_t lx = 0, ly = 0, lz = 0;
      for (unsigned b = 0; b < p.localLevel; ++b) {
        lx |= std::uint32_t((p.morton >> (bits * b)) & 1u) << b;
        ly |= std::uint32_t((p.morton >> (bits * b + 1)) & 1u) << b;
        if (bits == 3) lz |= std::uint32_t((p.morton >> (bits * b + 2)) & 1u) << b;
      }
      const std::uint32_t gl = level + p.localLevel;
      const std::uint32_t gx = (x << p.localLevel) | lx, gy = (y << p.localLevel) | ly,
                          gz = (z << p.localLevel) | lz;
      const std::uint64_t levelOffset =
          ((std::uint64_t(1) << (bits * p.localLevel)) - 1) / (im.branching - 1);
      const std::uint64_t bit = levelOffset + p.morton;
      for (std::size_t c = 0; c < im.contentUris.size(); ++c) {
        if (c >= subtree->contents.size() || !subtree->contents[c].at(bit)) continue;
        const std::string contentUri = expandTemplate(im.contentUris[c], gl, gx, gy, gz);
        auto content = resolve(contentUri, im.dir);
        if (!content)
          return makeError(tree_.tiles[p.record].name + ": content " + content.message());
        tree_.tiles[p.record].contents.push_back(*content);
      }
      if (gl + 1 >= im.availableLevels) continue;
      // Children: inside this subtree, or roots of child subtrees below its last level.
      for (unsigned c = im.branching; c-- > 0;) {
        const std::uint64_t childMorton = (p.morton << bits) | c;
        const bool inside = p.localLevel + 1 < im.subtreeLevels;
        const std::uint64_t childBit =
            ((std::uint64_t(1) << (bits * (p.localLevel + 1))) - 1) / (im.branching - 1) +
            childMorton;
        if (inside ? !subtree->tiles.at(childBit) : !subtree->childSubtrees.at(childMorton))
          continue;
        const std::uint32_t cx = (gx << 1) | (c & 1u), cy = (gy << 1) | ((c >> 1) & 1u),
                            cz = (gz << 1) | ((c >> 2) & 1u);
        const std::string childName = tree_.tiles[im.root].name + " implicit " +
                                      std::to_string(gl + 1) + "/" + std::to_string(cx) + "/" +
                                      std::to_string(cy) +
                                      (im.branching == 8 ? "/" + std::to_string(cz) : "");
        auto created = newTile(childName, p.record);
        if (!created) return created.error();
        TileRecord& rec = tree_.tiles[*created];
        const TileRecord& parent = tree_.tiles[p.record];
        rec.depth = im.depth + gl + 1;
        rec.transform = parent.transform;
        rec.contentUp = im.up;
        rec.add = parent.add;
        rec.geometricError = parent.geometricError * 0.5;  // "half of its parent's"
        rec.volumeCentre = parent.volumeCentre;
        rec.region = parent.region;
        if (inside) {
          stack.push_back({p.localLevel + 1, childMorton, *created});
        } else if (auto s = readSubtree(im, gl + 1, cx, cy, cz, *created); !s) {
          return s;
        }
      }
    }
    return Ok{};
  }

  TilesetLimits limits_;
  TilesetTree tree_;
  fs::path canonicalTop_;
  std::vector<fs::path> open_;  // the tileset files on the current chain of external ones
  bool warnedRequestVolume_ = false;
};

}  // namespace

bool isTilesetFile(const fs::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".json") return false;
  std::error_code ec;
  if (!fs::is_regular_file(path, ec) || fs::file_size(path, ec) > (256ull << 20)) return false;
  auto bytes = readFileBounded(path, 256ull << 20, path.string());
  return bytes && detectTileFormat(*bytes) == TileFormat::Tileset;
}

Result<TilesetTree> readTilesetTree(const fs::path& tilesetJson, const TilesetLimits& limits) {
  try {
    return Reader(tilesetJson, limits).run(tilesetJson);
  } catch (const std::bad_alloc&) {
    return makeError(tilesetJson.string() + ": out of memory while reading the tileset");
  }
}

}  // namespace hlod::tiles
