#version 450
// Deferred shading, geometry pass (thesis §3.1.4): per visible pixel the G-buffer gets the normal
// (view space, half-sphere encoded, through the platform's two-channel 16-bit path), the diffuse
// colour (texture applied) and the specular colour and power. Depth comes from rasterisation.
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
layout(location = 2) out vec4 outSpecular;

void main() {
  vec3 N = shadingNormal(inNormal, inWorldPos, inUv);
  vec3 diffuseColor = material.diffuse.rgb;
  if ((material.flags.x & MATERIAL_DIFFUSE_TEXTURE) != 0u) diffuseColor = diffuseColor * texture(diffuseTexture, inUv).rgb;
  outNormal = parityWriteRg16(encodeWorldNormal(N));
  outDiffuse = vec4(diffuseColor, 1.0);
  outSpecular = vec4(material.specular.rgb, encodeSpecularPower(material.specular.w));
}
