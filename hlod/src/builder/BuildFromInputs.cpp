// From inputs to a node store: city folders (loaded a block at a time) and imported models
// (buildings grouped into blocks), placed in one frame, each block anchored in latitude and
// longitude for the quadtree (Parry sec. 3), built on every core.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include "builder/InOrderPool.h"
#include "hlod/builder/HlodBuilder.h"
#include "hlod/city/City.h"
#include "hlod/geodesy/GeoReference.h"

namespace hlod {

namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The blocks of each unit prepared on every core and committed in order (InOrderPool.h).
using PrepareFn = std::function<Result<std::vector<PreparedBlock>>(std::size_t)>;
Status prepareInParallel(HlodBuilder& builder, std::size_t count, unsigned threads,
                         const PrepareFn& prepare,
                         const std::function<void(std::size_t, std::uint64_t)>& committed) {
  return prepareInOrder<std::vector<PreparedBlock>>(
      count, threads, prepare,
      [&](std::size_t i, std::vector<PreparedBlock>&& blocks) -> Status {
        std::uint64_t triangles = 0;
        for (PreparedBlock& b : blocks) {
          triangles += b.inputTriangles;
          if (auto s = builder.commitBlock(std::move(b)); !s) return s;
        }
        if (committed) committed(i, triangles);
        return Ok{};
      },
      "block");
}

// How a geo-referenced input moves into the ENU frame `to` through ECEF: exactly (a rotation
// and an offset) from another ENU frame; vertex by vertex through the inverse projection from a
// projected CRS, its normals then turned by the projection's local rotation at `centre` (grid
// north is not true north: up to a few degrees). One Placement per input, so that positions two
// of its blocks share move to the same place.
struct Placement {
  std::function<glm::dvec3(const glm::dvec3&)> point;
  glm::dmat3 turn{1.0};

  Placement(const GeoReference& from, const EnuFrame& to, const glm::dvec3& centre) {
    if (const EnuFrame* frame = from.frame()) {
      const EnuToEnu fromTo(*frame, to);
      turn = fromTo.rotation;
      point = [fromTo](const glm::dvec3& p) { return fromTo.point(p); };
      return;
    }
    point = [from, to](const glm::dvec3& p) { return to.fromEcef(from.toEcef(p)); };
    const glm::dvec3 o = point(centre);
    const glm::dvec3 east = glm::normalize(point(centre + glm::dvec3(1, 0, 0)) - o);
    glm::dvec3 north = point(centre + glm::dvec3(0, 1, 0)) - o;
    north = glm::normalize(north - glm::dot(north, east) * east);
    turn = glm::dmat3(east, north, glm::cross(east, north));
  }
  void apply(Model& model) const {
    for (Mesh& mesh : model.meshes) {
      for (glm::dvec3& p : mesh.positions) p = point(p);
      for (glm::vec3& n : mesh.normals) n = glm::vec3(turn * glm::dvec3(n));
    }
  }
};

// Appends src's meshes and objects to dst. fileObjects: a file without objects becomes one
// (Model::objectRuns); not when a city joins the files, whose objects are its buildings.
void appendModel(Model& dst, Model&& src, bool fileObjects) {
  const auto meshBase = std::uint32_t(dst.meshes.size());
  const auto objectBase =
      std::uint32_t(std::max(dst.cityObjects, dst.objectRuns.empty() ? 0 : dst.objectCount()));
  if (src.objectRuns.empty() && fileObjects)
    for (std::uint32_t m = 0; m < src.meshes.size(); ++m)
      src.objectRuns.push_back({0, m, 0, std::uint32_t(src.meshes[m].triangleCount())});
  for (ObjectRun r : src.objectRuns) {
    r.mesh += meshBase;
    r.object += objectBase;
    dst.objectRuns.push_back(r);
  }
  dst.cityObjects += src.cityObjects;
  for (Mesh& m : src.meshes) dst.meshes.push_back(std::move(m));
}

// A city folder as one input: its manifest, and the move from its frame into the store's (none
// when the store's frame is its own).
struct CitySource {
  CityManifest manifest;
  std::optional<EnuToEnu> move;
};

// A model as one input: where its coordinates are on the earth (its blocks' anchors), and its
// placement into the store's frame (none: the store's frame is its own). Its buildings are
// grouped into blocks in its own frame, where its x/y are the ground.
struct ModelSource {
  const Model* model = nullptr;
  GeoReference geo;
  std::optional<Placement> place;
  GeoReference placedGeo;  // the store's frame, when placed
};

// Builds the blocks of the cities and models into one store.
Result<Skeleton> buildBlocks(const std::vector<CitySource>& cities,
                             const std::vector<ModelSource>& models,
                             const std::function<void(HlodBuilder&)>& setFrame,
                             const std::filesystem::path& dir, const BuildOptions& options,
                             const BuildProgressFn& progress,
                             std::chrono::steady_clock::time_point t0) {
  if (!(options.blockSize > 0.0 && std::isfinite(options.blockSize)))
    return makeError("the block size must be a positive number of metres");
  auto builder = HlodBuilder::create(dir, options);
  if (!builder) return builder.error();
  setFrame(**builder);
  // Work: each city block, then each model's blocks: whole meshes cut by size (a model without
  // city objects) or its buildings grouped into grid blocks.
  struct Unit {
    std::size_t source, index;
    bool city, group;
  };
  std::vector<Unit> units;
  for (std::size_t c = 0; c < cities.size(); ++c)
    for (std::size_t j = 0; j < cities[c].manifest.blocks.size(); ++j)
      units.push_back({c, j, true, false});
  std::vector<std::vector<Block>> meshBlocks(models.size());
  std::vector<std::vector<BuildingBlock>> groups(models.size());
  for (std::size_t m = 0; m < models.size(); ++m) {
    const ModelSource& source = models[m];
    if (source.model->meshes.empty()) continue;
    if (source.model->cityObjects > 0) {
      groups[m] = groupBuildingsIntoBlocks(*source.model, options.blockSize);
      for (std::size_t g = 0; g < groups[m].size(); ++g) units.push_back({m, g, false, true});
    } else if (source.place) {
      Model placed = *source.model;
      source.place->apply(placed);
      meshBlocks[m] = cutIntoBlocks(placed, options.maxBlockTriangles);
    } else {
      meshBlocks[m] = cutIntoBlocks(*source.model, options.maxBlockTriangles);
    }
    for (std::size_t i = 0; i < meshBlocks[m].size(); ++i) units.push_back({m, i, false, false});
  }
  BuildProgress p;
  p.blockCount = units.size();
  const HlodBuilder& b = **builder;
  const auto prepare = [&](std::size_t i) -> Result<std::vector<PreparedBlock>> {
    std::vector<PreparedBlock> out;
    const Unit u = units[i];
    if (u.city) {
      // One block per worker in memory at a time: load, build its subtree, free.
      const CitySource& city = cities[u.source];
      auto block = loadCityBlock(city.manifest, u.index);
      if (!block) return block.error();
      if (city.move) {
        for (glm::dvec3& q : block->positions) q = city.move->point(q);
        for (glm::vec3& n : block->normals) n = glm::vec3(city.move->direction(glm::dvec3(n)));
      }
      // A city block is one texture already; split only blocks over the bound.
      Model one;
      one.meshes.push_back(std::move(*block));
      std::vector<Block> parts = cutIntoBlocks(one, options.maxBlockTriangles);
      // A city block's sides (the middles of its streets, on its box) meet its neighbours'
      // ground; in another city's frame they are no longer planes of constant x or y.
      const Aabb box = one.bounds();
      one = Model{};
      for (Block& part : parts) {
        if (!city.move)
          for (int axis = 0; axis < 2; ++axis)
            for (double v : {box.min[axis], box.max[axis]}) part.sides.push_back({axis, v});
        out.push_back(b.prepareBlock(part.mesh, part.seam, part.sides));
        out.back().anchor = city.manifest.blocks[u.index].anchor;
        part = Block{};
      }
      return out;
    }
    const ModelSource& source = models[u.source];
    // The anchor where the block is in its own model's frame: the centre of its box on the
    // ground.
    const auto anchorOf = [](const GeoReference& geo, const Aabb& box) -> std::optional<LatLon> {
      if (!geo.known()) return std::nullopt;
      const glm::dvec3 c = box.centre();
      return geo.toLatLon({c.x, c.y, box.min.z});
    };
    if (!u.group) {
      Block& block = meshBlocks[u.source][u.index];
      out.push_back(b.prepareBlock(block.mesh, block.seam));
      // A placed model's blocks are in the store's frame already.
      out.back().anchor =
          anchorOf(source.place ? source.placedGeo : source.geo, block.mesh.bounds());
      block = Block{};  // each worker frees its own block
      return out;
    }
    BuildingBlock& group = groups[u.source][u.index];
    const std::optional<LatLon> anchor = anchorOf(source.geo, group.model.bounds());
    if (source.place) {
      source.place->apply(group.model);
      for (glm::dvec3& q : group.shared) q = source.place->point(q);
    }
    std::vector<Block> parts = cutIntoBlocks(group.model, options.maxBlockTriangles);
    group.model = Model{};
    for (Block& part : parts) {
      part.seam.insert(part.seam.end(), group.shared.begin(), group.shared.end());
      out.push_back(b.prepareBlock(part.mesh, part.seam));
      out.back().anchor = anchor;
      part = Block{};
    }
    group.shared = {};
    return out;
  };
  const auto committed = [&](std::size_t, std::uint64_t triangles) {
    p.trianglesDone += triangles;
    ++p.blocksDone;
    p.seconds = secondsSince(t0);
    if (progress) progress(p);
  };
  if (auto s = prepareInParallel(**builder, units.size(), options.threads, prepare, committed); !s)
    return s.error();
  return (*builder)->finish(secondsSince(t0), [&](std::size_t done, std::size_t total) {
    p.cellsDone = done;
    p.cellCount = total;
    p.seconds = secondsSince(t0);
    if (progress) progress(p);
  });
}

Result<CityManifest> readCity(const std::filesystem::path& cityDir) {
  auto manifest = readCityManifest(cityDir);
  if (!manifest) return manifest.error();
  if (manifest->blocks.empty())
    return makeError((cityDir / "city.json").string() +
                     " lists no blocks: no triangles to build a store from");
  return manifest;
}

// The options with the model's up axis where they give none: the blocks' facades (the parry
// simplifier's first level) stand on it.
BuildOptions withUpOf(const BuildOptions& options, const Model& model) {
  BuildOptions o = options;
  o.up = options.up.value_or(upAxisOf(model));
  return o;
}

// The object hierarchy of a model (Manocha sec. 2.2) as the store's one block.
Result<Skeleton> buildObjects(const Model& model, const std::filesystem::path& dir,
                              const BuildOptions& options, const BuildProgressFn& progress,
                              std::chrono::steady_clock::time_point t0) {
  auto builder = HlodBuilder::create(dir, options);
  if (!builder) return builder.error();
  (*builder)->setModelFrame(upAxisOf(model), model.crs);
  const ObjectHierarchy hierarchy = buildObjectHierarchy(model, objectHierarchyOptions(options));
  BuildProgress p;
  p.blockCount = 1;
  p.nodeCount = hierarchy.nodes.size();
  const auto nodesDone = [&](std::size_t done, std::size_t total) {
    p.nodesDone = done;
    p.nodeCount = total;
    p.seconds = secondsSince(t0);
    if (progress) progress(p);
  };
  if (auto s = (*builder)->addObjectHierarchy(model, hierarchy, nodesDone); !s) return s.error();
  p.blocksDone = 1;
  p.trianglesDone = (*builder)->inputTriangles();
  if (progress) progress(p);
  return (*builder)->finish(secondsSince(t0));
}

// A model built as `options.hierarchy` says (resolveHierarchy).
Result<Skeleton> buildModel(const Model& model, const std::filesystem::path& dir,
                            const BuildOptions& options, const BuildProgressFn& progress,
                            std::chrono::steady_clock::time_point t0) {
  const BuildOptions o = withUpOf(options, model);
  if (resolveHierarchy(options.hierarchy, model) == HierarchyMode::Objects)
    return buildObjects(model, dir, o, progress, t0);
  const std::vector<ModelSource> models{{&model, GeoReference::of(model.crs), std::nullopt, {}}};
  return buildBlocks(
      {}, models, [&](HlodBuilder& b) { b.setModelFrame(upAxisOf(model), model.crs); }, dir, o,
      progress, t0);
}

}  // namespace

Result<Skeleton> buildStoreFromModel(const Model& model, const std::filesystem::path& dir,
                                     const BuildOptions& options, const BuildProgressFn& progress) {
  return buildModel(model, dir, options, progress, std::chrono::steady_clock::now());
}

Result<Skeleton> buildStoreFromCity(const std::filesystem::path& cityDir,
                                    const std::filesystem::path& dir, const BuildOptions& options,
                                    const BuildProgressFn& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  if (options.hierarchy == HierarchyMode::Objects)
    return makeError(cityDir.string() +
                     " is a city folder: its blocks are cut by planes (--hierarchy objects is for "
                     "model files)");
  auto manifest = readCity(cityDir);
  if (!manifest) return manifest.error();
  // The city's frame is the east-north-up frame at its origin: kept, so that the store can be
  // placed on the globe again (a 3D Tiles export's root transform).
  ModelCrs crs;
  crs.toEnu = true;
  crs.originLat = manifest->origin.lat;
  crs.originLon = manifest->origin.lon;
  crs.originHeight = manifest->origin.height;
  crs.description = "city folder: east-north-up metres at its origin";
  std::vector<CitySource> cities(1);
  cities[0].manifest = std::move(*manifest);
  return buildBlocks(
      cities, {}, [&](HlodBuilder& b) { b.setModelFrame(UpAxis::Z, crs); }, dir, options, progress,
      t0);
}

Result<Skeleton> buildStoreFromInputs(std::vector<BuildInput> inputs,
                                      const std::filesystem::path& dir, const BuildOptions& options,
                                      const BuildProgressFn& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  if (inputs.empty()) return makeError("no input to build a store from");
  if (inputs.size() == 1)
    return inputs[0].cityDir ? buildStoreFromCity(*inputs[0].cityDir, dir, options, progress)
                             : buildStoreFromModel(inputs[0].model, dir, options, progress);
  std::vector<CitySource> cities;
  std::vector<GeoReference> geo;
  for (BuildInput& in : inputs) {
    if (in.cityDir) {
      auto manifest = readCity(*in.cityDir);
      if (!manifest) return manifest.error();
      geo.push_back(GeoReference::enu(manifest->origin));
      cities.push_back({std::move(*manifest), std::nullopt});
    } else {
      geo.push_back(GeoReference::of(in.model.crs));
    }
  }
  const auto anchored =
      std::find_if(geo.begin(), geo.end(), [](const GeoReference& g) { return g.known(); });
  const auto loose =
      std::find_if(geo.begin(), geo.end(), [](const GeoReference& g) { return !g.known(); });
  if (anchored == geo.end()) {
    // Mesh files: joined as they are, in the first one's frame and CRS.
    Model merged;
    merged.zUp = inputs[0].model.zUp;
    merged.crs = inputs[0].model.crs;
    const bool city = std::any_of(inputs.begin(), inputs.end(),
                                  [](const BuildInput& in) { return in.model.cityObjects > 0; });
    for (BuildInput& in : inputs) appendModel(merged, std::move(in.model), !city);
    return buildModel(merged, dir, options, progress, t0);
  }
  if (options.hierarchy == HierarchyMode::Objects)
    return makeError(
        "geo-referenced inputs and city folders are placed as blocks cut by planes "
        "(--hierarchy objects is for model files without a geographic anchor)");
  if (loose != geo.end()) {
    const BuildInput& l = inputs[std::size_t(loose - geo.begin())];
    const BuildInput& a = inputs[std::size_t(anchored - geo.begin())];
    return makeError(l.name + " has no geographic anchor (CRS: " +
                     (l.model.crs.description.empty() ? "none" : l.model.crs.description) +
                     "), so it cannot be placed beside " + a.name +
                     ": build inputs without an anchor on their own");
  }
  // One frame for all: the first input's ENU frame (a projected one: the ENU frame at its centre).
  const auto groundCentre = [](const Aabb& box) {
    const glm::dvec3 c = box.centre();
    return glm::dvec3(c.x, c.y, box.min.z);
  };
  const EnuFrame target = geo[0].frame()
                              ? *geo[0].frame()
                              : EnuFrame(geo[0].toLatLon(groundCentre(inputs[0].model.bounds())));
  std::vector<ModelSource> models;
  std::size_t city = 0;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    if (inputs[i].cityDir) {
      if (i > 0) cities[city].move.emplace(*geo[i].frame(), target);
      ++city;
      continue;
    }
    ModelSource source{&inputs[i].model, geo[i], std::nullopt, GeoReference::enu(target.origin())};
    if (i > 0 || !geo[0].frame())
      source.place.emplace(geo[i], target, inputs[i].model.bounds().centre());
    models.push_back(std::move(source));
  }
  ModelCrs crs;
  crs.toEnu = true;
  crs.originLat = target.origin().lat;
  crs.originLon = target.origin().lon;
  crs.originHeight = target.origin().height;
  crs.description = std::to_string(inputs.size()) +
                    " inputs placed through ECEF in east-north-up metres at the first one's origin";
  return buildBlocks(
      cities, models, [&](HlodBuilder& b) { b.setModelFrame(UpAxis::Z, crs); }, dir, options,
      progress, t0);
}

}  // namespace hlod
