#pragma once
// The camera of one frame, in double precision. The renderer draws camera-relative: for each
// mesh it forms view * translate(centre - eye) in double and only then casts to float, so a model
// 6,000 km from the origin draws as steadily as one at the origin.
#include <glm/glm.hpp>

namespace renderer {

struct FrameView {
  glm::dvec3 eye{0.0};
  glm::dmat4 rotation{1.0};    // world -> view rotation (the look-at matrix without translation)
  glm::dmat4 projection{1.0};  // reversed-Z (depth 1 at near, 0 at far), clip depth in [0, 1]
  glm::dvec3 viewDir{0.0, 0.0, -1.0};
  double farDistance = 1e5;  // the far plane: fog's derived density uses it
  // A sphere holding what is drawn (world): the shadow map is fitted to it. Radius 0: the
  // renderer fits one around the meshes' centres.
  glm::dvec3 sceneCentre{0.0};
  double sceneRadius = 0.0;
};

// Reversed-Z perspective for glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE) and depth test
// GREATER with a 32-bit float depth buffer: float precision is spent where distances are large.
glm::dmat4 reversedZPerspective(double fovYRadians, double aspect, double zNear, double zFar);

// Builds the view of a camera at eye looking at target: hlod::Camera's forward, right and true
// up (and its fallbacks when target is on the eye or up is parallel to the view), so that the
// image is drawn from the camera the selectors culled for.
FrameView makeFrameView(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up,
                        double fovYDegrees, double aspect, double zNear, double zFar);

}  // namespace renderer
