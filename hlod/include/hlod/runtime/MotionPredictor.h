#pragma once
// Where the camera of a session without a known path will be (Manocha sec. 5.3: "the
// prefetching algorithm estimates the LOD switching and visibility events along with
// frame-to-frame coherence"). The camera's recent motion is extrapolated: position at the
// velocity of the last frames, view direction turning at their turn rate. The selection for
// the predicted camera goes to the loader's prefetch (FrameDriver), which catches
//  - LOD-switching events: nodes the camera approaches are refined there before here;
//  - visibility events at the frustum: the predicted frustum is widened by c_widen, so nodes
//    about to enter the view are among its nodes;
//  - occlusion events: the predicted selection sees the current occlusion state, so hidden
//    nodes stay at their low priority, while the detail of nodes hidden only lately stays
//    wanted (SelectorParams::c_occludedKeepFrames) for when they come back out.
#include <optional>

#include "hlod/runtime/CameraPath.h"

namespace hlod {

struct MotionPredictorParams {
  double c_ahead = 0.5;    // seconds ahead
  double c_widen = 0.25;   // the predicted view's field of view grows by this share
  double c_maxGap = 0.5;   // seconds: frames further apart are not one motion
  double c_smooth = 0.5;   // weight of the newest velocity in the running estimate
};

class MotionPredictor {
 public:
  explicit MotionPredictor(const MotionPredictorParams& params = {}) : params_(params) {}
  // The camera of a frame, in time order. A gap over c_maxGap (or time going back) starts anew.
  void observe(const CameraSample& sample);
  // The camera c_ahead seconds after the last one, or nothing before two frames of one motion
  // (or when the camera rests: nothing new to fetch).
  std::optional<CameraSample> predict() const;
  void reset() { frames_ = 0; }

 private:
  MotionPredictorParams params_;
  CameraSample last_;
  glm::dvec3 velocity_{0.0};    // of the position, world units per second
  glm::dvec3 turn_{0.0};        // of the unit view direction, per second
  int frames_ = 0;
};

}  // namespace hlod
