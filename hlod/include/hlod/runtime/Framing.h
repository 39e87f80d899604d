#pragma once
// Framing a model: where a camera stands to see the whole model fill most of the frame, upright.
// Two rules: a still view (frameBounds: `hlodr render MODEL`'s default view, the service's first
// camera, the frame driver's calibration frame) frames the model's box as seen from its
// direction; the orbit path frames the box's bounding sphere, which holds the model seen from
// any side.
#include <glm/glm.hpp>

#include "hlod/Mesh.h"
#include "hlod/UpAxis.h"
#include "hlod/runtime/Camera.h"
#include "hlod/store/Skeleton.h"

namespace hlod {

// The share of the frame's smaller side an orbited model's bounding sphere spans. The sphere
// holds the model seen from any side, so an orbit never leaves the frame; it is also loose
// (an elongated model spans less), hence a small margin only.
constexpr double kFramingFill = 0.95;
// The share of the frame's width or height (whichever the model reaches first) a still view's
// box spans: the box's corners are the model's extremes, so a margin of a few pixels suffices.
constexpr double kBoxFramingFill = 0.95;

// Distance from the centre of a sphere of `radius` at which a camera looking at that centre,
// with a vertical field of view of fovY degrees and width / height `aspect`, sees the sphere's
// outline span `fill` of the frame's smaller side. Seen from distance d, the outline's
// half-size on the image plane (at unit depth) is tan(asin(r / d)) = r / sqrt(d^2 - r^2); the
// frame's smaller half-size is tan(fovY / 2) * min(1, aspect).
double framingDistance(double radius, double fovY, double aspect, double fill = kFramingFill);

// The frame a model's cameras stand in: for a model lying on the earth in earth-centred
// coordinates (hlod/geodesy/EarthCentred.h: a terrain in ECEF), the east-north-up frame at the
// centre of its box, up the ellipsoid's normal; otherwise its up axis's (upFrame).
UpFrame modelUpFrame(UpAxis up, const Aabb& bounds);
// The same for a store: its up axis and the box of its roots.
UpFrame modelUpFrame(const Skeleton& skeleton);

// Unit direction from a target to the camera: `azimuth` radians around up from the frame's first
// horizontal axis towards the second, `elevation` radians above the plane they span.
glm::dvec3 orbitDirection(const UpFrame& frame, double azimuth, double elevation);
inline glm::dvec3 orbitDirection(UpAxis up, double azimuth, double elevation) {
  return orbitDirection(upFrame(up), azimuth, elevation);
}

// Where a model is seen from by default: a three-quarter view from 30 degrees above. A z-up
// city (and an earth-centred model, in its east-north-up frame) from the south-west, so that
// facades on both street directions show; a y-up mesh from its front (+Z, the glTF convention)
// and a little to its right (+X).
glm::dvec3 defaultViewDirection(const UpFrame& frame);
inline glm::dvec3 defaultViewDirection(UpAxis up) {
  return defaultViewDirection(upFrame(up));
}

// A camera looking along -direction (unit) with the model's up, as near as it can stand with the
// box's eight corners inside kBoxFramingFill of the frame: they reach it on one axis and the
// projection is centred on both (perspective moves the target a little off the box's centre).
// Every corner lies ahead of the camera. A flat city seen from 30 degrees above fills the
// frame's width, where its bounding sphere left it a small share. Near and far hold the box.
Camera frameBounds(const Aabb& bounds, const UpFrame& frame, const glm::dvec3& direction,
                   double fovY, double aspect);
inline Camera frameBounds(const Aabb& bounds, UpAxis up, const glm::dvec3& direction, double fovY,
                          double aspect) {
  return frameBounds(bounds, upFrame(up), direction, fovY, aspect);
}

// The default view of a model: modelUpFrame, defaultViewDirection and frameBounds in one.
Camera defaultView(const Aabb& bounds, UpAxis up, double fovY, double aspect);

}  // namespace hlod
