#pragma once
// Camera path generators: a path made from a store's Skeleton, one generator per file in this
// folder (WalkFlyPath.cpp, DrivePath.cpp, OrbitPath.cpp, FlyAroundPath.cpp; CatwalkPath.cpp is
// made from the store's geometry, its kind's `fromStore`), declared in hlod/runtime/CameraPath.h
// and listed by kind in PathKinds.cpp, where makeCameraPath finds it. To add one: write
// NAMEPath.cpp with a Result<CameraPath> makeNAMEPath(const Skeleton&), declare it beside the
// others in CameraPath.h, and add its kind to kPathKinds; paths that follow streets use
// Streets.h. Private to the runtime.
#include "hlod/runtime/CameraPath.h"
#include "hlod/store/Skeleton.h"

namespace hlod {

// The box of the skeleton's roots: what a generator frames.
inline Aabb rootBounds(const Skeleton& sk) {
  Aabb all;
  for (std::uint32_t r : sk.roots) {
    if (r < sk.nodes.size()) all.extend(sk.nodes[r].bounds);
  }
  return all;
}

}  // namespace hlod
