#version 450
// SSAO's G-buffer: view-space half-sphere normals through the platform's two-channel 16-bit path
// (as the deferred technique writes them) and the diffuse colour the ambient term is made of (as
// the deferred G-buffer stores it, so the apply pass recomputes eq. 3.5 exactly); depth comes
// from rasterisation.
#include "parity_math.glsl"
#include "scene_data.glsl"
#include "../platforms/platform.glsl"
#include "gbuffer.glsl"
#include "normal_mapping.glsl"

layout(set = 0, binding = 2) uniform sampler2D diffuseTexture;

layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;

layout(location = 0) out vec4 outNormal;
layout(location = 1) out vec4 outDiffuse;

void main() {
  vec3 diffuseColor = material.diffuse.rgb;
  if ((material.flags.x & MATERIAL_DIFFUSE_TEXTURE) != 0u) diffuseColor = diffuseColor * texture(diffuseTexture, inUv).rgb;
  outNormal = parityWriteRg16(encodeWorldNormal(shadingNormal(inNormal, inWorldPos, inUv)));
  outDiffuse = vec4(diffuseColor, 1.0);
}
