// Simplification with meshoptimizer's meshopt_simplify (edge collapses driven by quadrics).
#include <algorithm>
#include <cfloat>
#include <vector>

#include <meshoptimizer.h>

#include "builder/SamePosition.h"
#include "builder/SimplifierImpl.h"

namespace hlod {

namespace {

class MeshoptSimplifier final : public Simplifier {
 public:
  const char* name() const override { return "meshopt"; }

  ReducedShape reduce(const Shape& shape, std::size_t targetTriangles,
                      double errorLimit) const override {
    // meshopt works on floats: positions relative to the box centre keep their precision.
    Aabb box;
    for (const auto& p : shape.positions) box.extend(p);
    const glm::dvec3 centre = box.centre();
    std::vector<float> pos;
    pos.reserve(shape.positions.size() * 3);
    auto push = [&](const glm::dvec3& q) {
      const glm::dvec3 p = q - centre;
      pos.insert(pos.end(), {float(p.x), float(p.y), float(p.z)});
    };
    // Split non-manifold vertices share a position, and meshopt would take them for attribute
    // wedges of one vertex again: move each further copy by a few micro-extents.
    const double nudge = 1e-6 * std::max(1e-9, glm::length(box.size()));
    const std::vector<std::uint32_t> first = firstAtSamePosition(shape.positions);
    std::vector<std::uint32_t> copies(shape.positions.size(), 0);  // so far, by first copy
    for (std::size_t v = 0; v < shape.positions.size(); ++v)
      push(shape.positions[v] + nudge * double(copies[first[v]]++) * glm::dvec3(1.0, 0.7, 0.3));
    // meshopt 0.18 has no per-vertex lock, but it never moves or removes a vertex that has three
    // or more attribute "wedges" (vertices at its position). Two unreferenced copies of each
    // locked vertex make it one; they take no part in any triangle.
    for (std::size_t v = 0; v < shape.positions.size(); ++v) {
      if (shape.locked[v] != kVertexLocked) continue;
      push(shape.positions[v]);
      push(shape.positions[v]);
    }
    const std::size_t vertexCount = pos.size() / 3;
    ReducedShape out;
    out.indices.resize(shape.indices.size());
    float relError = 0.0f;
    // meshopt's target_error is relative to the mesh's extent (meshopt_simplifyScale).
    const float scale = meshopt_simplifyScale(pos.data(), vertexCount, sizeof(float) * 3);
    const float targetError =
        scale > 0.0f && errorLimit < double(scale) ? float(errorLimit / double(scale)) : 1.0f;
    const std::size_t n = meshopt_simplify(
        out.indices.data(), shape.indices.data(), shape.indices.size(), pos.data(), vertexCount,
        sizeof(float) * 3, targetTriangles * 3, targetError, 0, &relError);
    out.indices.resize(n);
    out.geometricError = double(relError) * double(scale);
    return out;
  }
};

}  // namespace

Simplifier* makeMeshoptSimplifier() {
  return new MeshoptSimplifier();
}

}  // namespace hlod
