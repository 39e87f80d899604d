#pragma once
// Camera paths: keyframes (time, position, target, up, fov) interpolated with C1 cubic Hermite
// splines (Catmull-Rom tangents for non-uniform times) on position, target and up; fov linear.
// Read from / written to JSON:
//   {"keyframes": [{"time": 0.0, "position": [x,y,z], "target": [x,y,z], "up": [0,0,1],
//                   "fov": 60.0}, ...]}
// time in seconds, strictly increasing; positions in world units; fov = vertical degrees;
// "up" and "fov" are optional (default +Z and 60). A bare array of keyframes is accepted too.
//
// Generators from a Skeleton (the hlod_0 boxes of the blocks; Z up, metres):
//   "walk-fly": ground-level walk (1.7 m eye height) along a street, rising into a fly-over of
//               the whole model (Lakhia Fig. 7), 35 s;
//   "drive":    a loop along streets at 1.5 m height and ~17 m/s, 20-40 s;
//   "orbit":    any model: a circle around the bounds centre at a distance that frames it, 30 s.
// Streets are the gaps between the blocks' boxes projected on X and on Y; a model without gaps
// uses lines just outside its bounds.
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "hlod/Camera.h"
#include "hlod/Result.h"
#include "hlod/Skeleton.h"

namespace hlod {

struct CameraKeyframe {
  double time = 0.0;
  glm::dvec3 position{0.0};
  glm::dvec3 target{0.0, 1.0, 0.0};
  glm::dvec3 up{0.0, 0.0, 1.0};
  double fovY = 60.0;
};

struct CameraSample {
  double time = 0.0;
  Camera camera;
  glm::dvec3 velocity{0.0};  // d position / dt, world units per second
};

class CameraPath {
 public:
  // At least 2 keyframes, strictly increasing times, all values finite, fov in (0, 180).
  static Result<CameraPath> fromKeyframes(std::vector<CameraKeyframe> keyframes);
  static Result<CameraPath> parse(std::string_view json);
  static Result<CameraPath> read(const std::string& path);
  std::string toJson() const;
  Status write(const std::string& path) const;

  const std::vector<CameraKeyframe>& keyframes() const { return keys_; }
  double startTime() const { return keys_.front().time; }
  double endTime() const { return keys_.back().time; }
  double duration() const { return endTime() - startTime(); }

  // t is clamped to [startTime, endTime]. aspect, near and far go into the Camera as given.
  CameraSample sample(double t, double aspect = 16.0 / 9.0, double nearPlane = 0.1,
                      double farPlane = 100000.0) const;
  // Frames at startTime + i / fps for i = 0 .. floor(duration * fps) (the last one <= endTime).
  std::vector<CameraSample> sampleAt(double fps, double aspect = 16.0 / 9.0) const;

 private:
  CameraPath() = default;
  std::vector<CameraKeyframe> keys_;
  std::vector<glm::dvec3> posTangent_, targetTangent_, upTangent_;
};

Result<CameraPath> makeWalkFlyPath(const Skeleton& skeleton);
Result<CameraPath> makeDrivePath(const Skeleton& skeleton);
Result<CameraPath> makeOrbitPath(const Skeleton& skeleton, double duration = 30.0,
                                 double fovY = 60.0);
// "walk-fly", "drive" or "orbit".
Result<CameraPath> makeCameraPath(std::string_view kind, const Skeleton& skeleton);
// The same keyframes with their times scaled about the start so that the path lasts `seconds`.
Result<CameraPath> withDuration(const CameraPath& path, double seconds);

}  // namespace hlod
