// importModel: picks the reader by extension, then validates what every reader produced, so the
// rest of hlodr can rely on finite coordinates, in-range indices and at least one triangle.
#include "hlod/import/Import.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "builder/ImageResize.h"
#include "hlod/import/InsideFolder.h"
#include "import/ImportUtil.h"

namespace hlod {
namespace import {

Result<std::string> readWholeFile(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    return fileError(path,
                     std::filesystem::exists(path, ec) ? "not a regular file" : "file not found");
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return fileError(path, "cannot open file");
  // One read of the known size; fall back to chunked reading for pipes and growing files.
  std::string bytes;
  const auto size = std::filesystem::file_size(path, ec);
  if (!ec && size > 0) {
    bytes.resize(static_cast<std::size_t>(size));
    bytes.resize(std::fread(bytes.data(), 1, bytes.size(), f));
  }
  char buffer[1 << 16];
  std::size_t n;
  while ((n = std::fread(buffer, 1, sizeof(buffer), f)) > 0) bytes.append(buffer, n);
  const bool failed = std::ferror(f) != 0;
  std::fclose(f);
  if (failed) return fileError(path, "read error");
  return bytes;
}

namespace {

// The warnings of the import running on this thread (importModel collects them into the
// Model): per thread, so that imports on the server's threads never mix their warnings.
thread_local std::vector<std::string>* t_warnings = nullptr;

// Collects this thread's import warnings into `w` while it lives.
struct WarningsInto {
  explicit WarningsInto(std::vector<std::string>* w) : outer(t_warnings) { t_warnings = w; }
  ~WarningsInto() { t_warnings = outer; }
  WarningsInto(const WarningsInto&) = delete;
  WarningsInto& operator=(const WarningsInto&) = delete;
  std::vector<std::string>* outer;
};

}  // namespace

void warn(const std::filesystem::path& path, const std::string& what) {
  if (t_warnings) t_warnings->push_back(path.string() + ": " + what);
}

std::shared_ptr<const Image> TextureCache::load(const std::filesystem::path& meshFile,
                                                const std::string& name) {
  std::string cleaned = name;
  // Files written on Windows use backslashes.
  std::replace(cleaned.begin(), cleaned.end(), '\\', '/');
  auto inside = insideFolder(meshFile.parent_path(), cleaned);
  if (!inside) {
    warn(meshFile, "texture not loaded: " + inside.message());
    return nullptr;
  }
  const std::filesystem::path& p = *inside;
  for (const auto& [q, img] : loaded_)
    if (q == p) return img;
  std::shared_ptr<const Image> image;
  auto r = loadImage(p);
  if (r.ok())
    image = std::make_shared<const Image>(std::move(r).value());
  else
    warn(meshFile, "texture not loaded (" + r.message() + ")");
  loaded_.emplace_back(p, image);
  return image;
}

namespace {

std::string lowerExtension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%g", v);
  return buf;
}

// The largest texture side hlodr draws: the GL limit of llvmpipe and of most GPUs. A larger
// texture failed to upload and its mesh was drawn black, with exit 0 and no word.
constexpr int kMaxTextureSide = 16384;

// A texture past kMaxTextureSide, shrunk to fit (its aspect kept) with a warning that names it;
// each shared texture once.
void shrinkLargeTextures(const std::filesystem::path& path, Model& model) {
  std::vector<std::pair<const Image*, std::shared_ptr<const Image>>> done;
  for (Mesh& mesh : model.meshes) {
    if (!mesh.texture) continue;
    const Image& t = *mesh.texture;
    const int side = std::max(t.width, t.height);
    if (side <= kMaxTextureSide) continue;
    auto it = std::find_if(done.begin(), done.end(), [&](const auto& d) { return d.first == &t; });
    if (it == done.end()) {
      const double scale = double(kMaxTextureSide) / side;
      const int w = std::max(1, int(t.width * scale)), h = std::max(1, int(t.height * scale));
      model.warnings.push_back(path.filename().string() + ": the texture of '" + mesh.name +
                               "' is " + std::to_string(t.width) + "x" + std::to_string(t.height) +
                               ", more than the " + std::to_string(kMaxTextureSide) +
                               " a side GL draws: resized to " + std::to_string(w) + "x" +
                               std::to_string(h));
      done.emplace_back(&t, std::make_shared<const Image>(resizeImage(t, w, h)));
      it = done.end() - 1;
    }
    mesh.texture = it->second;
  }
}

// Checks the invariants the rest of hlodr relies on; drops meshes without triangles.
Status validate(const std::filesystem::path& path, Model& model) {
  shrinkLargeTextures(path, model);
  std::vector<Mesh> kept;
  kept.reserve(model.meshes.size());
  std::vector<std::uint32_t> keptAs(model.meshes.size(), 0xffffffffu);  // for objectRuns
  std::size_t vertexBase = 0;
  for (std::size_t k = 0; k < model.meshes.size(); ++k) {
    Mesh& mesh = model.meshes[k];
    const std::size_t n = mesh.positions.size();
    for (std::size_t i = 0; i < n; ++i) {
      const auto& p = mesh.positions[i];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        return fileError(path, "vertex " + std::to_string(vertexBase + i) +
                                   " has a non-finite coordinate (" + fmt(p.x) + ", " + fmt(p.y) +
                                   ", " + fmt(p.z) + ")");
      for (int c = 0; c < 3; ++c)
        if (std::abs(p[c]) > kMaxCoordinate)
          return fileError(path, "vertex " + std::to_string(vertexBase + i) + " has coordinate " +
                                     fmt(p[c]) + ", beyond the range hlodr stores (at most " +
                                     fmt(kMaxCoordinate) + " in magnitude)");
    }
    if (mesh.indices.size() % 3 != 0) return fileError(path, "index count is not a multiple of 3");
    for (std::uint32_t idx : mesh.indices)
      if (idx >= n)
        return fileError(path, "face index " + std::to_string(idx) + " out of range (" +
                                   std::to_string(n) + " vertices)");
    if (!mesh.normals.empty() && mesh.normals.size() != n) mesh.normals.clear();
    for (auto& nrm : mesh.normals)
      if (!std::isfinite(nrm.x) || !std::isfinite(nrm.y) || !std::isfinite(nrm.z))
        nrm = glm::vec3(0.0f);
    if (!mesh.texCoords.empty() && mesh.texCoords.size() != n)
      return fileError(path, "texture coordinate count differs from vertex count");
    for (auto& uv : mesh.texCoords)
      if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) uv = glm::vec2(0.0f);
    vertexBase += n;
    if (!mesh.indices.empty()) {
      keptAs[k] = std::uint32_t(kept.size());
      kept.push_back(std::move(mesh));
    }
  }
  model.meshes = std::move(kept);
  // Runs follow their meshes; a run outside its mesh is a reader's bug, dropped all the same.
  std::erase_if(model.objectRuns, [&](ObjectRun& r) {
    if (r.mesh >= keptAs.size() || keptAs[r.mesh] == 0xffffffffu) return true;
    r.mesh = keptAs[r.mesh];
    const std::size_t tris = model.meshes[r.mesh].triangleCount();
    return r.firstTriangle > tris || r.triangleCount > tris - r.firstTriangle;
  });
  if (model.meshes.empty()) return fileError(path, "mesh has no triangles");
  return Ok{};
}

// .city.json and .cityjson say CityJSON by their name; another .json must say so inside.
bool cityJsonByName(const std::filesystem::path& path) {
  std::string name = path.filename().string();
  std::transform(name.begin(), name.end(), name.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  const auto endsWith = [&](std::string_view s) {
    return name.size() >= s.size() && name.compare(name.size() - s.size(), s.size(), s) == 0;
  };
  return endsWith(".city.json") || endsWith(".cityjson");
}

}  // namespace
}  // namespace import

bool isMeshFile(const std::filesystem::path& path) {
  const std::string ext = import::lowerExtension(path);
  if (import::cityJsonByName(path)) return true;
  if (ext == ".json") {
    auto bytes = import::readWholeFile(path);
    return bytes.ok() && import::looksLikeCityJson(*bytes);
  }
  return ext == ".obj" || ext == ".ply" || ext == ".off" || ext == ".stl" || ext == ".gltf" ||
         ext == ".glb" || ext == ".cityjson";
}

Result<GltfContent> importGltfBytes(const GltfBytes& in) {
  using namespace import;
  std::vector<std::string> warnings;
  Result<GltfContent> scene = makeError("");
  {
    const WarningsInto collect(&warnings);
    try {
      scene = readGltfBytes(in);
    } catch (const std::bad_alloc&) {
      return fileError(in.name, "out of memory while reading");
    } catch (const std::exception& e) {
      return fileError(in.name, std::string("read failed: ") + e.what());
    }
  }
  if (!scene) return scene;
  scene->model.warnings = std::move(warnings);
  if (scene->model.meshes.empty()) return scene;
  if (auto s = validate(in.name, scene->model); !s.ok()) {
    if (scene->model.meshes.empty()) return scene;  // no triangles: an empty content
    return s.error();
  }
  return scene;
}

Result<Model> importModel(const std::filesystem::path& path, const ImportOptions& options) {
  using namespace import;
  const std::string ext = lowerExtension(path);
  // CityJSON is .city.json, .cityjson, or any .json whose content says so (read below).
  const bool byName = cityJsonByName(path);
  const bool json = byName || ext == ".json";
  if (!json && !isMeshFile(path))
    return fileError(path, "unknown mesh format '" + ext +
                               "' (expected .obj, .ply, .off, .stl, "
                               ".gltf, .glb, .city.json or .cityjson)");
  Result<Model> model = makeError("");
  std::vector<std::string> warnings;
  const WarningsInto collect(&warnings);
  try {
    if (ext == ".gltf" || ext == ".glb") {
      std::error_code ec;
      if (!std::filesystem::is_regular_file(path, ec)) return fileError(path, "file not found");
      model = readGltf(path, ext == ".glb");
    } else {
      auto bytes = readWholeFile(path);
      if (!bytes.ok()) return bytes.error();
      if (bytes->empty()) return fileError(path, "file is empty");
      if (json && !byName && !looksLikeCityJson(*bytes))
        return fileError(path, "a .json file that is not CityJSON (no \"type\": \"CityJSON\")");
      if (json)
        model = readCityJson(path, *bytes, options);
      else if (ext == ".ply")
        model = readPly(path, *bytes);
      else if (ext == ".off")
        model = readOff(path, *bytes);
      else if (ext == ".stl")
        model = readStl(path, *bytes);
      else
        model = readObj(path, *bytes);
    }
  } catch (const std::bad_alloc&) {
    return fileError(path, "out of memory while reading");
  } catch (const std::exception& e) {
    return fileError(path, std::string("read failed: ") + e.what());
  }
  if (!model.ok()) return model;
  model->warnings = std::move(warnings);
  for (auto& mesh : model->meshes)
    if (mesh.name.empty()) mesh.name = path.stem().string();
  if (auto s = validate(path, *model); !s.ok()) return s.error();
  return model;
}

}  // namespace hlod
