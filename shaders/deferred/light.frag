#version 450
// Deferred shading, light volume pass: the light material.flags.y (eq. 3.7 point, eq. 3.8 with
// the spot factor of eq. 3.12) at the G-buffer's surface, added to the accumulation target by
// blending (One, One).
#include "parity_math.glsl"
#include "scene_data.glsl"
#include "phong.glsl"
#include "../platforms/platform.glsl"
#include "gbuffer.glsl"
#include "deferred_light.glsl"
#include "gbuffer_read.glsl"

layout(location = 0) out vec4 outLight;

void main() {
  Surface s = readSurface();
  vec3 color = localLightTerms(lights[material.flags.y], s.worldPos, s.N, s.C, s.diffuseColor, s.specularColor, s.power);
  outLight = parityWriteRgba16Hdr(vec4(color, 0.0));
}
