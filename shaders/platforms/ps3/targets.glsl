// PS3 (RSX). Rg16Unorm: there is no 2x16-bit colour surface (P1), so two 16-bit values are
// packed into an A8R8G8B8 surface (packed16x2, P2) and read through a Y16_X16 view.
//   Write: X16 = round(x * 65535), A = hi(X16), R = lo(X16), G = hi(Y16), B = lo(Y16); the ROP
//   stores k/255 as k exactly.
//   Host storage (argb8_host.glsl): RGBA8 whose 16-bit words are little-endian (bytes lo, hi),
//   so the RG16_UNORM view of it is the Y16_X16 view: .r = X16 / 65535, .g = Y16 / 65535 (the
//   typeless 16-bit swap RPCS3 does on a copy is folded into the storage; consoleBytes()
//   restores [A, R, G, B]).
// Depth: the D24S8 surface is read as A8R8G8B8 with the BARG remap and decoded as
// texDepth2D_precise does (P4); its bitcast texel uses the same host order as colour.
#include "argb8_host.glsl"
#ifndef PARITY_PS3_DEPTH_REMAP
#define PARITY_PS3_DEPTH_REMAP 0xAA93u
#endif
#ifndef PARITY_PS3_DEPTH_PRECISE_DP3
#define PARITY_PS3_DEPTH_PRECISE_DP3 0
#endif

uvec2 parityPs3Unorm16(vec2 v) {
  precise vec2 t = clamp(v, 0.0, 1.0) * 65535.0 + 0.5;
  return uvec2(floor(t));
}
// Exact path: the two little-endian 16-bit words through an RG16_UINT view of the RGBA8
// storage, i.e. the bytes the ROP stores from the byte outputs below, with no float -> unorm8
// conversion involved.
#define PARITY_RG16_BITS_TYPE uvec4
uvec4 parityWriteRg16Bits(vec2 v) { return uvec4(parityPs3Unorm16(v), 0u, 0u); }
// Blendable path (the P3 traps blend these bytes): each byte k is written as (k + 0.25) / 255 so
// that any float -> unorm8 conversion within 0.6 ULP stores k, and a blend of such bytes
// rounds as the model's round(c * 255) does instead of landing on an exact .5 tie.
vec4 parityWriteRg16(vec2 v) {
  uvec2 q = parityPs3Unorm16(v);
  vec4 argb = vec4(uvec4(q.x >> 8, q.x & 255u, q.y >> 8, q.y & 255u));
  return (parityPs3HostTexelOfArgb(argb) + 0.25) / 255.0;
}
#define PARITY_RG16_SAMPLER sampler2D
vec2 parityReadRg16(vec4 texel) { return texel.xy; }

// Texture remap word (P2/P4): channels indexed [A, R, G, B]; bits 0-7 select the input of each
// output, bits 8-15 the output control (0 zero, 1 one, 2 remap). Returns (r, g, b, a).
vec4 parityPs3Remap(uint remap, vec4 argb) {
  vec4 outArgb;
  for (int o = 0; o < 4; ++o) {
    uint control = (remap >> (8 + 2 * o)) & 3u;
    uint from = (remap >> (2 * o)) & 3u;
    outArgb[o] = control == 0u ? 0.0 : control == 1u ? 1.0 : argb[from];
  }
  return vec4(outArgb[1], outArgb[2], outArgb[3], outArgb[0]);
}

#define PARITY_DEPTH_SAMPLER sampler2D
#define PARITY_DEPTH_ARRAY_SAMPLER sampler2DArray  // a layered depth target (shadow cube faces)
#define PARITY_DEPTH_TEXEL vec4
// texel = the host texel of the A8R8G8B8 view (argb8_host.glsl order).
float parityReadDepth(vec4 texel) {
  vec4 c = parityPs3Remap(PARITY_PS3_DEPTH_REMAP, parityPs3ArgbOfHostTexel(texel));
  precise vec3 t = c.rgb * 255.0 + 0.5;
  vec3 bytes = floor(t);
#if PARITY_PS3_DEPTH_PRECISE_DP3
  // _depth_factor_precise = (0x3b800001, 0x37800001, 0x33800001), fp32 DP3 in order.
  precise float d = bytes.x * uintBitsToFloat(0x3b800001u) + bytes.y * uintBitsToFloat(0x37800001u);
  precise float e = d + bytes.z * uintBitsToFloat(0x33800001u);
  return e;
#else
  uint d24 = (uint(bytes.x) << 16) | (uint(bytes.y) << 8) | uint(bytes.z);
  return float(d24) / 16777215.0;
#endif
}

// Rgba16Hdr (light accumulation): colour output for the attachment, and the logical value of a
// texel of its read texture. Additive blending must stay correct on the stored values, so a
// platform may only scale linearly here.
vec4 parityWriteRgba16Hdr(vec4 v) { return v; }
vec4 parityReadRgba16Hdr(vec4 texel) { return texel; }
