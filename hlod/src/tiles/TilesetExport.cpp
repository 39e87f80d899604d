// exportTileset: a node store as a 3D Tiles 1.1 tileset (hlod/tiles/TilesetExport.h).
// 3D Tiles 1.1 (OGC 22-025r4): tileset.schema.json (asset, geometricError, root), tile.schema.json
// (boundingVolume, geometricError, refine, transform, content, children), boundingVolume.box.
#include "hlod/tiles/TilesetExport.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <optional>

#include <nlohmann/json.hpp>

#include "hlod/tiles/Glb.h"
#include "tiles/TilesetFrame.h"

namespace hlod::tiles {

namespace fs = std::filesystem;

namespace {

// The generator name an export writes; checkReplaceableExport recognises it.
constexpr const char* kGenerator = "hlodr";

Status writeFile(const fs::path& path, const void* data, std::size_t size) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return makeError("cannot create " + path.string());
  const bool ok = std::fwrite(data, 1, size, f) == size;
  const bool closed = std::fclose(f) == 0;
  if (!ok || !closed) {
    std::error_code ec;
    fs::remove(path, ec);
    return makeError("cannot write " + path.string() + " (disk full?)");
  }
  return Ok{};
}

nlohmann::json vec3Json(const glm::dvec3& v) {
  return {v.x, v.y, v.z};
}

// A box as 3D Tiles writes it: centre, then the half-axes along x, y and z.
nlohmann::json boxJson(const Aabb& b) {
  const glm::dvec3 c = b.centre(), h = (b.max - b.min) * 0.5;
  return {c.x, c.y, c.z, h.x, 0.0, 0.0, 0.0, h.y, 0.0, 0.0, 0.0, h.z};
}

// A box in the tile frame: the world box through the axis map (a permutation with signs keeps
// boxes axis-aligned).
Aabb toTileFrame(const Aabb& world, const AxisMap& u) {
  Aabb out;
  out.extend(u.apply(world.min));
  out.extend(u.apply(world.max));
  return out;
}

struct SharedTexture {
  std::string uri;  // relative to content/
  bool written = false;
};

}  // namespace

Status checkReplaceableExport(const fs::path& dir) {
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(dir, ec);
  if (st.type() == fs::file_type::not_found) return Ok{};
  if (st.type() != fs::file_type::directory)
    return makeError(dir.string() + " exists and is not a folder; not replacing it");
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (!((name == "tileset.json" && entry.is_regular_file(ec)) ||
          (name == "content" && entry.is_directory(ec))))
      return makeError(dir.string() + " holds " + name +
                       ", which is not part of an hlodr tileset; not replacing the folder (give "
                       "another -o, or remove it yourself)");
  }
  if (ec) return makeError("cannot list " + dir.string() + ": " + ec.message());
  if (fs::is_empty(dir, ec)) return Ok{};
  std::ifstream in(dir / "tileset.json");
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded() || !j.is_object() || !j.contains("asset") || !j["asset"].is_object() ||
      j["asset"].value("generator", "") != kGenerator)
    return makeError((dir / "tileset.json").string() + " was not written by hlodr; not replacing " +
                     dir.string());
  return Ok{};
}

Result<TilesetExportReport> exportTileset(const NodeStore& store, const fs::path& dir,
                                          const TilesetExportOptions& options,
                                          const TilesetExportProgress& progress) {
  if (auto s = checkReplaceableExport(dir); !s) return s.error();
  const Skeleton& sk = store.skeleton();
  if (sk.roots.empty()) return makeError("the store has no nodes to export");
  TilesetExportReport report;
  const AxisMap worldToTile = upToZ(sk.up);
  const AxisMap worldToGltf = worldToTile.then(yUpToZUp().inverse());
  const std::optional<GeoPlacement> geo = geoPlacement(sk);
  report.geoReferenced = geo.has_value();
  report.frame = geo ? "on the globe: " + geo->description
                     : std::string("not geo-referenced: the model's own frame, ") +
                           upAxisName(sk.up) + " up turned to z";

  // Written beside dir, renamed into place at the end.
  std::error_code ec;
  if (dir.has_parent_path()) fs::create_directories(dir.parent_path(), ec);
  const fs::path tmp = dir.string() + ".tmp-" + std::to_string(::getpid());
  fs::remove_all(tmp, ec);
  struct RemoveOnFailure {
    fs::path path;
    bool keep = false;
    ~RemoveOnFailure() {
      std::error_code e;
      if (!keep) fs::remove_all(path, e);
    }
  } cleanup{tmp};
  if (!fs::create_directories(tmp / "content", ec) || ec)
    return makeError("cannot create " + (tmp / "content").string());

  // Textures the store shares between nodes (one texture section, several nodes): once each.
  std::map<std::uint64_t, std::size_t> sharers;
  for (const NodeInfo& n : sk.nodes)
    if (n.textureSize > 0) ++sharers[n.textureOffset];
  std::map<std::uint64_t, SharedTexture> shared;
  const char* imageExt = options.jpegQuality > 0 ? ".jpg" : ".png";
  const char* mime = options.jpegQuality > 0 ? "image/jpeg" : "image/png";
  for (const auto& [offset, count] : sharers)
    if (count > 1) shared[offset].uri = "tex-" + std::to_string(shared.size()) + imageExt;

  // Bottom up: each tile's geometric error (at least its children's, 0 at the leaves) and its
  // box (every vertex as a viewer places it, and the node's box), in the tile frame.
  const std::size_t count = sk.nodes.size();
  std::vector<double> error(count, 0.0);
  std::vector<Aabb> tileBox(count);
  for (std::size_t done = 0; done < count; ++done) {
    if (options.cancel && options.cancel->load()) return makeError("cancelled");
    const auto n = std::uint32_t(done);
    const NodeInfo& info = sk.nodes[n];
    auto mesh = store.loadNode(n);
    if (!mesh) return makeError("node " + std::to_string(n) + ": " + mesh.message());
    if (mesh->triangleCount() == 0)
      return makeError("node " + std::to_string(n) + " has no triangles (a glTF mesh needs one)");
    Aabb world = info.bounds;
    for (const glm::vec3& p : mesh->positions) world.extend(mesh->centre + glm::dvec3(p));
    tileBox[n] = toTileFrame(world, worldToTile);

    GlbContent content;
    content.mesh = &*mesh;
    content.toGltf = worldToGltf;
    content.translation = worldToGltf.apply(mesh->centre);
    if (mesh->texture && mesh->texCoords.size() == mesh->positions.size()) {
      const auto it = shared.find(info.textureOffset);
      const auto encode = [&] {
        return options.jpegQuality > 0 ? encodeJpeg(*mesh->texture, options.jpegQuality)
                                       : encodePng(*mesh->texture);
      };
      content.image.mimeType = mime;
      if (info.textureSize > 0 && it != shared.end()) {
        content.image.uri = it->second.uri;
        if (!it->second.written) {
          const std::vector<std::uint8_t> bytes = encode();
          if (auto s = writeFile(tmp / "content" / it->second.uri, bytes.data(), bytes.size()); !s)
            return s.error();
          report.bytes += bytes.size();
          it->second.written = true;
          ++report.sharedTextures;
        }
      } else {
        content.image.bytes = encode();
      }
    }
    const std::vector<std::byte> glb = encodeGlb(content);
    if (auto s =
            writeFile(tmp / "content" / ("n" + std::to_string(n) + ".glb"), glb.data(), glb.size());
        !s)
      return s.error();
    report.bytes += glb.size();
    ++report.contents;
    if (progress) progress(done + 1, count);
  }
  // Children after their parents (decodeSkeleton guarantees it): a reverse pass is bottom up.
  for (std::size_t k = count; k-- > 0;) {
    const NodeInfo& info = sk.nodes[k];
    if (info.childCount == 0) continue;
    error[k] = std::max(info.geometricError, 0.0);
    for (std::uint32_t c = info.firstChild; c < info.firstChild + info.childCount; ++c)
      error[k] = std::max(error[k], error[c]);
  }

  // The anchors of the blocks' roots (the quadtree's): kept so that an import rebuilds it.
  std::map<std::uint32_t, glm::dvec2> anchors;
  for (const QuadBlock& b : sk.quadtree.blocks) anchors[b.root] = b.anchor;

  const auto tileJson = [&](const auto& self, std::uint32_t n) -> nlohmann::json {
    const NodeInfo& info = sk.nodes[n];
    nlohmann::json extras = {
        {"node", n},
        {"block", info.block},
        {"level", info.level},
        {"cell", info.isCell()},
        {"centre", vec3Json(info.centre)},
        {"boundsMin", vec3Json(info.bounds.min)},
        {"boundsMax", vec3Json(info.bounds.max)},
        {"numTri", info.numTri},
        {"numTexTri", info.numTexTri},
        {"cost", info.cost},
        {"staticBenefit", info.staticBenefit},
        {"avgNormal", {info.avgNormal.x, info.avgNormal.y, info.avgNormal.z}},
        {"geometricError", info.geometricError},
    };
    if (const auto a = anchors.find(n); a != anchors.end())
      extras["anchor"] = {a->second.x, a->second.y};
    nlohmann::json tile = {{"boundingVolume", {{"box", boxJson(tileBox[n])}}},
                           {"geometricError", error[n]},
                           {"content", {{"uri", "content/n" + std::to_string(n) + ".glb"}}},
                           {"extras", {{"hlodr", extras}}}};
    if (info.childCount > 0) {
      nlohmann::json children = nlohmann::json::array();
      for (std::uint32_t c = info.firstChild; c < info.firstChild + info.childCount; ++c)
        children.push_back(self(self, c));
      tile["children"] = std::move(children);
    }
    return tile;
  };

  Aabb all;
  double rootError = 0.0;
  for (std::uint32_t r : sk.roots) {
    all.extend(tileBox[r]);
    rootError = std::max(rootError, error[r]);
  }
  const double diagonal = glm::length(all.size());
  nlohmann::json root;
  if (sk.roots.size() == 1) {
    root = tileJson(tileJson, sk.roots.front());
    ++report.tiles;
  } else {
    // A root without content above the store's roots, always refined (hlodr draws every root).
    nlohmann::json children = nlohmann::json::array();
    for (std::uint32_t r : sk.roots) children.push_back(tileJson(tileJson, r));
    root = {{"boundingVolume", {{"box", boxJson(all)}}},
            {"geometricError", std::max(diagonal, rootError)},
            {"children", std::move(children)}};
    ++report.tiles;
  }
  report.tiles += count;
  root["refine"] = "REPLACE";
  if (geo) {
    nlohmann::json m = nlohmann::json::array();
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) m.push_back(geo->tileToEcef[c][r]);  // column-major
    root["transform"] = m;
  }
  const ModelCrs& crs = sk.crs;
  nlohmann::json frame = {
      {"format", 1},
      {"up", upAxisName(sk.up)},
      {"worldToTile",
       {{"axis", {worldToTile.axis[0], worldToTile.axis[1], worldToTile.axis[2]}},
        {"sign", {worldToTile.sign[0], worldToTile.sign[1], worldToTile.sign[2]}}}},
      {"crs",
       {{"epsg", crs.epsg},
        {"description", crs.description},
        {"toEnu", crs.toEnu},
        {"origin", {crs.originLat, crs.originLon, crs.originHeight}}}},
      {"params",
       {{"levelFactor", sk.params.levelFactor},
        {"desiredTri", sk.params.desiredTri},
        {"cTex", sk.params.cTex},
        {"simplifier", sk.params.simplifier}}},
      {"facts",
       {{"inputTriangles", store.facts().inputTriangles},
        {"blockCount", store.facts().blockCount},
        {"buildSeconds", store.facts().buildSeconds}}},
      {"quadtree", sk.quadtree.domain == QuadtreeDomain::Geographic ? "geographic"
                   : sk.quadtree.domain == QuadtreeDomain::Model    ? "model"
                                                                    : "none"}};
  nlohmann::json tileset = {
      {"asset", {{"version", "1.1"}, {"generator", kGenerator}}},
      {"geometricError",
       std::max(diagonal, std::max(rootError, root["geometricError"].get<double>()))},
      {"root", std::move(root)},
      {"extras", {{"hlodr", std::move(frame)}}}};
  const std::string text = tileset.dump();
  if (auto s = writeFile(tmp / "tileset.json", text.data(), text.size()); !s) return s.error();
  report.bytes += text.size();

  // Into place: an earlier export goes only now that the new one is complete.
  if (fs::exists(dir, ec)) {
    fs::remove_all(dir, ec);
    if (ec) return makeError("cannot replace " + dir.string() + ": " + ec.message());
  }
  fs::rename(tmp, dir, ec);
  if (ec) return makeError("cannot move the tileset to " + dir.string() + ": " + ec.message());
  cleanup.keep = true;
  return report;
}

}  // namespace hlod::tiles
