// The city manifest: the input is city.json, read from a folder that also holds block_0000.ply
// (a one-triangle block) for the manifest to name. A manifest that reads is then loaded block by
// block (the first four), which moves anchored blocks through the geographic frames.
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "FuzzSupport.h"
#include "hlod/city/City.h"

namespace {

constexpr const char* kBlock =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
    "property double z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0\n10 0 0\n0 10 5\n3 0 1 2\n";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto city = fuzz::tempFolder() / "city";
  static const bool made = [&] {
    std::filesystem::create_directories(city);
    fuzz::writeFile("city/block_0000.ply", kBlock);
    return true;
  }();
  (void)made;
  fuzz::writeFile("city/city.json", fuzz::view(data, size));
  auto manifest = hlod::readCityManifest(city);
  fuzz::report("readCityManifest", manifest);
  if (!manifest.ok()) return 0;
  for (const auto& b : manifest->blocks) {
    if (!std::isfinite(b.anchor.lat) || !std::isfinite(b.anchor.lon) ||
        std::abs(b.anchor.lat) > 90.0 || std::abs(b.anchor.lon) > 180.0)
      std::abort();
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(b.bounds.min[c]) || !std::isfinite(b.bounds.max[c])) std::abort();
  }
  for (std::size_t i = 0; i < manifest->blocks.size() && i < 4; ++i) {
    auto mesh = hlod::loadCityBlock(*manifest, i);
    fuzz::report("loadCityBlock", mesh);
    if (!mesh.ok()) continue;
    for (const auto& p : mesh->positions)
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) std::abort();
  }
  return 0;
}
