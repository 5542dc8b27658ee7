#version 450
// Deferred shading, last pass: the accumulated light becomes the final colour (alpha 1, as the
// forward shaders write; pixels no geometry covered keep the accumulation's clear, black).
#include "../platforms/platform.glsl"

layout(set = 0, binding = 8) uniform sampler2D lightAccumulation;

layout(location = 0) out vec4 outColor;

void main() {
  vec4 light = parityReadRgba16Hdr(texelFetch(lightAccumulation, ivec2(gl_FragCoord.xy), 0));
  outColor = vec4(light.rgb, 1.0);
}
