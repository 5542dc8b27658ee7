#version 450
// G-buffer of tiled deferred shading (thesis §2.4): normal, diffuse colour (with the texture
// applied) and specular power, specular colour, in the platform's Rgba16Hdr targets (float on
// the reference, so that there the shading pass repeats the forward shader's arithmetic on the
// same values); depth is the depth buffer's.
#include "parity_math.glsl"
#include "scene_data.glsl"
#include "normal_mapping.glsl"
#include "platform.glsl"

layout(set = 0, binding = 2) uniform sampler2D diffuseTexture;

layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;

layout(location = 0) out vec4 outNormal;
layout(location = 1) out vec4 outDiffusePower;
layout(location = 2) out vec4 outSpecular;

void main() {
  vec3 diffuseColor = material.diffuse.rgb;
  if ((material.flags.x & MATERIAL_DIFFUSE_TEXTURE) != 0u) diffuseColor = diffuseColor * texture(diffuseTexture, inUv).rgb;
  outNormal = parityWriteRgba16Hdr(vec4(shadingNormal(inNormal, inWorldPos, inUv), 0.0));
  outDiffusePower = parityWriteRgba16Hdr(vec4(diffuseColor, material.specular.w));
  outSpecular = parityWriteRgba16Hdr(vec4(material.specular.rgb, 0.0));
}
