#version 450
// Xbox 360 depth resolve (X3): a raw copy, no conversion, averaging or exponent bias. The host
// keeps the resolved D24S8 texel as the word (D24 << 8) | stencil in an R32_UINT texture.
#include "../common/depth24.glsl"
layout(binding = 0) uniform sampler2D uDepth;
layout(binding = 1) uniform usampler2D uStencil;
layout(location = 0) out uint oWord;
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  uint d24 = parityDepthToD24(texelFetch(uDepth, p, 0).x);
  oWord = (d24 << 8) | (texelFetch(uStencil, p, 0).x & 255u);
}
