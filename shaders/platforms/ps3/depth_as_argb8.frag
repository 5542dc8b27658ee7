#version 450
// PS3 (P4): the D24S8 surface seen as A8R8G8B8, i.e. its memory bytes [D_hi, D_mid, D_lo, S]
// (big-endian word (D24 << 8) | stencil), stored in the host texel order of every emulated
// A8R8G8B8 surface (argb8_host.glsl). RPCS3 emulates this bitcast in a shader as well.
#include "../common/depth24.glsl"
#include "argb8_host.glsl"
layout(binding = 0) uniform sampler2D uDepth;
layout(binding = 1) uniform usampler2D uStencil;
layout(location = 0) out vec4 oArgbBytes;
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  uint d24 = parityDepthToD24(texelFetch(uDepth, p, 0).x);
  uint s = texelFetch(uStencil, p, 0).x & 255u;
  oArgbBytes = parityPs3HostTexelOfArgb(vec4(uvec4(d24 >> 16, (d24 >> 8) & 255u, d24 & 255u, s)) / 255.0);
}
