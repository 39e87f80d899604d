#pragma once
// Per-node pre-processed values (Lakhia III-B): bounding box, cost (eq. 1), static benefit
// (eq. 2) and average normal (eq. 3).
#include <cstdint>

#include "hlod/Mesh.h"
#include "hlod/store/Skeleton.h"

namespace hlod {

// Eq. 1: cost_n = numTexTri_n * c_tex + numUnTexTri_n * (1 - c_tex).
double nodeCost(std::uint64_t numTexTri, std::uint64_t numUnTexTri, double cTex);

// Eq. 2: staticBenefit_n = sqrt(numTri_n * sum of triangle areas).
double staticBenefit(std::uint64_t numTri, double area);

struct NodeMeasures {
  Aabb bounds;
  std::uint32_t numTri = 0;
  std::uint32_t numTexTri = 0;  // triangles drawn with a texture
  double area = 0.0;
  double cost = 0.0;
  double staticBenefit = 0.0;
  glm::vec3 avgNormal{0.0f, 0.0f, 1.0f};
};

// Eq. 3: area-weighted average of the triangle normals, normalised. Zero-area triangles add
// nothing; when nothing is left (no area, or normals cancelling out) the result is +Z, never NaN.
glm::vec3 averageNormal(const Mesh& mesh);

// All of the above for one node's mesh. A mesh is textured when it has a texture and one texture
// coordinate per vertex; then all its triangles count as textured.
NodeMeasures measureNode(const Mesh& mesh, double cTex);

// The measures of a node's mesh in its NodeInfo: numTri, numTexTri, minTri (its progression's
// coarsest, 0 without one), cost, staticBenefit and avgNormal.
void describeNode(NodeInfo& info, const Mesh& mesh, double cTex);

// The mesh as a node's payload: positions in float relative to `centre` (the node's, so that
// node centres nest), the rest as toLocal gives it.
LocalMesh localAround(const Mesh& mesh, const glm::dvec3& centre);

// Sum of triangle areas, in double.
double surfaceArea(const Mesh& mesh);

}  // namespace hlod
