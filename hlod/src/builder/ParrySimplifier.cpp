// Simplification by Parry's sphere-hierarchy vertex clustering (hlod/parry/ParryPiece.h).
#include <cassert>

#include "builder/SimplifierImpl.h"
#include "hlod/parry/ParryPiece.h"

namespace hlod {

namespace {

class ParrySimplifier final : public Simplifier {
 public:
  const char* name() const override { return "parry"; }

  SimplifiedMesh simplify(const Mesh& mesh, std::size_t targetTriangles,
                          const std::vector<std::uint8_t>& locked, double) const override {
    SimplifiedMesh out;
    if (mesh.triangleCount() == 0) {
      out.mesh = mesh;
      return out;
    }
    const ParryPiece piece = organisePiece(mesh, locked);
    out.mesh = pieceAt(mesh, piece, targetTriangles, &out.geometricError);
    return out;
  }

  SimplifiedMesh simplifyUnion(const Mesh& mesh, std::size_t targetTriangles,
                               const std::vector<std::uint8_t>& locked,
                               double errorLimit) const override {
    return simplify(mesh, targetTriangles, locked, errorLimit);
  }

 protected:
  ReducedShape reduce(const Shape&, std::size_t, double) const override {
    assert(false && "ParrySimplifier replaces simplify() whole");
    return {};
  }
};

}  // namespace

Simplifier* makeParrySimplifier() {
  return new ParrySimplifier();
}

}  // namespace hlod
