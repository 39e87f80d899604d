#pragma once
// GLSL sources of the mesh pass. Effects are #defines: HAS_TEXTURE, LAMBERT, FOG.

namespace renderer::shaders {

inline constexpr const char* kMeshVertex = R"(
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec2 aTexCoord;
uniform mat4 uModelView;   // camera-relative, formed in double on the CPU
uniform mat4 uProjection;  // reversed-Z
out vec3 vNormal;
out vec2 vTexCoord;
out float vDistance;
void main() {
  vec4 p = uModelView * vec4(aPosition, 1.0);
  gl_Position = uProjection * p;
  vNormal = aNormal;
  vTexCoord = aTexCoord;
  vDistance = length(p.xyz);
}
)";

inline constexpr const char* kMeshFragment = R"(
in vec3 vNormal;
in vec2 vTexCoord;
in float vDistance;
uniform vec4 uBaseColor;
uniform vec3 uSunDir;
uniform vec3 uUp;
uniform vec3 uBackground;
uniform float uFogDensity;
#ifdef HAS_TEXTURE
uniform sampler2D uTexture;
#endif
out vec4 fragColor;
void main() {
  vec4 albedo = uBaseColor;
#ifdef HAS_TEXTURE
  albedo *= texture(uTexture, vTexCoord);
#endif
  vec3 colour = albedo.rgb;
#ifdef LAMBERT
  vec3 n = normalize(vNormal);
  if (!gl_FrontFacing) n = -n;  // two-sided: scanned and CAD data have mixed winding
  float sun = max(dot(n, uSunDir), 0.0);
  float sky = 0.5 + 0.5 * dot(n, uUp);
  colour *= 0.30 + 0.25 * sky + 0.55 * sun;
#endif
#ifdef FOG
  float f = exp(-uFogDensity * vDistance);
  colour = mix(uBackground, colour, clamp(f, 0.0, 1.0));
#endif
  fragColor = vec4(colour, 1.0);
}
)";

}  // namespace renderer::shaders
