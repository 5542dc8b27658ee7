// Lighting of a translucent surface, shared by the stencil-routed A-buffer and the depth-peeling
// reference so that both blend identical colours: ambient, directional and every local light
// (thesis eq. 3.5-3.12), opacity from the material (flags.w, float bits).
#ifndef PARITY_TRANSLUCENT_SHADING_GLSL
#define PARITY_TRANSLUCENT_SHADING_GLSL
#include "parity_math.glsl"
#include "scene_data.glsl"
#include "phong.glsl"

layout(set = 0, binding = 2) uniform sampler2D diffuseTexture;

layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;

vec4 shadeTranslucent() {
  vec3 N = normalize3(inNormal);
  vec3 C = normalize3(frame.cameraPos.xyz - inWorldPos);
  if (dot3(N, C) < 0.0) N = -N;  // lit from the side the camera sees
  vec3 diffuseColor = material.diffuse.rgb;
  if (material.flags.x != 0u) diffuseColor = diffuseColor * texture(diffuseTexture, inUv).rgb;
  vec3 specularColor = material.specular.rgb;
  float power = material.specular.w;
  vec3 color = diffuseColor * frame.ambient.rgb;
  color += phongTerms(N, frame.directionalDir.xyz, C, diffuseColor, specularColor, power) * frame.directionalColor.rgb;
  for (uint i = 0u; i < frame.counts.x; ++i) {
    Light light = lights[i];
    vec3 toSurface = inWorldPos - light.positionRadius.xyz;
    float d = length3(toSurface);
    float A = attenuation(d, light.colorK.w, light.positionRadius.w);
    if (A == 0.0) continue;
    vec3 L = toSurface / d;
    float F = 1.0;
    if (floatBitsToUint(light.directionType.w) == LIGHT_SPOT)
      F = spotFactor(light.directionType.xyz, L, light.cone.x, light.cone.y);
    color += phongTerms(N, L, C, diffuseColor, specularColor, power) * light.colorK.rgb * (A * F);
  }
  return vec4(color, uintBitsToFloat(material.flags.w));
}

#endif
