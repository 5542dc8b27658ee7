#version 450
// The material's diffuse colour with its texture applied, as deferred shading's geometry pass
// stores it (shaders/deferred/gbuffer.frag): an RGBA8 output needs no platform write function.
#include "parity_math.glsl"
#include "scene_data.glsl"

layout(set = 0, binding = 2) uniform sampler2D diffuseTexture;

layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;

layout(location = 0) out vec4 outColor;

void main() {
  vec3 diffuseColor = material.diffuse.rgb;
  if ((material.flags.x & MATERIAL_DIFFUSE_TEXTURE) != 0u) diffuseColor = diffuseColor * texture(diffuseTexture, inUv).rgb;
  outColor = vec4(diffuseColor, 1.0);
}
