#include "renderer/FrameView.h"

#include <cmath>

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
  glm::dvec3 f = target - eye;
  const double len = glm::length(f);
  f = len > 0.0 ? f / len : glm::dvec3(0, 0, -1);
  glm::dvec3 s = glm::cross(f, up);
  if (glm::length(s) < 1e-12)
    s = glm::cross(f, std::abs(f.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 1, 0));
  s = glm::normalize(s);
  const glm::dvec3 u = glm::cross(s, f);
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
  return v;
}

}  // namespace renderer
