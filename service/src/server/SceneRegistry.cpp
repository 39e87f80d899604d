#include "server/SceneRegistry.h"

#include <algorithm>

#include "hlod/runtime/Framing.h"
#include "service/SceneLoading.h"

namespace service::server {

namespace fs = std::filesystem;

hlod::Camera Scene::defaultCamera(double aspect,
                                  const std::optional<hlod::SceneCamera>& sceneCamera) const {
  hlod::Camera c = service::storeCamera(store->skeleton(), 50.0, aspect);
  if (sceneCamera) {
    c.position = sceneCamera->position;
    c.target = sceneCamera->target;
    c.up = sceneCamera->up.value_or(c.up);
    c.fovY = sceneCamera->fov;
  }
  return c;
}

namespace {

nlohmann::json vec(const glm::dvec3& v) {
  return {v.x, v.y, v.z};
}

}  // namespace

std::string sourceOf(const hlod::Skeleton& sk) {
  // The store keeps no input format of its own: its builder's name and the CRS description its
  // importer wrote say it (TilesetImport, BuildFromInputs, CityJsonFrame). An hlodr export read
  // back keeps the store it came from, and so its source.
  const std::string& crs = sk.crs.description;
  if (sk.params.simplifier == hlod::kTilesetSimplifier || crs.starts_with("3D Tiles"))
    return "3d-tiles";
  if (crs.starts_with("city folder")) return "city";
  if (crs.starts_with("EPSG:") || crs.starts_with("none declared")) return "cityjson";
  if (crs.ends_with("inputs placed through ECEF in east-north-up metres at the first one's origin"))
    return "inputs";
  return "mesh";
}

nlohmann::json Scene::summary() const {
  const hlod::Skeleton& sk = store->skeleton();
  hlod::Aabb bounds;
  std::uint32_t depth = 0;
  std::uint64_t hlod0 = 0, leaves = 0;
  for (std::uint32_t r : sk.roots) bounds.extend(sk.nodes[r].bounds);
  for (std::uint32_t r : sk.blockRoots()) hlod0 += sk.nodes[r].numTri;
  for (std::uint32_t n = 0; n < sk.nodes.size(); ++n) {
    depth = std::max(depth, sk.nodes[n].level);
    if (sk.isLeaf(n)) leaves += sk.nodes[n].numTri;
  }
  const hlod::Camera cam = defaultCamera(16.0 / 9.0);
  return {{"id", id},
          {"nodes", sk.nodes.size()},
          {"levels", depth + 1},
          {"depth", depth},
          {"blocks", sk.blockRoots().size()},
          {"source", sourceOf(sk)},
          {"triangles",
           {{"input", store->facts().inputTriangles}, {"hlod0", hlod0}, {"leaves", leaves}}},
          {"bounds", {{"min", vec(bounds.min)}, {"max", vec(bounds.max)}}},
          // The page's orbit and walk stand on it: an earth-centred store's ellipsoid normal.
          {"up", vec(hlod::modelUpFrame(sk.up, bounds).up)},
          {"defaultCamera",
           {{"position", vec(cam.position)},
            {"target", vec(cam.target)},
            {"up", vec(cam.up)},
            {"fov", cam.fovY}}}};
}

nlohmann::json Scene::detail() const {
  nlohmann::json j = summary();
  const hlod::Skeleton& sk = store->skeleton();
  std::vector<std::pair<std::uint64_t, std::uint64_t>> perLevel;
  std::uint64_t memory = 0;
  for (const auto& n : sk.nodes) {
    if (n.level >= perLevel.size()) perLevel.resize(n.level + 1);
    ++perLevel[n.level].first;
    perLevel[n.level].second += n.numTri;
    memory += n.memoryBytes;
  }
  nlohmann::json levels = nlohmann::json::array();
  for (std::size_t l = 0; l < perLevel.size(); ++l)
    levels.push_back(
        {{"level", l}, {"nodes", perLevel[l].first}, {"triangles", perLevel[l].second}});
  j["levelsDetail"] = levels;
  j["payloadBytes"] = store->facts().payloadBytes;
  j["memoryBytes"] = memory;
  j["build"] = {{"levelFactor", sk.params.levelFactor},
                {"desiredTri", sk.params.desiredTri},
                {"simplifier", sk.params.simplifier},
                {"seconds", store->facts().buildSeconds}};
  return j;
}

hlod::FrontTiming Scene::knownTiming(int width, int height) const {
  std::lock_guard lock(mutex_);
  auto it = timings_.find({width, height});
  return it == timings_.end() ? hlod::FrontTiming{} : it->second;
}

void Scene::rememberTiming(int width, int height, const hlod::FrontTiming& timing) {
  if (!(timing.vTime > 0.0)) return;
  std::lock_guard lock(mutex_);
  timings_[{width, height}] = timing;
}

SceneRegistry::SceneRegistry(fs::path dataDir, std::uint64_t cacheCapBytes)
    : dataDir_(std::move(dataDir)), cache_(std::make_shared<hlod::NodeCache>(cacheCapBytes)) {}

bool SceneRegistry::validId(const std::string& id) {
  if (id.empty() || id.size() > 64 || id[0] == '.') return false;
  return std::all_of(id.begin(), id.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-' || c == '.';
  });
}

void SceneRegistry::scan(const std::function<void(const std::string&)>& log) {
  std::error_code ec;
  std::vector<std::pair<std::string, fs::path>> found;
  for (const auto& e : fs::directory_iterator(dataDir_, ec)) {
    const fs::path p = e.path();
    if (p.extension() != ".hlod" || !e.is_directory(ec)) continue;
    const std::string id = p.stem().string();
    if (!validId(id) || !fs::exists(p / "skeleton.bin", ec)) continue;
    found.emplace_back(id, p);
  }
  std::sort(found.begin(), found.end());
  for (const auto& [id, p] : found) {
    {
      std::lock_guard lock(mutex_);
      if (scenes_.count(id)) continue;
      auto b = broken_.find(id);
      if (b != broken_.end() && b->second == fs::last_write_time(p / "skeleton.bin", ec))
        continue;  // said once; tried again only when the store changes
    }
    auto store = hlod::NodeStore::open(p);
    if (!store) {
      log("scene " + id + " skipped: " + store.message());
      std::lock_guard lock(mutex_);
      broken_[id] = fs::last_write_time(p / "skeleton.bin", ec);
      continue;
    }
    if ((*store)->skeleton().roots.empty()) {
      log("scene " + id + " skipped: the store has no nodes");
      continue;
    }
    auto scene = std::make_shared<Scene>();
    scene->id = id;
    scene->path = p;
    scene->store = std::move(*store);
    std::lock_guard lock(mutex_);
    scene->cacheStore = nextCacheStore_++;
    broken_.erase(id);
    scenes_[id] = scene;
    log("scene " + id + ": " + std::to_string(scene->store->skeleton().nodes.size()) +
        " nodes from " + p.string());
  }
}

std::shared_ptr<Scene> SceneRegistry::find(const std::string& id) const {
  if (!validId(id)) return nullptr;
  std::lock_guard lock(mutex_);
  auto it = scenes_.find(id);
  return it == scenes_.end() ? nullptr : it->second;
}

std::string SceneRegistry::storeIdOf(const std::string& storePath) {
  std::string store = fs::path(storePath).filename().string();
  const std::string suffix = ".hlod";
  if (store.size() > suffix.size() && store.ends_with(suffix))
    store.resize(store.size() - suffix.size());
  return store;
}

std::vector<SceneRegistry::SceneFileEntry> SceneRegistry::sceneFiles() const {
  // Scene files are a few hundred bytes: anything large is not one, and a folder of thousands of
  // JSON files is not worth reading on every listing.
  constexpr std::uintmax_t kMaxBytes = 1 << 20;
  constexpr std::size_t kMaxFiles = 256;
  std::error_code ec;
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dataDir_, ec)) {
    const fs::path p = e.path();
    if (p.extension() != ".json" || !e.is_regular_file(ec) || !validId(p.filename().string()))
      continue;
    if (e.file_size(ec) > kMaxBytes || files.size() >= kMaxFiles) continue;
    files.push_back(p);
  }
  std::sort(files.begin(), files.end());
  std::vector<SceneFileEntry> out;
  for (const fs::path& p : files) {
    auto file = hlod::readSceneFile(p);
    if (file && !file->store.empty())
      out.push_back({p.filename().string(), storeIdOf(file->store), std::move(*file)});
  }
  return out;
}

std::vector<std::shared_ptr<Scene>> SceneRegistry::all() const {
  std::lock_guard lock(mutex_);
  std::vector<std::shared_ptr<Scene>> out;
  for (const auto& [id, s] : scenes_) out.push_back(s);
  return out;
}

}  // namespace service::server
