#version 450
// Shadowed forward shading, one pass per local light (material.flags.y), added to the target:
// eq. 3.7/3.8 attenuated by the light's shadow map (reused from light to light).
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
  Light light = lights[material.flags.y];
  vec3 toSurface = inWorldPos - light.positionRadius.xyz;
  float d = length3(toSurface);
  float A = attenuation(d, light.colorK.w, light.positionRadius.w);
  vec3 color = vec3(0.0);
  if (A > 0.0) {
    vec3 L = toSurface / d;
    float F = 1.0;
    if (floatBitsToUint(light.directionType.w) == LIGHT_SPOT)
      F = spotFactor(light.directionType.xyz, L, light.cone.x, light.cone.y);
    if (F > 0.0)
      color = phongTerms(N, L, C, diffuseColor, material.specular.rgb, material.specular.w) * light.colorK.rgb *
              (A * F * shadowFactor(inWorldPos, N));
  }
  outColor = vec4(color, 0.0);
}
