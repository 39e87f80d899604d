// The camera path kinds makeCameraPath knows, and the one place a new generator is listed
// (runtime/paths/PathGenerators.h says how to add one).
#include <string>

#include "hlod/store/NodeSource.h"
#include "runtime/paths/PathGenerators.h"

namespace hlod {

namespace {

// A generator from the skeleton, or (fromStore) one that needs the store's geometry.
struct PathKind {
  std::string_view name;
  Result<CameraPath> (*make)(const Skeleton&);
  Result<CameraPath> (*fromStore)(const NodeSource&) = nullptr;
};

// In the order messages and --help list them.
constexpr PathKind kPathKinds[] = {
    {"walk-fly", makeWalkFlyPath},
    {"drive", makeDrivePath},
    {"orbit", [](const Skeleton& skeleton) { return makeOrbitPath(skeleton); }},
    {"facade", makeFacadePath},
    {"fly-around", [](const Skeleton& skeleton) { return makeFlyAroundPath(skeleton); }},
    {"catwalk", nullptr, makeCatwalkPath},
};

}  // namespace

std::vector<std::string_view> cameraPathKinds() {
  std::vector<std::string_view> out;
  for (const PathKind& k : kPathKinds) out.push_back(k.name);
  return out;
}

namespace {

Result<CameraPath> make(std::string_view kind, const Skeleton& skeleton, const NodeSource* store) {
  std::string known;
  for (const PathKind& k : kPathKinds) {
    if (k.name == kind) {
      if (k.fromStore && store) return k.fromStore(*store);
      if (k.make) return k.make(skeleton);
      return makeError("camera path '" + std::string(kind) +
                       "' is made from the store's geometry, not its skeleton alone");
    }
    known += (known.empty() ? "" : ", ") + std::string(k.name);
  }
  return makeError("unknown camera path '" + std::string(kind) + "' (known: " + known + ")");
}

}  // namespace

Result<CameraPath> makeCameraPath(std::string_view kind, const Skeleton& skeleton) {
  return make(kind, skeleton, nullptr);
}

Result<CameraPath> makeCameraPath(std::string_view kind, const NodeSource& store) {
  return make(kind, store.skeleton(), &store);
}

}  // namespace hlod
