#version 450
// Deferred shading, first lighting pass (full screen): ambient (eq. 3.5) and the directional
// light (eq. 3.6) from the G-buffer into the light accumulation target. DEFERRED_SHADOWS
// (deferred-shadows): the directional light attenuated by its shadow map, looked up at the
// surface the G-buffer rebuilds.
#include "parity_math.glsl"
#include "scene_data.glsl"
#include "phong.glsl"
#include "../platforms/platform.glsl"
#include "gbuffer.glsl"
#include "gbuffer_read.glsl"
#ifdef DEFERRED_SHADOWS
#define SHADOW_DATA_BINDING 11
#define SHADOW_MAP_BINDING 12
#include "../effects/shadow.glsl"
#endif

layout(location = 0) out vec4 outLight;

void main() {
  Surface s = readSurface();
  vec3 color = s.diffuseColor * frame.ambient.rgb;  // eq. 3.5
  vec3 directional = phongTerms(s.N, frame.directionalDir.xyz, s.C, s.diffuseColor, s.specularColor, s.power) *
                     frame.directionalColor.rgb;  // eq. 3.6
#ifdef DEFERRED_SHADOWS
  directional *= shadowFactor(s.worldPos, s.N);
#endif
  color += directional;
  outLight = parityWriteRgba16Hdr(vec4(color, 0.0));
}
