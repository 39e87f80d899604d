#pragma once
// Monotone cubic Hermite interpolation of camera keyframes after M. Steffen, "A simple method for
// monotonic interpolation in one dimension" (Astron. Astrophys. 239, 1990): per component, the
// tangent at a keyframe is the slope of the parabola through it and its neighbours, limited so
// that the cubic between two keyframes stays between their values (no overshoot), 0 at a turn;
// a field whose last keyframe repeats its first (a loop) gets periodic tangents. CameraPath.h
// says what that means for a path. Private to the runtime.
#include <vector>

#include <glm/glm.hpp>

#include "hlod/runtime/CameraPath.h"

namespace hlod {

// Steffen's tangent at an interior keyframe from the slopes dl (over an interval hl) on its left
// and dr (over hr) on its right.
double steffenInterior(double dl, double dr, double hl, double hr);
// Steffen's tangent at an end keyframe, slope d0 over h0 next to it and d1 over h1 after that.
double steffenEnd(double d0, double d1, double h0, double h1);

// Per-component monotone tangents at every keyframe of `field`; C1 at the keyframes (and across
// the seam of a loop). At least 2 keyframes, strictly increasing times.
std::vector<glm::dvec3> monotoneTangents(const std::vector<CameraKeyframe>& k,
                                         glm::dvec3 CameraKeyframe::*field);

// True when every interval's change of `field` and its slope are finite with room to spare, so
// that the tangents (at most 3 slopes) and the Hermite terms cannot overflow.
bool slopesFinite(const std::vector<CameraKeyframe>& k, glm::dvec3 CameraKeyframe::*field);

// The cubic Hermite segment from p0 (tangent m0) to p1 (tangent m1) over an interval of length h,
// at s in [0, 1], and its derivative by time.
glm::dvec3 hermite(const glm::dvec3& p0, const glm::dvec3& m0, const glm::dvec3& p1,
                   const glm::dvec3& m1, double h, double s);
glm::dvec3 hermiteDerivative(const glm::dvec3& p0, const glm::dvec3& m0, const glm::dvec3& p1,
                             const glm::dvec3& m1, double h, double s);

}  // namespace hlod
