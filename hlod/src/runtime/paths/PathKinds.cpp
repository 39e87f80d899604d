// The camera path kinds makeCameraPath knows, and the one place a new generator is listed
// (runtime/paths/PathGenerators.h says how to add one).
#include <string>

#include "runtime/paths/PathGenerators.h"

namespace hlod {

namespace {

struct PathKind {
  std::string_view name;
  Result<CameraPath> (*make)(const Skeleton&);
};

// In the order messages and --help list them.
constexpr PathKind kPathKinds[] = {
    {"walk-fly", makeWalkFlyPath},
    {"drive", makeDrivePath},
    {"orbit", [](const Skeleton& skeleton) { return makeOrbitPath(skeleton); }},
    {"facade", makeFacadePath},
};

}  // namespace

std::vector<std::string_view> cameraPathKinds() {
  std::vector<std::string_view> out;
  for (const PathKind& k : kPathKinds) out.push_back(k.name);
  return out;
}

Result<CameraPath> makeCameraPath(std::string_view kind, const Skeleton& skeleton) {
  std::string known;
  for (const PathKind& k : kPathKinds) {
    if (k.name == kind) return k.make(skeleton);
    known += (known.empty() ? "" : ", ") + std::string(k.name);
  }
  return makeError("unknown camera path '" + std::string(kind) + "' (known: " + known + ")");
}

}  // namespace hlod
