#pragma once
// Shader variants as feature bits (as filament's material variants, Godot's feature defines):
// a key names one program, the program kind in the high bits and the declared effects it
// compiles in the low bits; each bit becomes one #define. Only declared effects set bits, so an
// undeclared effect is never compiled.
#include <cstdint>
#include <string>

#include "hlod/scene/SceneFile.h"

namespace renderer {

enum class ProgramKind : std::uint32_t {
  Mesh,
  ShadowDepth,
  Sky,
  Ssao,
  SsaoBlur,
  Composite,
  Outline
};

namespace variant {
constexpr std::uint32_t kTexture = 1u << 0;
constexpr std::uint32_t kLit = 1u << 1;
constexpr std::uint32_t kBlinnPhong = 1u << 2;
constexpr std::uint32_t kSun = 1u << 3;
constexpr std::uint32_t kFog = 1u << 4;
constexpr std::uint32_t kShadows = 1u << 5;
constexpr std::uint32_t kSunDisc = 1u << 6;  // sky: a glow around the sun
constexpr std::uint32_t kSplats = 1u << 7;   // mesh: points sized by their sphere
}  // namespace variant

struct VariantKey {
  ProgramKind kind = ProgramKind::Mesh;
  std::uint32_t bits = 0;
  std::uint32_t packed() const { return static_cast<std::uint32_t>(kind) << 16 | bits; }
  bool operator<(const VariantKey& o) const { return packed() < o.packed(); }
  bool operator==(const VariantKey& o) const { return packed() == o.packed(); }
};

// The mesh pass's variant for a mesh with or without a texture under the declared effects, drawn
// as triangles or as splats.
VariantKey meshVariant(const hlod::SceneEffects& effects, bool textured, bool splats = false);
// "#define HAS_TEXTURE\n#define LIT\n...": one line per bit of the key.
std::string definesFor(const VariantKey& key);

}  // namespace renderer
