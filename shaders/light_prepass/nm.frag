#version 450
// Light pre-pass, first geometry pass: the n/m buffer, the normal (view space, half-sphere
// encoded, through the platform's two-channel 16-bit path) and the specular power m, which the
// light pass needs because specular light depends on it non-linearly (RTR blog).
#include "parity_math.glsl"
#include "scene_data.glsl"
#include "../platforms/platform.glsl"
#include "gbuffer.glsl"
#include "normal_mapping.glsl"

layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;

layout(location = 0) out vec4 outNormal;
layout(location = 1) out vec4 outPower;

void main() {
  outNormal = parityWriteRg16(encodeWorldNormal(shadingNormal(inNormal, inWorldPos, inUv)));
  outPower = vec4(encodeSpecularPower(material.specular.w), 0.0, 0.0, 1.0);
}
