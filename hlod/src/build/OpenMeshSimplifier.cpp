// Simplification with OpenMesh's decimater and its quadric module (Garland-Heckbert, as QSlim,
// which Lakhia III-A used).
#include <algorithm>
#include <cmath>
#include <vector>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include "build/SimplifierImpl.h"

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

  SimplifiedMesh reduce(const Mesh& mesh, std::size_t targetTriangles) const override {
    SimplifiedMesh out;
    const glm::dvec3 centre = mesh.bounds().centre();
    OmMesh om;
    OpenMesh::VPropHandleT<std::uint32_t> source;
    om.add_property(source);
    std::vector<OmMesh::VertexHandle> vh(mesh.positions.size());
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
      const glm::dvec3 p = mesh.positions[i] - centre;
      vh[i] = om.add_vertex(OmMesh::Point(p.x, p.y, p.z));
      om.property(source, vh[i]) = std::uint32_t(i);
    }
    // Triangles OpenMesh rejects (non-manifold) are kept as they are, beside the decimated mesh.
    std::vector<std::uint32_t> rejected;
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
      const auto a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
      if (!om.add_face(vh[a], vh[b], vh[c]).is_valid()) rejected.insert(rejected.end(), {a, b, c});
    }
    // Lock the border: the cuts to neighbouring nodes (and texture seams, which are open edges
    // after welding on position and uv) must not move.
    for (auto v : om.vertices())
      if (om.is_boundary(v)) om.status(v).set_locked(true);
    om.update_face_normals();

    OpenMesh::Decimater::DecimaterT<OmMesh> decimater(om);
    ModQuadricWithError::Handle quadric;
    OpenMesh::Decimater::ModNormalFlippingT<OmMesh>::Handle flipping;
    decimater.add(quadric);
    decimater.add(flipping);
    if (!decimater.initialize()) {
      out.mesh = mesh;
      return out;
    }
    const std::size_t keptFaces =
        targetTriangles > rejected.size() / 3 ? targetTriangles - rejected.size() / 3 : 1;
    decimater.decimate_to_faces(0, keptFaces);
    out.geometricError = std::sqrt(std::max(0.0, decimater.module(quadric).maxError()));
    om.garbage_collection();

    Mesh kept = mesh;
    kept.indices.clear();
    for (auto f : om.faces()) {
      for (auto v : om.fv_range(f)) kept.indices.push_back(om.property(source, v));
    }
    kept.indices.insert(kept.indices.end(), rejected.begin(), rejected.end());
    out.mesh = compactVertices(kept);
    return out;
  }
};

}  // namespace

Simplifier* makeOpenMeshSimplifier() {
  return new OpenMeshSimplifier();
}

}  // namespace hlod
