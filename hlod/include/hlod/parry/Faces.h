#pragma once
// A block's facades and faces (Parry et al. sec. 3-4, Fig. 3): "Each block is composed of a set
// of simple facades", the sides of the block, and each facade of faces, near-planar segments of
// it; "Facades will typically be flat, though care must be taken in handling smoothly curving
// building fronts." Faces are what the sphere hierarchy simplifies (each on its own, its outline
// kept: ParrySimplifier.h); facades are the first level of a block's tree.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "hlod/Mesh.h"
#include "hlod/UpAxis.h"

namespace hlod {

struct FaceParams {
  // A triangle joins a face when its normal is within this angle of the face's first triangle's
  // and its corners within planeTolerance of that triangle's plane (a curved front becomes faces
  // of about this much turn).
  double maxAngleDegrees = 20.0;
  // Relative to the diagonal of the mesh's box.
  double planeTolerance = 2e-3;
};

struct Face {
  glm::dvec3 normal{0.0, 0.0, 1.0};  // of its first triangle (unit)
  double area = 0.0;
  std::uint32_t triangles = 0;
};

struct FaceSegmentation {
  std::vector<std::uint32_t> faceOf;  // per triangle of the mesh
  std::vector<Face> faces;
};

// Grows faces over the triangles sharing an edge (the same two vertices: a texture seam, where
// vertices differ in texture coordinates, ends a face), largest triangles first. Triangles of no
// area join the face of a neighbour.
FaceSegmentation segmentFaces(const Mesh& mesh, const FaceParams& params = {});

// The facade a face belongs to: the side of the block it faces (kFacadeSides of them, about the
// block's dominant horizontal direction), its roof or its underside.
constexpr std::uint32_t kFacadeSides = 4;
constexpr std::uint32_t kFacadeRoof = kFacadeSides;
constexpr std::uint32_t kFacadeUnderside = kFacadeSides + 1;
constexpr std::uint32_t kFacadeCount = kFacadeSides + 2;

// Per face: its facade. A face whose normal is within 45 degrees of up is roof, of down the
// underside; the others go to the side whose direction (the block's dominant direction, the
// area-weighted mean of the faces' horizontal directions modulo 90 degrees, turned by multiples of
// 90) is nearest their normal's horizontal direction. Details attached to a facade (sec. 3: "window
// frames or doorways") stay with it: a face of less than kDetailShare of its own facade's area
// takes the facade of the neighbouring face it shares the longest outline with (largest details
// first, so a window's sill follows its recess, which follows the wall).
constexpr double kDetailShare = 0.05;
std::vector<std::uint32_t> facadesOf(const Mesh& mesh, const FaceSegmentation& faces, UpAxis up);

}  // namespace hlod
