#pragma once
// How a mesh's triangles simplify further without re-simplifying: Parry's simplification arrays
// (hlod/parry/SimplificationArrays.h) carried with a mesh, a node payload and a GPU mesh, so that
// a node can be drawn with any number of triangles between its coarsest and its own.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace hlod {

// Parry's simplification arrays from a mesh's triangles down (hlod/parry/SimplificationArrays.h),
// over the mesh's own vertices: the mesh's triangles are in the order the combinations decimate
// them; combination j moves the vertices of moves[2 k] for k in [moveEnd[j-1], moveEnd[j]) into
// vertex moves[2 k + 1] (a vertex of the mesh that its triangles do not use until then), and
// decimates increments[j] triangles. (A sphere combination is one move per child in the paper;
// here a child has a copy per face it belongs to, each with the face's texture coordinates, and
// each copy moves.) Empty: the mesh is drawn whole only.
struct Progression {
  std::vector<std::uint32_t> moves;       // pairs: a vertex, the vertex it combines into
  std::vector<std::uint32_t> moveEnd;     // per combination: the end of its pairs in moves
  std::vector<std::uint32_t> increments;  // per combination: the triangles it decimates

  bool empty() const { return increments.empty(); }
  std::size_t decimated() const;  // the sum of the increments
};

// The triangles of a mesh (indices, in decimation order) drawn with n of them, n between
// triangles - progression.decimated() and the mesh's triangle count: its last n triangles, each
// corner moved to the vertex it references once the combinations that decimate triangles before
// them are made. Exactly n triangles: where a combination that decimates several straddles the
// cut, those of its triangles inside the n are left with no area (a GPU draws nothing of them).
// n = the triangle count gives the indices unchanged. vertexCount bounds every index.
std::vector<std::uint32_t> progressiveIndices(std::span<const std::uint32_t> indices,
                                              const Progression& progression, std::size_t n,
                                              std::size_t vertexCount);

}  // namespace hlod
