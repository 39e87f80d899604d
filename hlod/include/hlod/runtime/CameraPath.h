#pragma once
// Camera paths: keyframes (time, position, target, up, fov) interpolated with C1 cubic Hermite
// splines on position, target and up, per component, with Steffen's monotone tangents (M.
// Steffen, "A simple method for monotonic interpolation in one dimension", A&A 239, 1990); fov
// linear. Read from / written to JSON:
//   {"keyframes": [{"time": 0.0, "position": [x,y,z], "target": [x,y,z], "up": [0,0,1],
//                   "fov": 60.0}, ...]}
// time in seconds, strictly increasing, finite, with a finite duration; positions in world units;
// fov = vertical degrees; "up" and "fov" are optional (default +Z and 60). A bare array of
// keyframes is accepted too.
//
// Interpolation. Between two keyframes each coordinate stays between its two keyframe values:
// the spline never overshoots (a walk at eye height followed by a climb no longer dips under the
// street first, as the Catmull-Rom tangents of earlier versions did), a coordinate equal at
// two keyframes is constant between them, and a keyframe where a coordinate turns (a local
// minimum or maximum) is a turning point of the curve. So the path stays inside the union of the
// axis-aligned boxes spanned by consecutive keyframes, and the speed on a segment is at most
// twice its chord length over its duration; the extreme points of a curve must be keyframes (the
// orbit's are), since it does not bulge beyond them. Elsewhere (no turn, neighbouring slopes within
// a factor of about 3) a keyframe's tangent is the slope of the parabola through it and its two
// neighbours, which for evenly spaced keyframes is Catmull-Rom's. A field whose last keyframe
// repeats its first (a loop, as the orbit) gets periodic tangents, C1 across the seam. The file
// format is unchanged: old paths read as before and sample differently only where the limits
// apply.
//
// Generators from a Skeleton (the hlod_0 boxes of the blocks):
//   "walk-fly": ground-level walk (1.7 m eye height) along a street, rising into a fly-over of
//               the whole model (Lakhia Fig. 7), 35 s; z-up cities in metres only;
//   "drive":    a loop along streets at 1.5 m height and ~17 m/s, 20-40 s; z-up cities only;
//   "orbit":    any model: a circle around the skeleton's up axis through the bounds centre,
//               30 degrees above it, at the distance that frames the bounding sphere
//               (framingDistance), keyframe up = the model's up, 30 s.
// A city kind on a store that is not z-up is an Error naming the kind and suggesting orbit.
// Streets are the gaps between the blocks' boxes projected on X and on Y; a model without gaps
// uses lines just outside its bounds.
// The spline is runtime/SteffenSpline.cpp, the JSON file runtime/CameraPathJson.cpp, and each
// generator a file of runtime/paths/ (paths/PathGenerators.h says how to add one).
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "hlod/Result.h"
#include "hlod/runtime/Camera.h"
#include "hlod/store/Skeleton.h"

namespace hlod {

class NodeSource;

// The most frames CameraPath::frameCount accepts by default: 10 million, 46 h at 60 fps or 3.9
// days at 30 fps. A path run streams its frames, so this bounds the run's length, not memory.
inline constexpr std::uint64_t kMaxPathFrames = 10'000'000;
// The most frames CameraPath::sampleAt holds in memory: 2^20 (about 150 MB of samples, 9.7 h at
// 30 fps).
inline constexpr std::uint64_t kMaxSampledFrames = std::uint64_t{1} << 20;

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
  // At least 2 keyframes, strictly increasing finite times with a finite duration, all values
  // finite and their slopes between keyframes finite, fov in (0, 180).
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

  // Number of frames at startTime + i / fps, i = 0 .. floor(duration * fps) (a product a
  // rounding error below an integer counts that frame). An Error when fps is not positive and
  // finite, or when that count is not finite or exceeds maxFrames; the message says what the
  // path's duration and fps give. Allocates nothing.
  Result<std::uint64_t> frameCount(double fps, std::uint64_t maxFrames = kMaxPathFrames) const;
  // Frame i of that sampling (fps as accepted by frameCount), computed from i directly: time =
  // startTime + i / fps in double, no accumulated steps, so frame 5 million of a day-long path is
  // where it should be. An i past the last frame gives the end of the path.
  CameraSample sampleFrame(std::uint64_t i, double fps, double aspect = 16.0 / 9.0) const;
  // All frames of that sampling in one vector, for short paths: empty when frameCount(fps,
  // maxFrames) is an Error. Long paths go frame by frame through frameCount and sampleFrame.
  std::vector<CameraSample> sampleAt(double fps, double aspect = 16.0 / 9.0,
                                     std::uint64_t maxFrames = kMaxSampledFrames) const;

 private:
  CameraPath() = default;
  std::vector<CameraKeyframe> keys_;
  std::vector<glm::dvec3> posTangent_, targetTangent_, upTangent_;
};

Result<CameraPath> makeWalkFlyPath(const Skeleton& skeleton);
Result<CameraPath> makeDrivePath(const Skeleton& skeleton);
// A 10 s walk 6 m off the middle of the walk-fly's street, looking 30 degrees towards its east
// facades (Lakhia's Fig. 1: a facade seen at a slant, near and far at once).
Result<CameraPath> makeFacadePath(const Skeleton& skeleton);
// aspect: the width / height the path is meant for (a portrait frame moves the camera back). The
// circle is around the model's up (modelUpFrame: an earth-centred model's ellipsoid normal).
Result<CameraPath> makeOrbitPath(const Skeleton& skeleton, double duration = 30.0,
                                 double fovY = 60.0, double aspect = 16.0 / 9.0);
// An orbit that starts at `start`: the circle around the frame's up through its target that
// passes through its position, looking at the target, at its fov, once round in `duration`
// seconds (a scene file's camera for a path job). An Error when the camera looks straight along
// the up axis.
Result<CameraPath> makeOrbitPathFrom(const Camera& start, const UpFrame& frame,
                                     double duration = 30.0);
inline Result<CameraPath> makeOrbitPathFrom(const Camera& start, UpAxis up,
                                            double duration = 30.0) {
  return makeOrbitPathFrom(start, upFrame(up), duration);
}
// A loop around a CAD scene's box, outside it, looking in (runtime/paths/FlyAroundPath.cpp).
Result<CameraPath> makeFlyAroundPath(const Skeleton& skeleton, double duration = 40.0);
// A walk at eye height along a CAD scene's catwalks, found in the store's full-detail geometry
// (hlod/runtime/CatwalkPath.h; runtime/paths/CatwalkPath.cpp).
Result<CameraPath> makeCatwalkPath(const NodeSource& store);
// "walk-fly", "drive", "orbit", "facade", "fly-around" or "catwalk": the generator of that kind
// (cameraPathKinds lists them); "catwalk" needs the store's geometry: the second form.
Result<CameraPath> makeCameraPath(std::string_view kind, const Skeleton& skeleton);
Result<CameraPath> makeCameraPath(std::string_view kind, const NodeSource& store);
// The kinds makeCameraPath knows, in the order its messages list them.
std::vector<std::string_view> cameraPathKinds();
// The same keyframes with their times scaled about the start so that the path lasts `seconds`.
Result<CameraPath> withDuration(const CameraPath& path, double seconds);

}  // namespace hlod
