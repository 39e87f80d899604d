#pragma once
// A splat (Parry et al. sec. 3 and 5, after QSplat [Rus00]): a node of the bounding-sphere
// hierarchy drawn as a point, sized by its sphere, with the sphere's normal and a texture
// coordinate for its colour. A node whose projected size falls below a few pixels is drawn as its
// splats instead of its triangles.
#include <glm/glm.hpp>

namespace hlod {

struct Splat {
  glm::vec3 position{0.0f};  // relative to the node's centre (LocalMesh::centre)
  float radius = 0.0f;
  glm::vec3 normal{0.0f, 0.0f, 1.0f};
  glm::vec2 texCoord{0.0f};
};

}  // namespace hlod
