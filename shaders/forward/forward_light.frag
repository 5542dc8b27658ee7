#version 450
// Multi-pass forward shading, one pass per light: the contribution of light material.flags.y
// (eq. 3.7 for a point light, eq. 3.8 with the spot factor of eq. 3.12 for a spot), added to the
// colour target by blending (One, One). Alpha 0, so the first pass's alpha stays.
#include "parity_math.glsl"
#include "scene_data.glsl"
#include "phong.glsl"
#include "normal_mapping.glsl"

layout(set = 0, binding = 2) uniform sampler2D diffuseTexture;

layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;

layout(location = 0) out vec4 outColor;

void main() {
  vec3 N = shadingNormal(inNormal, inWorldPos, inUv);  // before the discard: it takes derivatives
  Light light = lights[material.flags.y];
  vec3 toSurface = inWorldPos - light.positionRadius.xyz;
  float d = length3(toSurface);
  float A = attenuation(d, light.colorK.w, light.positionRadius.w);
  if (A == 0.0) discard;  // beyond the radius: nothing to add

  vec3 C = normalize3(frame.cameraPos.xyz - inWorldPos);
  vec3 diffuseColor = material.diffuse.rgb;
  if ((material.flags.x & MATERIAL_DIFFUSE_TEXTURE) != 0u) diffuseColor = diffuseColor * texture(diffuseTexture, inUv).rgb;
  vec3 specularColor = material.specular.rgb;
  float power = material.specular.w;

  vec3 L = toSurface / d;
  float F = 1.0;
  if (floatBitsToUint(light.directionType.w) == LIGHT_SPOT)
    F = spotFactor(light.directionType.xyz, L, light.cone.x, light.cone.y);  // eq. 3.12
  outColor = vec4(phongTerms(N, L, C, diffuseColor, specularColor, power) * light.colorK.rgb * (A * F), 0.0);
}
