// Procedural city: block generation and the streaming writer of a city folder (see City.h).
#include "hlod/city/City.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <exception>
#include <fstream>
#include <memory>
#include <mutex>
#include <system_error>
#include <thread>

#include <nlohmann/json.hpp>

#include "city/CityPlan.h"
#include "hlod/export/ImageWriter.h"
#include "hlod/export/PlyWriter.h"

namespace hlod {

namespace fs = std::filesystem;

namespace {

// PNG at compression level 1 and no row filter: these noisy textures barely shrink at higher
// levels or with filters, and the defaults (level 6, adaptive filters) made PNG encoding take 4x
// as long as everything else in writeCity together.
Status writePng(const fs::path& path, const Image& image) {
  return writeImageFile(path, image, {.alpha = true, .fastPng = true});
}

}  // namespace

std::string cityBlockName(int index) {
  char name[32];
  std::snprintf(name, sizeof name, "block_%04d", index);
  return name;
}

LatLon cityToLatLon(const glm::dvec3& p) {
  static const EnuFrame frame(LatLon{kCityOriginLat, kCityOriginLon, 0.0});
  return frame.toGeodetic(p);
}

Mesh generateBlock(const CityOptions& options, int index) {
  const city::BlockPlan plan = city::planBlock(options.seed, index, options.textureSize);
  Mesh mesh = city::buildBlockGeometry(plan);
  mesh.name = cityBlockName(index);
  mesh.baseColor = glm::vec4(1.0f);
  mesh.oneSided = true;  // closed boxes and ground, wound outwards (BlockGeometry)
  if (options.textures) mesh.texture = std::make_shared<const Image>(city::paintBlockTexture(plan));
  return mesh;
}

std::uint64_t estimateCityBytes(const CityOptions& options) {
  constexpr std::uint64_t kPlyBytesPerBlock = 2'400'000;
  constexpr double kPngBytesPerTexel = 1.3;
  constexpr std::uint64_t kManifestBytesPerBlock = 400;
  const double texels = double(options.textureSize) * double(options.textureSize);
  const auto perBlock = kPlyBytesPerBlock + kManifestBytesPerBlock +
                        static_cast<std::uint64_t>(std::ceil(texels * kPngBytesPerTexel));
  return static_cast<std::uint64_t>(std::max(options.blocks, 0)) * perBlock;
}

namespace {

std::string gigabytes(std::uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f GB", double(bytes) / 1e9);
  return text;
}

}  // namespace

Status writeCity(const fs::path& dir, const CityOptions& options, const CityProgressFn& progress) {
  if (options.blocks < 1 || options.blocks > kMaxCityBlocks)
    return makeError("block count " + std::to_string(options.blocks) + " is outside [1, " +
                     std::to_string(kMaxCityBlocks) + "]");
  if (options.textureSize < 64 || options.textureSize > 4096)
    return makeError("texture size " + std::to_string(options.textureSize) +
                     " is outside [64, 4096]");
  if (dir.empty()) return makeError("no output directory given");
  std::error_code ec;
  // 100,000 blocks are about 270 GB: say so before filling the disk (and before creating dir).
  fs::path existing = fs::absolute(dir, ec);
  while (!fs::exists(existing, ec) && existing != existing.parent_path())
    existing = existing.parent_path();
  const std::uint64_t needed = estimateCityBytes(options);
  const fs::space_info space = fs::space(existing, ec);
  if (!ec && space.available < needed)
    return makeError("writing " + std::to_string(options.blocks) + " blocks takes about " +
                     gigabytes(needed) + ", but the disk of " + dir.string() + " has only " +
                     gigabytes(space.available) + " free (write fewer blocks, or elsewhere)");
  fs::create_directories(dir, ec);
  std::error_code ec2;
  if (ec && !fs::is_directory(dir, ec2))
    return makeError("cannot create directory " + dir.string() + ": " + ec.message());
  if (!fs::is_directory(dir, ec)) return makeError(dir.string() + " is not a directory");

  const fs::path tmp = dir / "city.json.tmp";
  {
    std::ofstream probe(tmp, std::ios::binary | std::ios::trunc);
    if (!probe) return makeError("cannot write into directory " + dir.string());
  }

  // Blocks are independent: a few workers each generate and write whole blocks (so at most one
  // block per worker is in memory), the caller's thread collects them in order for the manifest
  // and the progress callback. The files do not depend on which worker wrote them.
  struct Written {
    bool ready = false;
    std::string error;
    std::size_t triangles = 0;
    Aabb bounds;
  };
  const int n = options.blocks;
  std::vector<Written> written(static_cast<std::size_t>(n));
  std::mutex mutex;
  std::condition_variable readyCv;
  std::atomic<int> next{0};
  std::atomic<bool> failed{false};
  auto worker = [&] {
    // An index once taken is always finished, so the collector never waits for nothing.
    while (!failed) {
      const int i = next++;
      if (i >= n) return;
      Written w;
      try {
        CityOptions withTextures = options;
        withTextures.textures = true;
        const Mesh mesh = generateBlock(withTextures, i);
        const std::string name = cityBlockName(i);
        Status s = writePly(dir / (name + ".ply"), mesh, name + ".png");
        if (s) s = writePng(dir / (name + ".png"), *mesh.texture);
        if (!s) w.error = s.message();
        w.triangles = mesh.triangleCount();
        w.bounds = mesh.bounds();
      } catch (const std::exception& e) {  // out of memory: report, do not terminate
        w.error = cityBlockName(i) + ": " + e.what();
      }
      w.ready = true;
      if (!w.error.empty()) failed = true;
      {
        std::lock_guard lock(mutex);
        written[static_cast<std::size_t>(i)] = std::move(w);
      }
      readyCv.notify_all();
    }
  };
  const int workers =
      std::clamp(static_cast<int>(std::thread::hardware_concurrency()), 1, std::min(8, n));
  std::vector<std::thread> threads;
  for (int t = 0; t < workers; ++t) threads.emplace_back(worker);
  auto joinAll = [&] {
    for (auto& t : threads) t.join();
    threads.clear();
  };

  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  nlohmann::ordered_json blocks = nlohmann::ordered_json::array();
  std::size_t total = 0;
  for (int i = 0; i < n; ++i) {
    Written w;
    {
      std::unique_lock lock(mutex);
      readyCv.wait(lock, [&] { return written[static_cast<std::size_t>(i)].ready; });
      w = written[static_cast<std::size_t>(i)];
    }
    if (!w.error.empty()) {
      failed = true;
      joinAll();
      return makeError(w.error);
    }
    const std::string name = cityBlockName(i);
    const LatLon anchor = cityToLatLon(w.bounds.centre());
    total += w.triangles;
    const Aabb& box = w.bounds;
    blocks.push_back(
        {{"name", name},
         {"mesh", name + ".ply"},
         {"texture", name + ".png"},
         {"triangles", w.triangles},
         {"bounds", {{box.min.x, box.min.y, box.min.z}, {box.max.x, box.max.y, box.max.z}}},
         {"anchor", {{"lat", anchor.lat}, {"lon", anchor.lon}, {"height", anchor.height}}}});
    if (progress)
      progress({i + 1, n, total, std::chrono::duration<double>(Clock::now() - start).count()});
  }
  joinAll();

  const nlohmann::ordered_json manifest = {
      {"format", "hlodr-city"},
      {"version", 1},
      {"seed", options.seed},
      {"blocks", std::move(blocks)},
      {"origin", {{"lat", kCityOriginLat}, {"lon", kCityOriginLon}, {"height", 0.0}}},
      {"triangles", total}};
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << manifest.dump(1) << '\n';
    out.close();
    if (!out) return makeError("cannot write " + tmp.string());
  }
  fs::rename(tmp, dir / "city.json", ec);
  if (ec) return makeError("cannot rename " + tmp.string() + " to city.json: " + ec.message());
  return Ok{};
}

}  // namespace hlod
