#version 450
// Xbox 360 resolve of a k_16_16 surface into a k_16_16 texture (X3), per component:
//   1. unpack s * 32/32767, clamped below at PARITY_K16_UNPACK_MIN (-32; mainline Xenia -1),
//   2. with PARITY_RESOLVE_SAMPLES 2 (copy_sample_select k01) sum both samples, fold 0.5 in,
//   3. multiply by 2^PARITY_RESOLVE_EXP_BIAS,
//   4. pack: unsigned uint(saturate(f) * 65535 + 0.5); signed (PARITY_RESOLVE_SIGNED) per the
//      signed-resolve parameter PARITY_SIGNED_K16_RESOLVE (0 raw int16 kept when there is
//      nothing to convert, 1 EDRAM-style re-encode, 2 unsigned saturate as mainline Xenia).
// Input: the RG16_UINT view of the EDRAM surface; output: the RG16_UINT view of the texture.
#include "fixed16.glsl"
#ifndef PARITY_K16_UNPACK_MIN
#define PARITY_K16_UNPACK_MIN -32.0
#endif
#ifndef PARITY_RESOLVE_SAMPLES
#define PARITY_RESOLVE_SAMPLES 1
#endif
#ifndef PARITY_RESOLVE_EXP_BIAS
#define PARITY_RESOLVE_EXP_BIAS 0
#endif
#ifndef PARITY_RESOLVE_SIGNED
#define PARITY_RESOLVE_SIGNED 1
#endif
#ifndef PARITY_SIGNED_K16_RESOLVE
#define PARITY_SIGNED_K16_RESOLVE 0
#endif
layout(binding = 0) uniform usampler2D uEdram;
layout(location = 0) out uvec4 oWord;

uint packUnorm16(float f) {
  float s = clamp(isnan(f) ? 0.0 : f, 0.0, 1.0);
  precise float t = s * 65535.0 + 0.5;
  return uint(t);
}

uint resolveComponent(uint s0, uint s1) {
  float f0 = max(parityX360DecodeFixed16(s0), PARITY_K16_UNPACK_MIN);
#if PARITY_RESOLVE_SAMPLES == 2
  float f1 = max(parityX360DecodeFixed16(s1), PARITY_K16_UNPACK_MIN);
  precise float sum = f0 + f1;
  precise float value = sum * exp2(float(PARITY_RESOLVE_EXP_BIAS - 1));
#else
  precise float value = f0 * exp2(float(PARITY_RESOLVE_EXP_BIAS));
#endif
#if PARITY_RESOLVE_SIGNED && PARITY_SIGNED_K16_RESOLVE != 2
#if PARITY_SIGNED_K16_RESOLVE == 0 && PARITY_RESOLVE_SAMPLES == 1 && PARITY_RESOLVE_EXP_BIAS == 0
  return s0 & 0xFFFFu;
#else
  return uint(parityX360EncodeFixed16(value, 0)) & 0xFFFFu;
#endif
#else
  return packUnorm16(value);
#endif
}

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
#if PARITY_RESOLVE_SAMPLES == 2
  // Xenos 2x: samples are vertical, sample 0 on top (X1): sample s of pixel y is row 2y + s.
  uvec2 a = texelFetch(uEdram, ivec2(p.x, 2 * p.y), 0).xy;
  uvec2 b = texelFetch(uEdram, ivec2(p.x, 2 * p.y + 1), 0).xy;
#else
  uvec2 a = texelFetch(uEdram, p, 0).xy;
  uvec2 b = a;
#endif
  oWord = uvec4(resolveComponent(a.x, b.x), resolveComponent(a.y, b.y), 0u, 0u);
}
