#pragma once
// What makes two meshes one material for a node payload (one texture and base colour each, and
// one side or two): how cutIntoBlocks groups a model's meshes. Private to the builder.
#include <tuple>

#include "hlod/Mesh.h"

namespace hlod {

struct MaterialKey {
  const Image* texture;
  float r, g, b, a;
  bool oneSided;
  bool operator<(const MaterialKey& o) const {
    return std::tie(texture, r, g, b, a, oneSided) <
           std::tie(o.texture, o.r, o.g, o.b, o.a, o.oneSided);
  }
};

inline MaterialKey materialKeyOf(const Mesh& m) {
  return {m.texture.get(), m.baseColor.r, m.baseColor.g, m.baseColor.b, m.baseColor.a, m.oneSided};
}

}  // namespace hlod
