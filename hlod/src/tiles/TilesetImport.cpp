// buildStoreFromTileset: a 3D Tiles tileset as a node store, its hierarchy kept
// (hlod/tiles/TilesetImport.h). The per-node measures are Lakhia et al. III-B's (eq. 1-3), as the
// builder computes them; the frames are 3D Tiles 1.1 sec. "Transforms".
#include "hlod/tiles/TilesetImport.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <unordered_map>

#include "builder/Preprocess.h"
#include "builder/SlabPartition.h"
#include "hlod/builder/HlodBuilder.h"
#include "hlod/geodesy/EarthCentred.h"
#include "hlod/import/Import.h"
#include "hlod/parry/Splats.h"
#include "hlod/store/NodeStore.h"
#include "hlod/tiles/MergeMaterials.h"
#include "hlod/tiles/TileFormats.h"
#include "tiles/TilesetFrame.h"

namespace hlod::tiles {

namespace fs = std::filesystem;

namespace {

// Composite tiles hold tiles; they may nest, this deep at most.
constexpr int kMaxCmptNesting = 4;

double determinant(const AxisMap& m) {
  return glm::determinant(m.matrix());
}

// A number from an hlodr export's extras, or `fallback`.
double numberIn(const nlohmann::json& j, const char* key, double fallback) {
  return j.is_object() && j.contains(key) && j[key].is_number() ? j[key].get<double>() : fallback;
}

std::optional<glm::dvec3> vec3From(const nlohmann::json& j, const char* key) {
  if (!j.is_object() || !j.contains(key) || !j[key].is_array() || j[key].size() != 3)
    return std::nullopt;
  glm::dvec3 v;
  for (int k = 0; k < 3; ++k) {
    if (!j[key][std::size_t(k)].is_number()) return std::nullopt;
    v[k] = j[key][std::size_t(k)].get<double>();
    if (!std::isfinite(v[k])) return std::nullopt;
  }
  return v;
}

// Where the tiles' coordinates go in hlodr's world.
struct WorldFrame {
  bool own = false;             // an hlodr export: its extras describe the store
  glm::dmat4 rootInverse{1.0};  // own: the root transform (its placement) undone
  glm::dmat4 tilesetToWorld{1.0};
  std::optional<EnuFrame> enu;  // an earth-centred tileset: the ENU frame of the world
  ModelCrs crs;
  std::optional<UpAxis> up;  // known from the frame (else from the surfaces)
  std::string description;
};

// A texture's pixels, for finding textures that nodes share (an export's shared textures come
// back as one Image per GLB).
std::uint64_t imageHash(const Image& image) {
  std::uint64_t h =
      1469598103934665603ull ^ std::uint64_t(image.width) ^ (std::uint64_t(image.height) << 32);
  for (std::uint8_t b : image.pixels) h = (h ^ b) * 1099511628211ull;
  return h;
}

class Importer {
 public:
  Importer(const TilesetImportOptions& options, TilesetImportReport& report)
      : options_(options), report_(report) {}

  Status run(const fs::path& tilesetJson, const fs::path& storeDir,
             const TilesetImportProgressFn& progress) {
    const auto t0 = std::chrono::steady_clock::now();
    auto tree = readTilesetTree(tilesetJson, options_.limits);
    if (!tree) return tree.error();
    tree_ = std::move(*tree);
    report_.tiles = tree_.tiles.size();
    for (auto& w : tree_.warnings) report_.warnings.push_back(std::move(w));
    chooseFrame();
    report_.hlodrExport = frame_.own;
    report_.frame = frame_.description;
    auto writer = NodeStoreWriter::create(storeDir);
    if (!writer) return writer.error();
    writer_ = std::move(*writer);

    inherited_.resize(tree_.tiles.size());
    nodeOfTile_.assign(tree_.tiles.size(), -1);
    for (std::size_t i = 0; i < tree_.tiles.size(); ++i) {
      if (auto s = processTile(std::uint32_t(i)); !s) return s;
      if (progress) progress({i + 1, tree_.tiles.size()});
    }
    if (nodes_.empty())
      return makeError(tilesetJson.string() + ": no tile holds triangles (nothing to draw)");
    auto skeleton = assemble();
    if (!skeleton) return skeleton.error();
    StoreFacts facts;
    facts.blockCount = std::uint32_t(skeleton->blockRoots().size());
    facts.inputTriangles = leafTriangles(*skeleton);
    facts.buildSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (frame_.own && tree_.hlodr.contains("facts")) {
      const nlohmann::json& f = tree_.hlodr["facts"];
      if (f.is_object() && f.contains("inputTriangles") && f["inputTriangles"].is_number_unsigned())
        facts.inputTriangles = f["inputTriangles"].get<std::uint64_t>();
    }
    if (auto s = writer_->finish(*skeleton, facts); !s) return s;
    report_.nodes = skeleton->nodes.size();
    report_.skeleton = std::move(*skeleton);
    return Ok{};
  }

 private:
  struct Node {
    std::uint32_t tile = 0;
    NodeInfo info;
    glm::dvec3 areaNormal{0.0};  // area-weighted normal sum (for the up axis)
  };

  static std::uint64_t leafTriangles(const Skeleton& s) {
    std::uint64_t n = 0;
    for (const NodeInfo& info : s.nodes)
      if (info.childCount == 0) n += info.numTri;
    return n;
  }

  const std::string& nameOf(std::uint32_t tile) const { return tree_.tiles[tile].name; }

  // The frame: an hlodr export's, an earth-centred tileset's ENU frame, or its own.
  void chooseFrame() {
    const TileRecord& root = tree_.tiles.front();
    const nlohmann::json& h = tree_.hlodr;
    bool own = h.is_object() && numberIn(h, "format", 0) == 1 && h.contains("worldToTile");
    for (const TileRecord& t : tree_.tiles)
      if (!t.contents.empty() && !(t.hlodr.is_object() && t.hlodr.contains("node"))) own = false;
    if (own) {
      const nlohmann::json& m = h["worldToTile"];
      AxisMap u;
      bool ok = m.is_object() && m.contains("axis") && m.contains("sign") && m["axis"].is_array() &&
                m["sign"].is_array() && m["axis"].size() == 3 && m["sign"].size() == 3;
      int seen = 0;
      for (int k = 0; ok && k < 3; ++k) {
        ok = m["axis"][std::size_t(k)].is_number_integer() && m["sign"][std::size_t(k)].is_number();
        if (!ok) break;
        const int a = m["axis"][std::size_t(k)].get<int>();
        const double s = m["sign"][std::size_t(k)].get<double>();
        ok = a >= 0 && a < 3 && (s == 1.0 || s == -1.0) && !(seen & (1 << a));
        if (ok) {
          seen |= 1 << a;
          u.axis[k] = a;
          u.sign[k] = float(s);
        }
      }
      const std::optional<UpAxis> up = h.contains("up") && h["up"].is_string()
                                           ? parseUpAxis(h["up"].get<std::string>())
                                           : std::nullopt;
      if (ok && up) {
        frame_.own = true;
        frame_.rootInverse = glm::inverse(root.transform);
        frame_.tilesetToWorld = glm::dmat4(u.inverse().matrix());
        frame_.up = *up;
        if (h.contains("crs") && h["crs"].is_object()) {
          const nlohmann::json& c = h["crs"];
          frame_.crs.epsg = int(numberIn(c, "epsg", 0));
          frame_.crs.description = c.value("description", std::string());
          frame_.crs.toEnu = c.value("toEnu", false);
          if (auto o = vec3From(c, "origin")) {
            frame_.crs.originLat = o->x;
            frame_.crs.originLon = o->y;
            frame_.crs.originHeight = o->z;
          }
        }
        frame_.description = "an hlodr export, read back in the frame it was exported from";
        return;
      }
    }
    const glm::dvec3 c = root.volumeCentre;
    if (root.region || isEarthCentred(c)) {
      LatLon origin = ecefToGeodetic(c);
      if (root.region) origin.height = root.regionMinHeight;
      frame_.enu.emplace(origin);
      frame_.tilesetToWorld = glm::dmat4(frame_.enu->rotation());
      frame_.tilesetToWorld[3] =
          glm::dvec4(-(frame_.enu->rotation() * frame_.enu->originEcef()), 1.0);
      frame_.up = UpAxis::Z;
      frame_.crs.epsg = 4978;
      frame_.crs.toEnu = true;
      frame_.crs.originLat = origin.lat;
      frame_.crs.originLon = origin.lon;
      frame_.crs.originHeight = origin.height;
      char buf[200];
      std::snprintf(buf, sizeof buf,
                    "3D Tiles, earth-centred (EPSG:4978): east-north-up metres at %.6f, %.6f, "
                    "%.1f m",
                    origin.lat, origin.lon, origin.height);
      frame_.crs.description = buf;
      frame_.description = buf;
      return;
    }
    frame_.description = "the tileset's own frame (not earth-centred)";
    frame_.crs.description = "3D Tiles, local frame";
  }

  // Tile frame -> world.
  glm::dmat4 tileToWorld(const TileRecord& t) const {
    if (!frame_.own) return frame_.tilesetToWorld * t.transform;
    // An export has its only transform on the root: undone exactly when the tile carries it.
    const glm::dmat4 rel = t.transform == tree_.tiles.front().transform
                               ? glm::dmat4(1.0)
                               : frame_.rootInverse * t.transform;
    return frame_.tilesetToWorld * rel;
  }

  glm::dvec3 worldOfTilesetPoint(const glm::dvec3& p) const {
    if (!frame_.own) return glm::dvec3(frame_.tilesetToWorld * glm::dvec4(p, 1.0));
    return glm::dvec3(frame_.tilesetToWorld * frame_.rootInverse * glm::dvec4(p, 1.0));
  }

  // The meshes of one content file (or a cmpt's inner tile), in world coordinates.
  Status loadContent(std::uint32_t tile, const fs::path& file, std::string_view bytes,
                     std::vector<Mesh>& out, int nesting) {
    const TileRecord& t = tree_.tiles[tile];
    const std::string what =
        nameOf(tile) + ": content " + file.lexically_relative(tree_.folder).generic_string();
    const TileFormat format = detectTileFormat(bytes);
    GltfBytes g;
    g.name = what;
    g.folder = tree_.folder;
    g.baseDir = file.parent_path();
    g.oneSidedFromMaterial = true;
    std::optional<glm::dvec3> rtc;
    switch (format) {
      case TileFormat::Glb:
      case TileFormat::GltfJson:
        g.bytes = bytes;
        g.binary = format == TileFormat::Glb;
        break;
      case TileFormat::B3dm: {
        auto b = parseB3dm(bytes);
        if (!b) return makeError(what + ": " + b.message());
        g.bytes = b->glb;
        rtc = b->rtcCenter;
        break;
      }
      case TileFormat::Cmpt: {
        if (nesting >= kMaxCmptNesting) return makeError(what + ": cmpt nested too deep");
        auto inner = parseCmpt(bytes);
        if (!inner) return makeError(what + ": " + inner.message());
        for (std::string_view part : *inner)
          if (auto s = loadContent(tile, file, part, out, nesting + 1); !s) return s;
        return Ok{};
      }
      case TileFormat::I3dm:
      case TileFormat::Pnts:
        report_.warnings.push_back(what + ": " + tileFormatName(format) +
                                   " content holds no triangles hlodr draws; skipped");
        return Ok{};
      case TileFormat::Tileset:
      case TileFormat::Unknown:
        return makeError(what + ": not a tile format hlodr reads");
    }
    auto scene = importGltfBytes(g);
    if (!scene) return scene.error();
    for (auto& w : scene->model.warnings) report_.warnings.push_back(std::move(w));
    if (!rtc) rtc = scene->rtcCenter;
    // glTF (y up) -> tile frame (z up) -> RTC -> tile transforms -> world.
    const glm::dmat4 toWorld = tileToWorld(t);
    const glm::dmat3 linear(toWorld);
    const glm::dmat3 normalMatrix = glm::transpose(glm::inverse(linear));
    const bool mirrored = glm::determinant(linear) * determinant(t.contentUp) < 0.0;
    const glm::dvec3 offset = rtc.value_or(glm::dvec3(0.0));
    for (Mesh& m : scene->model.meshes) {
      for (glm::dvec3& p : m.positions) {
        const glm::dvec3 q = t.contentUp.apply(p) + offset;
        p = glm::dvec3(toWorld * glm::dvec4(q, 1.0));
        for (int k = 0; k < 3; ++k)
          if (!std::isfinite(p[k]) || std::abs(p[k]) > kMaxCoordinate)
            return makeError(what + ": a vertex lies beyond the range hlodr stores");
      }
      for (glm::vec3& n : m.normals) {
        const glm::dvec3 v = normalMatrix * glm::dvec3(t.contentUp.apply(n));
        const double len = glm::length(v);
        n = glm::vec3(len > 0.0 && std::abs(len - 1.0) > 1e-6 ? v / len : v);
      }
      if (mirrored)
        for (std::size_t k = 0; k + 2 < m.indices.size(); k += 3)
          std::swap(m.indices[k + 1], m.indices[k + 2]);
      out.push_back(std::move(m));
    }
    return Ok{};
  }

  Status loadTile(std::uint32_t tile, std::vector<Mesh>& out) {
    for (const fs::path& file : tree_.tiles[tile].contents) {
      const std::string what =
          nameOf(tile) + ": content " + file.lexically_relative(tree_.folder).generic_string();
      std::error_code ec;
      if (!fs::is_regular_file(file, ec)) return makeError(what + " not found");
      const auto size = fs::file_size(file, ec);
      if (ec || size > options_.maxContentBytes)
        return makeError(what + ": larger than " + std::to_string(options_.maxContentBytes) +
                         " bytes");
      std::string bytes(size, '\0');
      std::FILE* f = std::fopen(file.c_str(), "rb");
      if (!f) return makeError(what + ": cannot open");
      const bool read = std::fread(bytes.data(), 1, bytes.size(), f) == bytes.size();
      std::fclose(f);
      if (!read) return makeError(what + ": cannot read");
      if (bytes.empty()) return makeError(what + " is empty");
      ++report_.contents;
      if (auto s = loadContent(tile, file, bytes, out, 0); !s) return s;
    }
    return Ok{};
  }

  // Hands a mesh down to a tile's children: each triangle to the child whose bounding volume's
  // centre is nearest its centroid (ADD refinement becomes REPLACE).
  void handDown(std::uint32_t tile, const Mesh& mesh) {
    const std::vector<std::uint32_t>& children = tree_.tiles[tile].children;
    std::vector<glm::dvec3> centres;
    for (std::uint32_t c : children)
      centres.push_back(worldOfTilesetPoint(tree_.tiles[c].volumeCentre));
    std::vector<std::vector<std::uint32_t>> parts(children.size());
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
      const glm::dvec3 p = centroid(mesh, t);
      std::size_t best = 0;
      for (std::size_t k = 1; k < centres.size(); ++k)
        if (glm::length(p - centres[k]) < glm::length(p - centres[best])) best = k;
      parts[best].push_back(std::uint32_t(t));
    }
    for (std::size_t k = 0; k < children.size(); ++k)
      if (!parts[k].empty()) inherited_[children[k]].push_back(subMesh(mesh, parts[k]));
  }

  Status processTile(std::uint32_t tile) {
    const TileRecord& t = tree_.tiles[tile];
    std::vector<Mesh> meshes;
    if (auto s = loadTile(tile, meshes); !s) return s;
    const bool own = std::any_of(meshes.begin(), meshes.end(),
                                 [](const Mesh& m) { return m.triangleCount() > 0; });
    std::vector<Mesh> handed = std::move(inherited_[tile]);
    inherited_[tile] = {};
    for (Mesh& m : handed) meshes.push_back(std::move(m));
    std::erase_if(meshes, [](const Mesh& m) { return m.triangleCount() == 0; });
    if (t.add) ++report_.addTiles;
    if (!own) ++report_.emptyTiles;
    if (meshes.empty()) return Ok{};  // no node: its children take its place
    MergedMesh merged = mergeMaterials(meshes);
    meshes = {};
    if (merged.wrappedMeshes > 0)
      report_.warnings.push_back(nameOf(tile) + ": " + std::to_string(merged.wrappedMeshes) +
                                 " repeating textures wrapped per vertex into one atlas");
    if (!own && !t.children.empty()) {
      handDown(tile, merged.mesh);  // only what it inherited: its children draw it
      return Ok{};
    }
    if (t.add && !t.children.empty()) handDown(tile, merged.mesh);

    Node node;
    node.tile = tile;
    NodeInfo& info = node.info;
    const Mesh& mesh = merged.mesh;
    info.bounds = mesh.bounds();
    info.centre = info.bounds.centre();
    info.geometricError = t.geometricError;
    describeNode(info, mesh, options_.cTex);
    const NodeMeasures measures = measureNode(mesh, options_.cTex);
    node.areaNormal = glm::dvec3(measures.avgNormal) * measures.area;
    if (frame_.own) {
      // What the store had, where the export wrote it (the measures of its double positions).
      const nlohmann::json& h = t.hlodr;
      if (auto c = vec3From(h, "centre")) info.centre = *c;
      const auto lo = vec3From(h, "boundsMin"), hi = vec3From(h, "boundsMax");
      if (lo && hi) {
        info.bounds.min = *lo;
        info.bounds.max = *hi;
      }
      info.cost = numberIn(h, "cost", info.cost);
      info.staticBenefit = numberIn(h, "staticBenefit", info.staticBenefit);
      if (auto n = vec3From(h, "avgNormal")) info.avgNormal = glm::vec3(*n);
      info.geometricError = numberIn(h, "geometricError", info.geometricError);
    }
    LocalMesh local = localAround(mesh, info.centre);
    local.splats = makeSplats(local);
    info.splatCount = std::uint32_t(local.splats.size());
    report_.triangles += mesh.triangleCount();

    // A texture another node of this depth stored already is shared, not stored again.
    const NodeInfo* owner = nullptr;
    std::uint64_t key = 0;
    if (local.texture && local.texCoords.size() == local.positions.size()) {
      key = imageHash(*local.texture) ^ (std::uint64_t(t.depth) * 0x9E3779B97F4A7C15ull);
      const auto range = textures_.equal_range(key);
      for (auto it = range.first; it != range.second && !owner; ++it)
        if (it->second.image->width == local.texture->width &&
            it->second.image->height == local.texture->height &&
            it->second.image->pixels == local.texture->pixels)
          owner = &nodes_[it->second.node].info;
    }
    const StoredPayload payload = storePayload(local, owner == nullptr);
    if (auto s = owner ? writer_->appendSharingTexture(payload, *owner, info)
                       : writer_->appendStored(payload, info);
        !s)
      return s;
    if (!owner && local.texture) textures_.emplace(key, TextureOwner{local.texture, nodes_.size()});
    nodeOfTile_[tile] = int(nodes_.size());
    nodes_.push_back(node);
    return Ok{};
  }

  // The kept nodes' tree: each node's parent is its nearest ancestor tile that is a node.
  Result<Skeleton> assemble() {
    const std::size_t n = nodes_.size();
    std::vector<std::int64_t> parentNode(n, -1);
    std::vector<std::vector<std::uint32_t>> childNodes(n);
    std::vector<std::uint32_t> rootNodes;
    for (std::size_t k = 0; k < n; ++k) {
      std::uint32_t up = tree_.tiles[nodes_[k].tile].parent;
      while (up != TileRecord::kNone && nodeOfTile_[up] < 0) up = tree_.tiles[up].parent;
      if (up == TileRecord::kNone) {
        rootNodes.push_back(std::uint32_t(k));
      } else {
        parentNode[k] = nodeOfTile_[up];
        childNodes[std::size_t(nodeOfTile_[up])].push_back(std::uint32_t(k));
      }
    }
    Skeleton s;
    if (frame_.own) {
      auto restored = restoreExport(parentNode, childNodes);
      if (restored) return restored;
      report_.warnings.push_back("the export's node numbers do not form a store (" +
                                 restored.message() + "); numbered afresh");
      frame_.own = false;
      report_.hlodrExport = false;
    }
    // Breadth first from the roots: children contiguous, after their parents.
    std::vector<std::uint32_t> order = rootNodes, id(n, 0);
    for (std::size_t head = 0; head < order.size(); ++head)
      for (std::uint32_t c : childNodes[order[head]]) order.push_back(c);
    for (std::size_t k = 0; k < order.size(); ++k) id[order[k]] = std::uint32_t(k);
    s.nodes.resize(n);
    std::vector<std::uint32_t> blockOf(n, 0);
    for (std::size_t r = 0; r < rootNodes.size(); ++r) blockOf[rootNodes[r]] = std::uint32_t(r);
    for (std::size_t k = 0; k < order.size(); ++k) {
      const std::uint32_t src = order[k];
      NodeInfo info = nodes_[src].info;
      if (parentNode[src] >= 0) {
        const std::uint32_t p = std::uint32_t(parentNode[src]);
        blockOf[src] = blockOf[p];
        info.parent = id[p];
        info.level = s.nodes[id[p]].level + 1;
      } else {
        info.parent = kNoNode;
        info.level = 0;
        s.roots.push_back(std::uint32_t(k));
      }
      info.block = blockOf[src];
      info.childCount = std::uint32_t(childNodes[src].size());
      info.firstChild = info.childCount ? id[childNodes[src].front()] : 0;
      s.nodes[k] = info;
    }
    finishSkeleton(s, {});
    return s;
  }

  // An hlodr export: its own node numbers, blocks, levels and cells, checked by the skeleton
  // codec (an export edited by hand falls back to fresh numbers).
  Result<Skeleton> restoreExport(const std::vector<std::int64_t>& parentNode,
                                 const std::vector<std::vector<std::uint32_t>>& childNodes) {
    const std::size_t n = nodes_.size();
    std::vector<std::uint32_t> id(n);
    std::vector<char> used(n, 0);
    for (std::size_t k = 0; k < n; ++k) {
      const nlohmann::json& h = tree_.tiles[nodes_[k].tile].hlodr;
      const double v = numberIn(h, "node", -1.0);
      if (!(v >= 0.0 && v < double(n)) || v != std::floor(v) || used[std::size_t(v)]++)
        return makeError("node numbers are not 0.." + std::to_string(n - 1) + " once each");
      id[k] = std::uint32_t(v);
    }
    Skeleton s;
    s.nodes.resize(n);
    std::map<std::uint32_t, glm::dvec2> anchors;
    for (std::size_t k = 0; k < n; ++k) {
      const nlohmann::json& h = tree_.tiles[nodes_[k].tile].hlodr;
      NodeInfo info = nodes_[k].info;
      info.parent = parentNode[k] >= 0 ? id[std::size_t(parentNode[k])] : kNoNode;
      info.childCount = std::uint32_t(childNodes[k].size());
      info.firstChild = info.childCount ? id[childNodes[k].front()] : 0;
      for (std::size_t c = 0; c < childNodes[k].size(); ++c)
        if (id[childNodes[k][c]] != info.firstChild + c)
          return makeError("a node's children are not numbered one after another");
      info.level = std::uint32_t(numberIn(h, "level", 0.0));
      info.block = h.value("cell", false) ? kCellBlock : std::uint32_t(numberIn(h, "block", 0.0));
      if (h.contains("anchor") && h["anchor"].is_array() && h["anchor"].size() == 2 &&
          h["anchor"][0].is_number() && h["anchor"][1].is_number()) {
        const glm::dvec2 lonLat(h["anchor"][0].get<double>(), h["anchor"][1].get<double>());
        // JSON's 1e400 reads as infinity: the quadtree's cells need a place on the globe.
        if (!std::isfinite(lonLat.x) || !(std::abs(lonLat.y) <= 90.0))
          return makeError("a block's anchor is not a longitude and a latitude");
        anchors[id[k]] = lonLat;
      }
      s.nodes[id[k]] = info;
      if (info.parent == kNoNode) s.roots.push_back(id[k]);
    }
    std::sort(s.roots.begin(), s.roots.end());
    finishSkeleton(s, anchors);
    // The codec checks the whole structure (levels, cells, quadtree) as for any store.
    StoreFacts facts;
    facts.payloadBytes = writer_->payloadBytes();
    auto decoded = decodeSkeleton(encodeSkeleton(s, facts));
    if (!decoded) return decoded.error();
    return s;
  }

  // The frame, the build parameters and the quadtree of the blocks' roots.
  void finishSkeleton(Skeleton& s, const std::map<std::uint32_t, glm::dvec2>& exportAnchors) {
    s.crs = frame_.crs;
    if (options_.up) {
      s.up = *options_.up;
    } else if (frame_.up) {
      s.up = *frame_.up;
    } else {
      // The axis the surfaces face on average (area-weighted over every node).
      glm::dvec3 sum(0.0);
      for (const Node& node : nodes_) sum += node.areaNormal;
      const glm::dvec3 a = glm::abs(sum);
      s.up = a.x > a.y && a.x > a.z ? UpAxis::X : a.y > a.z ? UpAxis::Y : UpAxis::Z;
    }
    if (frame_.own && tree_.hlodr.contains("params") && tree_.hlodr["params"].is_object()) {
      const nlohmann::json& p = tree_.hlodr["params"];
      s.params.levelFactor = std::clamp(numberIn(p, "levelFactor", 4.0), 2.0, 64.0);
      s.params.desiredTri = std::uint32_t(std::max(1.0, numberIn(p, "desiredTri", 1.0)));
      s.params.cTex = std::clamp(numberIn(p, "cTex", options_.cTex), 0.0, 1.0);
      s.params.simplifier = p.value("simplifier", std::string(kTilesetSimplifier));
    } else {
      // What the tileset's tree looks like in the builder's terms: its mean branching and its
      // roots' median triangles.
      std::size_t inner = 0, children = 0;
      std::vector<std::uint32_t> rootTris;
      for (const NodeInfo& info : s.nodes) {
        if (info.childCount) ++inner;
        children += info.childCount;
      }
      for (std::uint32_t r : s.roots) rootTris.push_back(s.nodes[r].numTri);
      std::nth_element(rootTris.begin(), rootTris.begin() + rootTris.size() / 2, rootTris.end());
      s.params.levelFactor = std::clamp(inner ? double(children) / double(inner) : 2.0, 2.0, 64.0);
      s.params.desiredTri = std::max<std::uint32_t>(1, rootTris[rootTris.size() / 2]);
      s.params.cTex = options_.cTex;
      s.params.simplifier = kTilesetSimplifier;
    }
    // The quadtree over the blocks' roots (the hlod_0 nodes, below any cell nodes).
    Skeleton blocks = s;
    blocks.roots = s.blockRoots();
    blocks.quadtree = {};
    std::vector<std::optional<LatLon>> anchors(blocks.roots.size());
    for (std::size_t i = 0; i < blocks.roots.size(); ++i) {
      const std::uint32_t r = blocks.roots[i];
      if (frame_.own) {
        const bool geographic = tree_.hlodr.value("quadtree", std::string()) == "geographic";
        if (const auto a = exportAnchors.find(r); geographic && a != exportAnchors.end())
          anchors[i] = LatLon{a->second.y, a->second.x, 0.0};
      } else if (frame_.enu) {
        const Aabb& b = s.nodes[r].bounds;
        const LatLon a = frame_.enu->toGeodetic({b.centre().x, b.centre().y, b.min.z});
        // A block far out in space has no latitude: the quadtree then takes the model's frame.
        if (std::isfinite(a.lon) && std::abs(a.lat) <= 90.0) anchors[i] = a;
      }
    }
    s.quadtree = quadtreeOfRoots(blocks, anchors);
  }

  struct TextureOwner {
    std::shared_ptr<const Image> image;
    std::size_t node;
  };

  TilesetImportOptions options_;
  TilesetImportReport& report_;
  TilesetTree tree_;
  WorldFrame frame_;
  std::unique_ptr<NodeStoreWriter> writer_;
  std::vector<std::vector<Mesh>> inherited_;  // per tile: triangles its ADD parent handed down
  std::vector<int> nodeOfTile_;
  std::vector<Node> nodes_;
  std::unordered_multimap<std::uint64_t, TextureOwner> textures_;
};

}  // namespace

Result<TilesetImportReport> buildStoreFromTileset(const fs::path& tilesetJson,
                                                  const fs::path& storeDir,
                                                  const TilesetImportOptions& options,
                                                  const TilesetImportProgressFn& progress) {
  TilesetImportReport report;
  try {
    if (auto s = Importer(options, report).run(tilesetJson, storeDir, progress); !s)
      return s.error();
  } catch (const std::bad_alloc&) {
    return makeError(tilesetJson.string() + ": out of memory while importing the tileset");
  }
  return report;
}

}  // namespace hlod::tiles
