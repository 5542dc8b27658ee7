#version 450
// Light pre-pass, second geometry pass: the materials applied to the accumulated light,
// colour = diffuse * (ambient + diffuse light) + specular colour * specular light (RTR blog's
// reconstruction phase; ambient as eq. 3.5).
#include "parity_math.glsl"
#include "scene_data.glsl"
#include "../platforms/platform.glsl"
#define PARITY_LIGHT_ACCUMULATION_INPUTS
#include "light_prepass.glsl"

layout(set = 0, binding = 2) uniform sampler2D diffuseTexture;

layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;

layout(location = 0) out vec4 outColor;

void main() {
  vec3 diffuseColor = material.diffuse.rgb;
  if ((material.flags.x & MATERIAL_DIFFUSE_TEXTURE) != 0u) diffuseColor = diffuseColor * texture(diffuseTexture, inUv).rgb;
  vec3 diffuseLight, specularLight;
  readLight(diffuseLight, specularLight);
  vec3 color = diffuseColor * frame.ambient.rgb;  // eq. 3.5
  color += diffuseColor * diffuseLight + material.specular.rgb * specularLight;
  outColor = vec4(color, 1.0);
}
