#pragma once
// The shapes the power plant is built of (private to plant/): boxes, I-beams, tubes swept along
// polylines with bends, flanges, domes, tori and prisms, appended to a glTF mesh with outward
// normals and counter-clockwise winding seen from outside.
#include <cstdint>
#include <vector>

#include "hlod/plant/GlbWriter.h"

namespace hlod::plant {

using glm::dvec3;

// A cross-section of a tube: its centre, the tube's direction there, and the direction of its
// first vertex (perpendicular to dir). Consecutive rings carry the frame along (parallel
// transport), so that their vertices line up and bends close without cracks.
struct Ring {
  dvec3 centre{0.0}, dir{0.0, 0.0, 1.0}, u{1.0, 0.0, 0.0};
};

// A straight stretch of a swept polyline (between its bends), with the frame there.
struct Straight {
  dvec3 a{0.0}, b{0.0}, dir{0.0}, u{0.0};
  double length() const;
};

struct Sweep {
  std::vector<Ring> rings;
  std::vector<Straight> straights;
};

// A unit vector perpendicular to d (unit).
dvec3 perpendicular(const dvec3& d);

// The rings along a polyline (at least two points, no two consecutive equal): straights with a
// ring every `step` (and at both ends), bends of radius bendRadius (smaller where the straights
// beside them are short) with bendRings rings per quarter turn.
Sweep sweepPolyline(const std::vector<dvec3>& points, double bendRadius, double step,
                    int bendRings);

class ShapeBuilder {
 public:
  explicit ShapeBuilder(GltfMesh& mesh) : m_(mesh) {}

  std::uint32_t vertex(const dvec3& p, const dvec3& n);
  void triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c);

  // A box from lo to hi in the frame (origin o; axes ex, ey, ez orthonormal, right-handed):
  // flat faces, four vertices each.
  void box(const dvec3& lo, const dvec3& hi, const dvec3& o = dvec3(0.0),
           const dvec3& ex = dvec3(1, 0, 0), const dvec3& ey = dvec3(0, 1, 0),
           const dvec3& ez = dvec3(0, 0, 1));
  // An I-beam of length 1 along +X: flanges across Z (width w, thickness tf), web along Y
  // (height h, thickness tw), centred on the X axis.
  void iBeam(double h, double w, double tf, double tw);
  // A tube of radius r through the rings, seg sides, smooth; caps closing the ends when asked.
  void tube(const std::vector<Ring>& rings, double r, int seg, bool capStart, bool capEnd);
  // As tube, a radius per ring (a frustum, a skirt); normals slant with the radius.
  void tube(const std::vector<Ring>& rings, const std::vector<double>& radii, int seg,
            bool capStart, bool capEnd);
  // A flat disc at c facing n (ring's frame u), and an annulus between r0 and r1.
  void disc(const dvec3& c, const dvec3& n, const dvec3& u, double r, int seg);
  void annulus(const dvec3& c, const dvec3& n, const dvec3& u, double r0, double r1, int seg);
  // A cylinder from a to b, capped.
  void cylinder(const dvec3& a, const dvec3& b, double r, int seg);
  // A pair of flanges around a pipe of radius r at c (direction d, frame u): a ring of radius rf,
  // 2 * halfThickness long, closed against the pipe by annuli.
  void flange(const dvec3& c, const dvec3& d, const dvec3& u, double r, double rf,
              double halfThickness, int seg);
  // Half an ellipsoid on the circle of radius r at c: toward d, reaching depth along it.
  void dome(const dvec3& c, const dvec3& d, double r, double depth, int seg, int rings);
  // A torus around axis (unit) at c: radius R of the ring, r of the tube.
  void torus(const dvec3& c, const dvec3& axis, double R, double r, int segRing, int segTube);
  // A prism from a to b with `sides` flat sides of circumradius r, capped (a bolt's hex head).
  void prism(const dvec3& a, const dvec3& b, double r, int sides);

  std::size_t triangles() const { return m_.indices.size() / 3; }

 private:
  GltfMesh& m_;
};

}  // namespace hlod::plant
