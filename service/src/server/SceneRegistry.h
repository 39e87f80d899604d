#pragma once
// The scenes of the server: every node store NAME.hlod/ directly in the data folder is scene
// NAME. Each store is opened once and shared by all sessions on it, with one decoded node cache
// for the whole server. Scene ids are looked up here, never turned into paths: a client cannot
// name anything outside the data folder.
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hlod/runtime/Camera.h"
#include "hlod/runtime/FrameDriver.h"
#include "hlod/runtime/NodeCache.h"
#include "hlod/scene/SceneFile.h"
#include "hlod/store/NodeStore.h"

namespace service::server {

struct Scene {
  std::string id;
  std::filesystem::path path;
  std::shared_ptr<const hlod::NodeStore> store;
  std::uint32_t cacheStore = 0;  // its number in the shared NodeCache's keys
  // The store's up axis and framing (hlod::frameBounds), as `hlodr render MODEL` would show it,
  // or a scene file's camera where it has one (its up defaults to the store's).
  hlod::Camera defaultCamera(double aspect,
                             const std::optional<hlod::SceneCamera>& sceneCamera = {}) const;
  nlohmann::json summary() const;  // for GET /api/scenes
  nlohmann::json detail() const;   // for GET /api/scenes/{id}

  // The timing of the last session at a frame size: a new session starts from it (the cold
  // start). vTime 0 where none is known.
  hlod::FrontTiming knownTiming(int width, int height) const;
  void rememberTiming(int width, int height, const hlod::FrontTiming& timing);

 private:
  mutable std::mutex mutex_;
  std::map<std::pair<int, int>, hlod::FrontTiming> timings_;
};

// Where a store came from, as it records it: "3d-tiles" (a tileset imported by `hlodr build
// TILESET.json`), "city" (a city folder), "cityjson", "inputs" (several inputs placed on the
// globe together) or "mesh" (a model file: OBJ, PLY, OFF, STL, glTF; also a store built before
// its CRS was recorded).
std::string sourceOf(const hlod::Skeleton& sk);

class SceneRegistry {
 public:
  SceneRegistry(std::filesystem::path dataDir, std::uint64_t cacheCapBytes);
  // Opens the stores not opened yet; a broken one is skipped with a line to `log`.
  void scan(const std::function<void(const std::string&)>& log);
  std::shared_ptr<Scene> find(const std::string& id) const;
  // The scene files (NAME.json, docs/scene.md) directly in the data folder, read afresh, by name,
  // with the store id each names. Other JSON files (camera paths, broken scenes) are left out: a
  // request that names one gets its parse error.
  struct SceneFileEntry {
    std::string name;
    std::string storeId;
    hlod::SceneFile file;
  };
  std::vector<SceneFileEntry> sceneFiles() const;
  // The store id a scene file's "store" names: its folder name without ".hlod" ("city.hlod",
  // "../out/city.hlod" and "city" are all "city").
  static std::string storeIdOf(const std::string& storePath);
  std::vector<std::shared_ptr<Scene>> all() const;
  const std::shared_ptr<hlod::NodeCache>& cache() const { return cache_; }
  const std::filesystem::path& dataDir() const { return dataDir_; }
  // Scene ids: 1..64 of [A-Za-z0-9_.-], not starting with a dot.
  static bool validId(const std::string& id);

 private:
  std::filesystem::path dataDir_;
  std::shared_ptr<hlod::NodeCache> cache_;
  mutable std::mutex mutex_;
  std::map<std::string, std::shared_ptr<Scene>> scenes_;
  std::map<std::string, std::filesystem::file_time_type> broken_;  // skipped, by skeleton time
  std::uint32_t nextCacheStore_ = 0;
};

}  // namespace service::server
