#version 450
// Shadowed forward shading, first pass: ambient (thesis eq. 3.5) and the directional light
// (eq. 3.6) attenuated by its shadow map.
#include "parity_math.glsl"
#include "scene_data.glsl"
#include "phong.glsl"
#include "shadow.glsl"
#include "normal_mapping.glsl"

layout(set = 0, binding = 2) uniform sampler2D diffuseTexture;

layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;

layout(location = 0) out vec4 outColor;

void main() {
  vec3 N = shadingNormal(inNormal, inWorldPos, inUv);
  vec3 C = normalize3(frame.cameraPos.xyz - inWorldPos);
  vec3 diffuseColor = material.diffuse.rgb;
  if (material.flags.x != 0u) diffuseColor = diffuseColor * texture(diffuseTexture, inUv).rgb;
  vec3 color = diffuseColor * frame.ambient.rgb;
  color += phongTerms(N, frame.directionalDir.xyz, C, diffuseColor, material.specular.rgb, material.specular.w) *
           frame.directionalColor.rgb * shadowFactor(inWorldPos, N);
  outColor = vec4(color, 1.0);
}
