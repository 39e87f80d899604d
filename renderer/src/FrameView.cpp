#include "renderer/FrameView.h"

#include <cmath>

#include "hlod/runtime/Camera.h"

namespace renderer {

glm::dmat4 reversedZPerspective(double fovYRadians, double aspect, double zNear, double zFar) {
  const double f = 1.0 / std::tan(fovYRadians * 0.5);
  glm::dmat4 p(0.0);
  p[0][0] = f / aspect;
  p[1][1] = f;
  // z_clip = n/(f-n) * z + n*f/(f-n), w_clip = -z: depth 1 at z = -near, 0 at z = -far.
  p[2][2] = zNear / (zFar - zNear);
  p[3][2] = zNear * zFar / (zFar - zNear);
  p[2][3] = -1.0;
  return p;
}

FrameView makeFrameView(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up,
                        double fovYDegrees, double aspect, double zNear, double zFar) {
  FrameView v;
  v.eye = eye;
  // The basis of hlod::Camera, which the selectors cull with: where the view is degenerate
  // (target on the eye, up parallel to the view) both must pick the same fallback, or the
  // image shows what the frustum culled.
  hlod::Camera camera;
  camera.position = eye;
  camera.target = target;
  camera.up = up;
  const glm::dvec3 f = camera.forward(), s = camera.right(), u = camera.trueUp();
  glm::dmat4 r(1.0);
  r[0][0] = s.x;
  r[1][0] = s.y;
  r[2][0] = s.z;
  r[0][1] = u.x;
  r[1][1] = u.y;
  r[2][1] = u.z;
  r[0][2] = -f.x;
  r[1][2] = -f.y;
  r[2][2] = -f.z;
  v.rotation = r;
  v.viewDir = f;
  v.projection = reversedZPerspective(glm::radians(fovYDegrees), aspect, zNear, zFar);
  v.farDistance = zFar;
  return v;
}

}  // namespace renderer
