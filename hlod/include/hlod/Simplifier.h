#pragma once
// Mesh simplification for the HLOD levels (Lakhia III-A used QSlim). Two implementations behind
// one interface: meshoptimizer's edge-collapse simplifier (default, "meshopt") and OpenMesh's
// quadric decimater ("openmesh").
//
// Contract shared by both: vertices on open borders are locked (never removed or moved). The
// builder's pieces are open along their cutting planes, so locking the border keeps every cut
// vertex and neighbouring nodes meet exactly. Output vertices are copies of input vertices
// (positions, normals and texture coordinates bit for bit); no vertex is moved.
#include <cstddef>
#include <memory>
#include <string_view>

#include "hlod/Mesh.h"
#include "hlod/Result.h"

namespace hlod {

struct SimplifiedMesh {
  Mesh mesh;                    // compact: only the vertices the kept triangles use
  double geometricError = 0.0;  // estimated deviation from the input, world units
};

class Simplifier {
 public:
  virtual ~Simplifier() = default;
  virtual const char* name() const = 0;
  // Simplifies toward targetTriangles (may stay above it when locked borders forbid more).
  // mesh should be welded (weldVertices) so that only real borders and cuts are open. A mesh
  // already at or below the target comes back unchanged.
  SimplifiedMesh simplify(const Mesh& mesh, std::size_t targetTriangles) const {
    if (mesh.triangleCount() <= targetTriangles || mesh.positions.empty()) return {mesh};
    return reduce(mesh, targetTriangles);
  }

 protected:
  // The simplifier proper, for a non-empty mesh above the target.
  virtual SimplifiedMesh reduce(const Mesh& mesh, std::size_t targetTriangles) const = 0;
};

// "meshopt" or "openmesh"; an Error naming the choices otherwise.
Result<std::unique_ptr<Simplifier>> makeSimplifier(std::string_view name);

// Merges vertices whose position and texture coordinate are equal (normals of merged vertices
// are averaged), and drops triangles with an invalid index or a repeated vertex. Vertices with
// equal positions but different texture coordinates stay apart (a texture seam).
Mesh weldVertices(const Mesh& mesh);

// Moves vertices to the order the triangles use them and drops unused ones.
Mesh compactVertices(const Mesh& mesh);

}  // namespace hlod
