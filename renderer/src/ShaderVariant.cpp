#include "renderer/ShaderVariant.h"

namespace renderer {

VariantKey meshVariant(const hlod::SceneEffects& e, bool textured, bool splats) {
  VariantKey key{ProgramKind::Mesh, 0};
  if (textured && e.textures) key.bits |= variant::kTexture;
  if (e.lit()) key.bits |= variant::kLit;
  if (e.shading == hlod::Shading::BlinnPhong) key.bits |= variant::kBlinnPhong;
  if (e.lit() && e.sun) key.bits |= variant::kSun;
  if (e.fog) key.bits |= variant::kFog;
  if (e.lit() && e.sun && e.shadows) key.bits |= variant::kShadows;
  if (splats) key.bits |= variant::kSplats;
  return key;
}

std::string definesFor(const VariantKey& key) {
  static const struct {
    std::uint32_t bit;
    const char* name;
  } kDefines[] = {{variant::kTexture, "HAS_TEXTURE"},
                  {variant::kLit, "LIT"},
                  {variant::kBlinnPhong, "BLINN_PHONG"},
                  {variant::kSun, "SUN"},
                  {variant::kFog, "FOG"},
                  {variant::kShadows, "SHADOWS"},
                  {variant::kSunDisc, "SUN_DISC"},
                  {variant::kSplats, "SPLATS"}};
  std::string defines;
  for (const auto& d : kDefines)
    if (key.bits & d.bit) defines += std::string("#define ") + d.name + "\n";
  return defines;
}

}  // namespace renderer
