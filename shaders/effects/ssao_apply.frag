#version 450
// Ambient occlusion applied to the ambient term only (Ferko 2012: SSAO attenuates the ambient
// light; direct light has its own visibility). The lit image is the deferred technique's
// unclamped HDR result, ambient (eq. 3.5) + directional + local lights; the ambient share it
// contains is diffuse x ambient, so the occluded image is lit - (1 - AO) x diffuse x ambient.
// The occlusion is upsampled bilinearly from its reduced resolution.
#include "scene_data.glsl"

layout(set = 0, binding = 6) uniform sampler2D occlusion;
layout(set = 0, binding = 7) uniform sampler2D litImage;
layout(set = 0, binding = 8) uniform sampler2D diffuseColor;

layout(location = 0) out vec4 outColor;

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec2 uv = gl_FragCoord.xy / vec2(textureSize(litImage, 0));
  float ao = texture(occlusion, uv).r;
  vec3 lit = texelFetch(litImage, p, 0).rgb;
  vec3 ambientLight = texelFetch(diffuseColor, p, 0).rgb * frame.ambient.rgb;  // eq. 3.5, as the lit pass adds it
  // max: lit went through the accumulation's 16-bit rounding, the ambient share did not.
  outColor = vec4(max(lit - (1.0 - ao) * ambientLight, vec3(0.0)), 1.0);
}
