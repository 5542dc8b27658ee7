#version 450
// SSAO's G-buffer: view-space half-sphere normals through the platform's two-channel 16-bit path
// (as the deferred technique writes them); depth comes from rasterisation.
#include "parity_math.glsl"
#include "scene_data.glsl"
#include "../platforms/platform.glsl"
#include "gbuffer.glsl"

layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;

layout(location = 0) out vec4 outNormal;

void main() { outNormal = parityWriteRg16(encodeWorldNormal(normalize3(inNormal))); }
