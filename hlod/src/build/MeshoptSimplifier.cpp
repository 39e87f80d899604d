// Simplification with meshoptimizer's meshopt_simplify (edge collapses driven by quadrics).
#include <cfloat>
#include <vector>

#include <meshoptimizer.h>

#include "build/SimplifierImpl.h"

namespace hlod {

namespace {

class MeshoptSimplifier final : public Simplifier {
 public:
  const char* name() const override { return "meshopt"; }

  SimplifiedMesh reduce(const Mesh& mesh, std::size_t targetTriangles) const override {
    SimplifiedMesh out;
    // meshopt works on floats: positions relative to the box centre keep their precision.
    const glm::dvec3 centre = mesh.bounds().centre();
    std::vector<float> pos(mesh.positions.size() * 3);
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
      const glm::dvec3 p = mesh.positions[i] - centre;
      pos[3 * i] = float(p.x);
      pos[3 * i + 1] = float(p.y);
      pos[3 * i + 2] = float(p.z);
    }
    // meshopt_simplify finds vertices sharing a position itself and keeps texture seams
    // (same position, different uv) intact, so the index buffer can be passed as it is.
    // LockBorder keeps every vertex on an open edge: the cuts between nodes.
    std::vector<std::uint32_t> dst(mesh.indices.size());
    float relError = 0.0f;
    const std::size_t n = meshopt_simplify(
        dst.data(), mesh.indices.data(), mesh.indices.size(), pos.data(), mesh.positions.size(),
        sizeof(float) * 3, targetTriangles * 3, 1.0f, meshopt_SimplifyLockBorder, &relError);
    dst.resize(n);
    const float scale = meshopt_simplifyScale(pos.data(), mesh.positions.size(), sizeof(float) * 3);
    Mesh kept = mesh;
    kept.indices = std::move(dst);
    out.mesh = compactVertices(kept);
    out.geometricError = double(relError) * double(scale);
    return out;
  }
};

}  // namespace

Simplifier* makeMeshoptSimplifier() {
  return new MeshoptSimplifier();
}

}  // namespace hlod
