#pragma once
// Camera and per-frame View for front selection (Lakhia III-C): view direction, frustum planes in
// double precision, distance of a box outside the frustum (for frustumVis) and the pixels per
// world unit at a distance (for screen-space-error selection). Pure math, no GL.
#include <array>
#include <limits>

#include <glm/glm.hpp>

#include "hlod/Mesh.h"

namespace hlod {

class OcclusionOracle;  // hlod/runtime/OcclusionCulling.h

// A plane n.p + d = 0 with unit normal n pointing into the frustum.
struct Plane {
  glm::dvec3 normal{0.0, 0.0, 1.0};
  double d = 0.0;

  double signedDistance(const glm::dvec3& p) const { return glm::dot(normal, p) + d; }
};

// Six planes: left, right, bottom, top, near, far; each normal points inside.
struct Frustum {
  std::array<Plane, 6> planes;

  // How far the box lies outside the frustum, in world units: 0 when the box touches or is inside
  // the frustum, otherwise the largest distance by which the box is behind one plane. This is a
  // lower bound of the true Euclidean distance (exact near faces, smaller near edges/corners),
  // which is what a linear fall-off of frustumVis needs: cheap and never overestimated.
  double distanceOutside(const Aabb& box) const;
  bool intersects(const Aabb& box) const { return distanceOutside(box) <= 0.0; }
};

struct Camera {
  glm::dvec3 position{0.0, -10.0, 0.0};
  glm::dvec3 target{0.0};
  glm::dvec3 up{0.0, 0.0, 1.0};  // Z is up in the city models
  double fovY = 60.0;            // vertical field of view, degrees
  double aspect = 16.0 / 9.0;    // width / height
  double nearPlane = 0.1;
  double farPlane = 100000.0;

  // Unit view direction (from position to target); the image plane normal. +Y when degenerate.
  glm::dvec3 forward() const;
  // Unit right and true-up vectors of the image plane (right-handed, up-corrected).
  glm::dvec3 right() const;
  glm::dvec3 trueUp() const;
  Frustum frustum() const;

  // Pixels covered by one world unit seen face-on at `distance` in a viewport `viewportHeight`
  // pixels tall: viewportHeight / (2 tan(fovY/2) distance). Distance is clamped below by 1e-9.
  double pixelsPerUnit(double distance, double viewportHeight) const;
};

// Euclidean distance from a point to a box (0 inside).
double distanceToBox(const glm::dvec3& p, const Aabb& box);

// Everything a selector needs about one frame.
struct View {
  Camera camera;
  glm::dvec3 velocity{0.0};  // camera velocity, world units per second (for the distance lookahead)
  int viewportWidth = 1280;
  int viewportHeight = 720;
  // Of this frame's budget, the ms already spent before drawing (the GPU uploads of nodes that
  // finished loading): budgeted selectors give the drawing what is left of c_targetTime.
  double spentMs = 0.0;
  // Distance fog: nodes wholly farther than this are fully fogged and culled (as Cesium culls
  // tiles whose fog factor reaches 1; hlod::fogCullDistance). Infinite: no fog culling.
  double fogCullDistance = std::numeric_limits<double>::infinity();
  // How many times the front is drawn this frame, in units of the geometry pass: 1, or 1 plus the
  // shadow pass's share when a shadow map is drawn from the sun (FrameDriver measures it). The
  // geometry pass gets the draw budget divided by this, and v_time stays the geometry pass's ms
  // per unit of cost whether or not a scene casts shadows.
  double frontDraws = 1.0;
  // Occlusion culling (OcclusionCulling.h): nodes found hidden by last frame's queries are left
  // out of the front with their subtrees. nullptr: culling is off, the frustum alone decides.
  const OcclusionOracle* occlusion = nullptr;
};

// About the pixels a box spans in the view: its diagonal seen face-on at its nearest point
// (infinite with the eye inside it). What decides that a node is drawn as splats.
double projectedPixels(const View& view, const Aabb& box);

}  // namespace hlod
