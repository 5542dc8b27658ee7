#version 450
// A-buffer store (Ferko 2012 §4.1): each translucent fragment lands in the one sample whose
// stencil equals 2 (the stencil test routes it; every covered sample's stencil then decrements),
// colour and opacity in target 0 (a Rgba16Hdr target), its depth in target 1 for the sort.
#include "translucent_shading.glsl"
#include "platform.glsl"

layout(set = 0, binding = 5) uniform PARITY_DEPTH_SAMPLER opaqueDepth;  // read as the platform reads depth

layout(location = 0) out vec4 outColor;
layout(location = 1) out vec4 outDepth;

void main() {
  // Hidden fragments are discarded before the stencil op, so they take no sample; the same test
  // as the depth-peeling reference's.
  if (gl_FragCoord.z >= parityReadDepth(texelFetch(opaqueDepth, ivec2(gl_FragCoord.xy), 0))) discard;
  outColor = parityWriteRgba16Hdr(shadeTranslucent());
  outDepth = vec4(gl_FragCoord.z, 0.0, 0.0, 0.0);
}
