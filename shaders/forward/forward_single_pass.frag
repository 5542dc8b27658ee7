#version 450
// Single-pass forward shading: ambient (eq. 3.5), one directional light (eq. 3.6) and every
// point/spot light of the scene (eq. 3.7, 3.8) summed in one fragment shader.
#include "parity_math.glsl"
#include "scene_data.glsl"
#include "phong.glsl"
#include "normal_mapping.glsl"
#ifdef FORWARD_HDR_TARGET
// Into the platform's Rgba16Hdr target: the hdr light accumulation, the transparency techniques' opaque image.
#include "platform.glsl"
#endif

layout(set = 0, binding = 2) uniform sampler2D diffuseTexture;

layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;

layout(location = 0) out vec4 outColor;

void main() {
  vec3 N = shadingNormal(inNormal, inWorldPos, inUv);
  vec3 C = normalize3(frame.cameraPos.xyz - inWorldPos);
  vec3 diffuseColor = material.diffuse.rgb;
  if ((material.flags.x & MATERIAL_DIFFUSE_TEXTURE) != 0u) diffuseColor = diffuseColor * texture(diffuseTexture, inUv).rgb;
  vec3 specularColor = material.specular.rgb;
  float power = material.specular.w;

  vec3 color = diffuseColor * frame.ambient.rgb;  // eq. 3.5
  color += phongTerms(N, frame.directionalDir.xyz, C, diffuseColor, specularColor, power) *
           frame.directionalColor.rgb;  // eq. 3.6

  for (uint i = 0u; i < frame.counts.x; ++i) {
    Light light = lights[i];
    vec3 toSurface = inWorldPos - light.positionRadius.xyz;
    float d = length3(toSurface);
    float A = attenuation(d, light.colorK.w, light.positionRadius.w);
    if (A == 0.0) continue;
    vec3 L = toSurface / d;
    float F = 1.0;
    if (floatBitsToUint(light.directionType.w) == LIGHT_SPOT)
      F = spotFactor(light.directionType.xyz, L, light.cone.x, light.cone.y);  // eq. 3.12
    color += phongTerms(N, L, C, diffuseColor, specularColor, power) * light.colorK.rgb * (A * F);
  }
#ifdef FORWARD_HDR_TARGET
  outColor = parityWriteRgba16Hdr(vec4(color, 1.0));
#else
  outColor = vec4(color, 1.0);
#endif
}
