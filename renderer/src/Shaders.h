#pragma once
// GLSL sources of hlodr's passes. Mesh effects are #defines (ShaderVariant.h): HAS_TEXTURE, LIT,
// BLINN_PHONG, SUN, FOG, SHADOWS, and SPLATS for nodes drawn as points; the sky's SUN_DISC.

namespace renderer::shaders {

inline constexpr const char* kMeshVertex = R"(
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec2 aTexCoord;
uniform mat4 uModelView;   // camera-relative, formed in double on the CPU
uniform mat4 uProjection;  // reversed-Z
uniform vec3 uOffset;      // mesh centre - eye, world axes
#ifdef SPLATS
layout(location = 3) in float aRadius;
uniform float uPointScale;  // projection[1][1] x viewport height: a radius at w = 1 in pixels x 2
#endif
out vec3 vNormal;
out vec2 vTexCoord;
out vec3 vFromEye;  // world axes, camera-relative
#ifdef SHADOWS
uniform mat4 uShadowModel;  // local position -> the sun's clip space
out vec4 vShadowCoord;
#endif
void main() {
  gl_Position = uProjection * (uModelView * vec4(aPosition, 1.0));
  vNormal = aNormal;
  vTexCoord = aTexCoord;
  vFromEye = aPosition + uOffset;
#ifdef SPLATS
  // The splat's sphere seen from here: its diameter in pixels (Parry sec. 5, QSplat).
  gl_PointSize = clamp(aRadius * uPointScale / gl_Position.w, 1.0, 64.0);
#endif
#ifdef SHADOWS
  vShadowCoord = uShadowModel * vec4(aPosition, 1.0);
#endif
}
)";

inline constexpr const char* kMeshFragment = R"(
in vec3 vNormal;
in vec2 vTexCoord;
in vec3 vFromEye;
uniform vec4 uBaseColor;
#ifdef HAS_TEXTURE
uniform sampler2D uTexture;
#endif
#ifdef LIT
uniform vec3 uUp;
#endif
#ifdef SUN
uniform vec3 uSunDir;
uniform vec3 uSunColour;  // colour x intensity
#endif
#ifdef FOG
uniform float uFogDensity;
uniform vec3 uFogColour;
#endif
#ifdef SHADOWS
in vec4 vShadowCoord;
uniform sampler2DShadow uShadowMap;
uniform float uShadowBias;   // depth units, at normal incidence
uniform float uShadowTexel;  // 1 / resolution
// 3x3 percentage-closer filter; outside the map is lit.
float sunVisibility(float cosine) {
  vec3 c = vShadowCoord.xyz / vShadowCoord.w;
  vec2 uv = c.xy * 0.5 + 0.5;
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0))) || c.z > 1.0) return 1.0;
  float bias = uShadowBias * (1.0 + 3.0 * sqrt(max(1.0 - cosine * cosine, 0.0)) / max(cosine, 0.2));
  float lit = 0.0;
  for (int y = -1; y <= 1; ++y)
    for (int x = -1; x <= 1; ++x)
      lit += texture(uShadowMap, vec3(uv + vec2(x, y) * uShadowTexel, c.z - bias));
  return lit / 9.0;
}
#endif
out vec4 fragColor;
void main() {
#ifdef SPLATS
  vec2 disc = gl_PointCoord - vec2(0.5);
  if (dot(disc, disc) > 0.25) discard;  // round splats
#endif
  vec4 albedo = uBaseColor;
#ifdef HAS_TEXTURE
  albedo *= texture(uTexture, vTexCoord);
#endif
  vec3 colour = albedo.rgb;
#ifdef LIT
  vec3 n = normalize(vNormal);
  if (!gl_FrontFacing) n = -n;  // two-sided: scanned and CAD data have mixed winding
  float sky = 0.5 + 0.5 * dot(n, uUp);
  vec3 light = vec3(0.30 + 0.25 * sky);
  vec3 specular = vec3(0.0);
#ifdef SUN
  float cosine = dot(n, uSunDir);
  float direct = max(cosine, 0.0);
#ifdef SHADOWS
  if (direct > 0.0) direct *= sunVisibility(cosine);
#endif
  light += 0.55 * direct * uSunColour;
#ifdef BLINN_PHONG
  vec3 h = normalize(uSunDir - normalize(vFromEye));
  if (cosine > 0.0) specular = 0.25 * pow(max(dot(n, h), 0.0), 48.0) * (direct / cosine) * uSunColour;
#endif
#endif
  colour = colour * light + specular;
#endif
#ifdef FOG
  float f = exp(-uFogDensity * length(vFromEye));
  colour = mix(uFogColour, colour, clamp(f, 0.0, 1.0));
#endif
  fragColor = vec4(colour, 1.0);
}
)";

// Depth only, from the sun: the shadow map.
inline constexpr const char* kShadowVertex = R"(
layout(location = 0) in vec3 aPosition;
uniform mat4 uShadowModel;
void main() { gl_Position = uShadowModel * vec4(aPosition, 1.0); }
)";
inline constexpr const char* kShadowFragment = R"(
void main() {}
)";

// One triangle that covers the screen; uv in [0, 1].
inline constexpr const char* kFullscreenVertex = R"(
out vec2 vUv;
void main() {
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  vUv = p;
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);  // depth 0: the far plane under reversed-Z
}
)";

// The sky gradient, drawn after the geometry where the depth is still the clear value (far).
inline constexpr const char* kSkyFragment = R"(
in vec2 vUv;
uniform mat4 uInvViewProj;  // (projection x rotation)^-1: clip -> world direction
uniform vec3 uUp;
uniform vec3 uHorizon;
uniform vec3 uZenith;
uniform vec3 uGround;
#ifdef SUN_DISC
uniform vec3 uSunDir;
uniform vec3 uSunColour;
#endif
out vec4 fragColor;
void main() {
  vec4 p = uInvViewProj * vec4(vUv * 2.0 - 1.0, 0.5, 1.0);
  vec3 dir = normalize(p.xyz / p.w);
  float t = dot(dir, uUp);
  vec3 c = t >= 0.0 ? mix(uHorizon, uZenith, pow(t, 0.6)) : mix(uHorizon, uGround, min(-t * 2.0, 1.0));
#ifdef SUN_DISC
  float s = max(dot(dir, uSunDir), 0.0);
  c += uSunColour * (0.25 * pow(s, 64.0) + 2.0 * pow(s, 2000.0));
#endif
  fragColor = vec4(min(c, vec3(1.0)), 1.0);
}
)";

// Reversed-Z depth -> view-space position: z_view = -B / (depth + A), x = ndc.x (-z) / P00.
inline constexpr const char* kViewPosition = R"(
uniform sampler2D uDepth;
uniform vec4 uProjectionParams;  // P00, P11, A = P22, B = P32
vec3 viewPosition(vec2 uv, float depth) {
  float z = -uProjectionParams.w / (depth + uProjectionParams.z);
  vec2 ndc = uv * 2.0 - 1.0;
  return vec3(ndc.x * -z / uProjectionParams.x, ndc.y * -z / uProjectionParams.y, z);
}
)";

// Screen-space ambient occlusion (Crytek / Bavoil-style hemisphere samples against the depth
// buffer), with a 4x4 interleaved rotation that the blur removes.
inline constexpr const char* kSsaoFragment = R"(
in vec2 vUv;
uniform float uAoRadius;
uniform float uAoStrength;
uniform int uAoSamples;
out vec4 fragColor;
float hash(float n) { return fract(sin(n) * 43758.5453); }
void main() {
  float depth = texture(uDepth, vUv).r;
  if (depth <= 0.0) { fragColor = vec4(1.0); return; }  // sky
  vec3 p = viewPosition(vUv, depth);
  vec3 n = normalize(cross(dFdx(p), dFdy(p)));
  if (dot(n, p) > 0.0) n = -n;  // towards the eye
  ivec2 px = ivec2(gl_FragCoord.xy) & 3;
  float angle = 6.2831853 * float(px.x * 4 + px.y) / 16.0;
  vec3 r = normalize(vec3(cos(angle), sin(angle), 0.0));
  vec3 t = normalize(r - n * dot(r, n));
  if (any(isnan(t))) t = normalize(cross(n, vec3(0.0, 1.0, 0.0)));
  vec3 b = cross(n, t);
  float occluded = 0.0;
  for (int i = 0; i < uAoSamples; ++i) {
    float fi = float(i);
    vec3 k = normalize(vec3(hash(fi * 3.1) * 2.0 - 1.0, hash(fi * 5.7) * 2.0 - 1.0,
                            0.15 + 0.85 * hash(fi * 9.3)));
    float s = (fi + 1.0) / float(uAoSamples);
    k *= uAoRadius * mix(0.1, 1.0, s * s);
    vec3 q = p + t * k.x + b * k.y + n * k.z;
    vec2 uv = vec2(q.x * uProjectionParams.x / -q.z, q.y * uProjectionParams.y / -q.z) * 0.5 + 0.5;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) continue;
    float d = texture(uDepth, uv).r;
    if (d <= 0.0) continue;
    float sceneZ = viewPosition(uv, d).z;
    float range = smoothstep(0.0, 1.0, uAoRadius / max(abs(p.z - sceneZ), 1e-6));
    // The bias grows with distance: depth reconstruction and the derivative normals lose
    // precision there, and a flat far ground must not occlude itself.
    float bias = 0.02 * uAoRadius + 0.002 * -p.z;
    occluded += (sceneZ >= q.z + bias ? 1.0 : 0.0) * range;
  }
  float ao = clamp(1.0 - uAoStrength * occluded / float(uAoSamples), 0.0, 1.0);
  fragColor = vec4(ao, ao, ao, 1.0);
}
)";

// 4x4 box blur: exactly the period of the SSAO rotation pattern.
inline constexpr const char* kBlurFragment = R"(
in vec2 vUv;
uniform sampler2D uAo;
out vec4 fragColor;
void main() {
  vec2 texel = 1.0 / vec2(textureSize(uAo, 0));
  float sum = 0.0;
  for (int y = -2; y < 2; ++y)
    for (int x = -2; x < 2; ++x) sum += texture(uAo, vUv + vec2(x, y) * texel).r;
  float ao = sum / 16.0;
  fragColor = vec4(ao, ao, ao, 1.0);
}
)";

// Multiplies the blurred occlusion into the colour (blend DST_COLOR, ZERO).
inline constexpr const char* kCompositeFragment = R"(
in vec2 vUv;
uniform sampler2D uAo;
out vec4 fragColor;
void main() { fragColor = vec4(vec3(texture(uAo, vUv).r), 1.0); }
)";

// Edges: where the depth buffer is not affine in screen space. Reversed-Z depth is affine in
// 1 / z, so it is affine across any plane: its second difference is 0 on flat faces and large at
// silhouettes and creases. Blended over the colour with the edge strength as alpha.
inline constexpr const char* kOutlineFragment = R"(
in vec2 vUv;
uniform vec3 uOutlineColour;
uniform float uOutlineThickness;
uniform float uOutlineThreshold;
out vec4 fragColor;
void main() {
  vec2 texel = uOutlineThickness / vec2(textureSize(uDepth, 0));
  float c = texture(uDepth, vUv).r;
  float l = texture(uDepth, vUv - vec2(texel.x, 0.0)).r;
  float r = texture(uDepth, vUv + vec2(texel.x, 0.0)).r;
  float d = texture(uDepth, vUv - vec2(0.0, texel.y)).r;
  float u = texture(uDepth, vUv + vec2(0.0, texel.y)).r;
  float scale = max(max(max(c, l), max(r, d)), u);
  if (scale <= 0.0) discard;  // all sky
  float e = max(abs(l + r - 2.0 * c), abs(d + u - 2.0 * c)) / scale;
  float edge = smoothstep(uOutlineThreshold, 2.0 * uOutlineThreshold, e);
  if (edge <= 0.0) discard;
  fragColor = vec4(uOutlineColour, edge);
}
)";

}  // namespace renderer::shaders
