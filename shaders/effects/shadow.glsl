// Shadow-map lookup with percentage-closer filtering: the four nearest texels compared with the
// receiver's depth and the results blended, as a comparison sampler with linear filtering does,
// but on depth read the way the platform reads depth (R24X8 on dx10, the BARG view of A8R8G8B8 on
// ps3, the resolved D24S8 word on x360; platforms/platform_layer.h), since a console's shadow map
// is a depth surface the platform must make readable. One block serves every light type (thesis §3.1):
// a directional or spot light uses faces[0]; a point light's cube is six 90-degree faces stored
// as six array layers, the face chosen by the major axis of the light-to-surface vector, so the
// same matrices render and look up the faces on every API.
#ifndef PARITY_SHADOW_GLSL
#define PARITY_SHADOW_GLSL
#include "parity_math.glsl"
#include "platform.glsl"

// Bindings 3 and 4 unless the including shader moves them (the deferred passes use 3 and 4 for
// the light volume transforms and the G-buffer depth): techniques/effects/shadow_maps.h.
#ifndef SHADOW_DATA_BINDING
#define SHADOW_DATA_BINDING 3
#endif
#ifndef SHADOW_MAP_BINDING
#define SHADOW_MAP_BINDING 4
#endif

layout(set = 0, binding = SHADOW_DATA_BINDING, std140) uniform ShadowData {
  mat4 faces[6];      // world -> shadow clip space, per face
  vec4 params;        // x: faces (0 no shadow, 1, or 6 for a cube), y: world size of a texel at
                      // clip w = 1 (perspective) or of any texel (orthographic, w = 1)
  vec4 lightPos;      // xyz: point light position (face selection); w: 1 for point lights
  vec4 toLight;       // xyz: unit direction to a directional light (w = 1), else w = 0
} shadow;

layout(set = 0, binding = SHADOW_MAP_BINDING) uniform PARITY_DEPTH_ARRAY_SAMPLER shadowMap;

// 1 where the receiver at `depth` is lit by texel `texel` of layer `layer` (LESS_EQUAL against
// the stored depth, clamped to the edge as the sampler would).
float shadowTexel(ivec2 texel, int layer, float depth) {
  ivec2 last = textureSize(shadowMap, 0).xy - 1;
  return depth <= parityReadDepth(texelFetch(shadowMap, ivec3(clamp(texel, ivec2(0), last), layer), 0)) ? 1.0 : 0.0;
}

uint shadowFace(vec3 fromLight) {
  vec3 a = abs(fromLight);
  if (a.x >= a.y && a.x >= a.z) return fromLight.x >= 0.0 ? 0u : 1u;
  if (a.y >= a.z) return fromLight.y >= 0.0 ? 2u : 3u;
  return fromLight.z >= 0.0 ? 4u : 5u;
}

// 1: lit, 0: in shadow. The depth bias is a world-space offset of the receiver along its normal
// and towards the light, in units of the shadow texel's footprint at the receiver, so it scales
// with the map's resolution and works for orthographic and perspective maps alike.
float shadowFactor(vec3 worldPos, vec3 N) {
  uint faceCount = uint(shadow.params.x + 0.5);
  if (faceCount == 0u) return 1.0;
  vec3 fromLight = worldPos - shadow.lightPos.xyz;
  uint face = faceCount == 6u ? shadowFace(fromLight) : 0u;
  vec3 toLight = shadow.toLight.w > 0.5 ? shadow.toLight.xyz : -normalize3(fromLight);
  vec4 clip = mul(shadow.faces[face], vec4(worldPos, 1.0));
  float texelWorld = shadow.params.y * clip.w;
  vec3 biased = worldPos + N * (1.5 * texelWorld) + toLight * texelWorld;
  clip = mul(shadow.faces[face], vec4(biased, 1.0));
  if (clip.w <= 0.0) return 1.0;
  vec3 ndc = clip.xyz / clip.w;
  if (any(greaterThan(abs(ndc.xy), vec2(1.0))) || ndc.z > 1.0 || ndc.z < 0.0) return 1.0;
  vec2 uv = ndc.xy * 0.5 + 0.5;  // NDC y = -1 is row 0, v = 0 (rhi.h conventions)
  vec2 p = uv * vec2(textureSize(shadowMap, 0).xy) - 0.5;
  ivec2 i = ivec2(floor(p));
  vec2 f = p - floor(p);
  int layer = int(face);
  float top = mix(shadowTexel(i, layer, ndc.z), shadowTexel(i + ivec2(1, 0), layer, ndc.z), f.x);
  float bottom = mix(shadowTexel(i + ivec2(0, 1), layer, ndc.z), shadowTexel(i + ivec2(1, 1), layer, ndc.z), f.x);
  return mix(top, bottom, f.y);
}

#endif
