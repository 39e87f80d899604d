#pragma once
// Parry et al. sec. 5 on a piece of a block: "When extending this algorithm to the facade faces
// ..., one of our requirements is that the shape of the face does not change during
// simplification. We accomplish this by assigning 'silhouette' points to the original data set.
// These points represent the outline or shape of the face that we wish to preserve. ...
// Ultimately, at the highest level of the hierarchy (lowest LOD), we wish to retain the fewest
// points necessary to describe a facade face."
//
// The piece is segmented into faces (Faces.h). Its facade faces, those of at least kMajorFace of
// its area, keep their shape: the corners of their outer outline (where it turns by more than
// silhouetteAngle, branches or ends) are silhouette vertices, and each straight run of it between
// corners is a group of its own (its vertices combine only along the run, so it stays straight).
// Every other vertex, the inside of a facade face with the holes in it (window openings) and the
// details attached to it (recesses, ledges), belongs to the group of the largest face that uses
// it, and simplifies away. A detail standing free (minor faces joined through the vertices they
// own, minor all together: a rooftop unit, a ledge of its own) is one group and simplifies away
// whole. Last, each run's root combines into a corner at its end (mergeIntoCorners), so at the
// coarsest a facade face is the polygon of its corners fanned from one inner vertex: "the fewest
// points necessary to describe a facade face". Vertices the caller locks (the piece's seams with
// its neighbours) are silhouette vertices too. The automatic silhouette is this document's choice:
// the paper leaves it open ("Automating silhouette vertex determination is a problem yet to be
// solved").
//
// The hierarchy is over positions, so faces that share a vertex move it alike and never open a
// crack. A drawn vertex is a (sphere, face) pair: the sphere's centre, with the face's texture
// coordinate there (from the face's affine texture mapping, as facades are mapped) and the
// face's normal where the sphere's turns too far from it; a leaf keeps its input vertex's.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "hlod/Mesh.h"
#include "hlod/parry/Faces.h"
#include "hlod/parry/SimplificationArrays.h"
#include "hlod/parry/SphereHierarchy.h"

namespace hlod {

constexpr double kMajorFace = 0.002;  // of the piece's area

struct ParryParams {
  FaceParams faces;
  double silhouetteAngleDegrees = 30.0;
};

struct ParryPiece {
  SphereHierarchy hierarchy;  // leaves: the distinct positions of the mesh
  SimplificationArrays arrays;
  FaceSegmentation faces;
  std::vector<std::uint32_t> positionOf;  // per mesh vertex: its leaf
  std::vector<std::uint8_t> silhouette;   // per leaf
  // Per face: its plane basis and the affine map from plane coordinates to texture coordinates
  // (rows u and v: a * s + b * t + c), and the box of its texture coordinates.
  struct FaceFrame {
    glm::dvec3 origin{0.0}, s{1, 0, 0}, t{0, 1, 0};
    glm::dvec3 u{0.0}, v{0.0};
    glm::vec2 uvMin{0.0f}, uvMax{0.0f};
  };
  std::vector<FaceFrame> frames;
};

// Organises the piece (a welded mesh). locked: per vertex of mesh, or empty; a non-zero flag
// makes its position a silhouette vertex.
ParryPiece organisePiece(const Mesh& mesh, const std::vector<std::uint8_t>& locked = {},
                         const ParryParams& params = {});

// The piece drawn with about n triangles (the boundary between combinations nearest n, clamped to
// what the arrays hold), with its progression down from there; mesh's material. splatSize
// receives the radius of the last combination made (the geometric error).
Mesh pieceAt(const Mesh& mesh, const ParryPiece& piece, std::size_t n, double* splatSize = nullptr);

}  // namespace hlod
