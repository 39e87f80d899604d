// Simplification with OpenMesh's decimater and its quadric module (Garland-Heckbert, as QSlim,
// which Lakhia III-A used).
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include "builder/SimplifierImpl.h"

namespace hlod {

namespace {

struct DoubleTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
  VertexAttributes(OpenMesh::Attributes::Status);
  EdgeAttributes(OpenMesh::Attributes::Status);
  HalfedgeAttributes(OpenMesh::Attributes::Status | OpenMesh::Attributes::PrevHalfedge);
  FaceAttributes(OpenMesh::Attributes::Status | OpenMesh::Attributes::Normal);
};
using OmMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;

// The quadric module, also remembering the largest quadric error of the collapses it allowed:
// sqrt of it bounds the distance of a removed vertex to the planes it stood for.
class ModQuadricWithError : public OpenMesh::Decimater::ModQuadricT<OmMesh> {
 public:
  using Base = OpenMesh::Decimater::ModQuadricT<OmMesh>;
  using Handle = OpenMesh::Decimater::ModHandleT<ModQuadricWithError>;
  explicit ModQuadricWithError(OmMesh& mesh) : Base(mesh) {}
  void preprocess_collapse(const CollapseInfo& ci) override {
    maxError_ = std::max(maxError_, double(Base::collapse_priority(ci)));
    Base::preprocess_collapse(ci);
  }
  double maxError() const { return maxError_; }

 private:
  double maxError_ = 0.0;
};

class OpenMeshSimplifier final : public Simplifier {
 public:
  const char* name() const override { return "openmesh"; }

  // errorLimit is left to the guard around it (the quadric module's limit is in squared
  // distances summed over planes, not a distance).
  ReducedShape reduce(const Shape& shape, std::size_t targetTriangles,
                      double /*errorLimit*/) const override {
    ReducedShape out;
    Aabb box;
    for (const auto& p : shape.positions) box.extend(p);
    const glm::dvec3 centre = box.centre();
    OmMesh om;
    OpenMesh::VPropHandleT<std::uint32_t> source;
    om.add_property(source);
    auto addVertex = [&](std::uint32_t i) {
      const glm::dvec3 p = shape.positions[i] - centre;
      const OmMesh::VertexHandle v = om.add_vertex(OmMesh::Point(p.x, p.y, p.z));
      om.property(source, v) = i;
      if (shape.locked[i] == kVertexLocked) om.status(v).set_locked(true);
      return v;
    };
    std::vector<OmMesh::VertexHandle> vh(shape.positions.size());
    for (std::size_t i = 0; i < shape.positions.size(); ++i) vh[i] = addVertex(std::uint32_t(i));
    // OpenMesh checks each collapse against the one-rings of both its ends and then updates the
    // neighbours of the vertex it keeps: at a vertex of n faces (a fan's centre, the first
    // vertex of a triangulated n-gon) a check costs O(n) and a collapse O(n^2), and a fan of
    // 12,000 triangles decimated for over a minute. The work per vertex is bounded: a vertex of
    // more than kMaxValence faces is split into copies of at most kMaxValence faces each (in
    // the faces' order), which map back to the one vertex in the output.
    constexpr std::size_t kMaxValence = 64;
    std::vector<std::uint32_t> valence(shape.positions.size(), 0), used(shape.positions.size(), 0);
    for (std::uint32_t i : shape.indices) ++valence[i];
    std::vector<std::vector<OmMesh::VertexHandle>> copies(shape.positions.size());
    auto handleOf = [&](std::uint32_t i) {
      if (valence[i] <= kMaxValence) return vh[i];
      const std::size_t copy = used[i]++ / kMaxValence;
      if (copy == 0) return vh[i];
      auto& c = copies[i];
      while (c.size() < copy) c.push_back(addVertex(i));
      return c[copy - 1];
    };
    // Triangles OpenMesh rejects (non-manifold) are kept as they are, beside the decimated mesh.
    std::vector<std::uint32_t> rejected;
    for (std::size_t t = 0; t + 2 < shape.indices.size(); t += 3) {
      const auto a = shape.indices[t], b = shape.indices[t + 1], c = shape.indices[t + 2];
      if (!om.add_face(handleOf(a), handleOf(b), handleOf(c)).is_valid())
        rejected.insert(rejected.end(), {a, b, c});
    }
    // The copies meet along a cut that OpenMesh sees as a border: the copies and the vertices
    // on the cut stay, so that both sides of it keep the same edges and close again in the
    // output (a collapse on one side only opened a crack).
    for (std::size_t i = 0; i < copies.size(); ++i) {
      if (copies[i].empty()) continue;
      std::vector<OmMesh::VertexHandle> split = copies[i];
      split.push_back(vh[i]);
      for (const OmMesh::VertexHandle v : split) {
        om.status(v).set_locked(true);
        for (const OmMesh::VertexHandle n : om.vv_range(v))
          if (om.is_boundary(n)) om.status(n).set_locked(true);
      }
    }
    om.update_face_normals();

    OpenMesh::Decimater::DecimaterT<OmMesh> decimater(om);
    ModQuadricWithError::Handle quadric;
    OpenMesh::Decimater::ModNormalFlippingT<OmMesh>::Handle flipping;
    decimater.add(quadric);
    decimater.add(flipping);
    if (!decimater.initialize()) {
      out.indices = shape.indices;
      return out;
    }
    const std::size_t keptFaces =
        targetTriangles > rejected.size() / 3 ? targetTriangles - rejected.size() / 3 : 1;
    decimater.decimate_to_faces(0, keptFaces);
    out.geometricError = std::sqrt(std::max(0.0, decimater.module(quadric).maxError()));
    om.garbage_collection();
    for (auto f : om.faces()) {
      std::array<std::uint32_t, 3> t{};
      int k = 0;
      for (auto v : om.fv_range(f)) t[std::size_t(k++)] = om.property(source, v);
      // Two copies of a split vertex in one triangle: no area, and a repeated index.
      if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
        out.indices.insert(out.indices.end(), t.begin(), t.end());
    }
    out.indices.insert(out.indices.end(), rejected.begin(), rejected.end());
    return out;
  }
};

}  // namespace

Simplifier* makeOpenMeshSimplifier() {
  return new OpenMeshSimplifier();
}

}  // namespace hlod
