#version 450
// Deferred shading, light volume pass: the light material.flags.y (eq. 3.7 point, eq. 3.8 with
// the spot factor of eq. 3.12) at the G-buffer's surface, added to the accumulation target by
// blending (One, One). DEFERRED_SHADOWS (deferred-shadows): attenuated by the light's shadow
// map, rendered just before this light's volume (a light without a map gets a block that turns
// the lookup off).
#include "parity_math.glsl"
#include "scene_data.glsl"
#include "phong.glsl"
#include "../platforms/platform.glsl"
#include "gbuffer.glsl"
#include "deferred_light.glsl"
#include "gbuffer_read.glsl"
#ifdef DEFERRED_SHADOWS
#define SHADOW_DATA_BINDING 11
#define SHADOW_MAP_BINDING 12
#include "../effects/shadow.glsl"
#endif

layout(location = 0) out vec4 outLight;

void main() {
  Surface s = readSurface();
  vec3 color = localLightTerms(lights[material.flags.y], s.worldPos, s.N, s.C, s.diffuseColor, s.specularColor, s.power);
#ifdef DEFERRED_SHADOWS
  if (any(notEqual(color, vec3(0.0)))) color *= shadowFactor(s.worldPos, s.N);
#endif
  outLight = parityWriteRgba16Hdr(vec4(color, 0.0));
}
