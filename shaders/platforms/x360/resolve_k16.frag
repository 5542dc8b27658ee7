#version 450
// Xbox 360 resolve of a k_16_16 surface into a k_16_16 texture (X3), per component:
//   1. unpack s * 32/32767, clamped below at PARITY_K16_UNPACK_MIN (-32; mainline Xenia -1),
//   2. with PARITY_RESOLVE_SAMPLES 2 (copy_sample_select k01) or 4 (k0123) sum the samples in
//      guest order, ((f0 + f1) + f2) + f3 as the model does in fp32, and fold 0.5 per doubling in,
//   3. multiply by 2^PARITY_RESOLVE_EXP_BIAS,
//   4. pack: unsigned uint(saturate(f) * 65535 + 0.5); signed (PARITY_RESOLVE_SIGNED) per the
//      signed-resolve parameter PARITY_SIGNED_K16_RESOLVE (0 raw int16 kept when there is
//      nothing to convert, 1 EDRAM-style re-encode, 2 unsigned saturate as mainline Xenia).
// Input: the RG16_UINT view of the EDRAM surface (4 samples: of the MSAA attachment, guest
// sample s read from host sample PARITY_HOST_SAMPLE_s); output: the RG16_UINT view of the texture.
// An unsigned destination counts the texels it clamps (PARITY_COUNT): lane 0 a negative value
// (W_RESOLVE_SIGN_LOSS), lane 1 a value above 1 (W_RESOLVE_RANGE_CLAMP).
#include "fixed16.glsl"
#include "texel_counts.glsl"
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
#ifndef PARITY_HOST_SAMPLE_0
#define PARITY_HOST_SAMPLE_0 0
#define PARITY_HOST_SAMPLE_1 1
#define PARITY_HOST_SAMPLE_2 2
#define PARITY_HOST_SAMPLE_3 3
#endif
#if PARITY_RESOLVE_SAMPLES == 4
layout(binding = 0) uniform usampler2DMS uEdram;
#else
layout(binding = 0) uniform usampler2D uEdram;
#endif
layout(location = 0) out uvec4 oWord;

bool signLost = false, rangeClamped = false;

uint packUnorm16(float f) {
  signLost = signLost || f < 0.0;
  rangeClamped = rangeClamped || f > 1.0;
  float s = clamp(isnan(f) ? 0.0 : f, 0.0, 1.0);
  precise float t = s * 65535.0 + 0.5;
  return uint(t);
}

float unpack(uint s) { return max(parityX360DecodeFixed16(s), PARITY_K16_UNPACK_MIN); }

// `s` holds the selected samples in guest order (unused lanes repeat sample 0).
uint resolveComponent(uvec4 s) {
#if PARITY_RESOLVE_SAMPLES == 4
  precise float sum = ((unpack(s.x) + unpack(s.y)) + unpack(s.z)) + unpack(s.w);
  precise float value = ldexp(sum, PARITY_RESOLVE_EXP_BIAS - 2);
#elif PARITY_RESOLVE_SAMPLES == 2
  precise float sum = unpack(s.x) + unpack(s.y);
  precise float value = ldexp(sum, PARITY_RESOLVE_EXP_BIAS - 1);
#else
  precise float value = ldexp(unpack(s.x), PARITY_RESOLVE_EXP_BIAS);
#endif
#if PARITY_RESOLVE_SIGNED && PARITY_SIGNED_K16_RESOLVE != 2
#if PARITY_SIGNED_K16_RESOLVE == 0 && PARITY_RESOLVE_SAMPLES == 1 && PARITY_RESOLVE_EXP_BIAS == 0
  return s.x & 0xFFFFu;
#else
  return uint(parityX360EncodeFixed16(value, 0)) & 0xFFFFu;
#endif
#else
  return packUnorm16(value);
#endif
}

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
#if PARITY_RESOLVE_SAMPLES == 4
  uvec2 a = texelFetch(uEdram, p, PARITY_HOST_SAMPLE_0).xy;
  uvec2 b = texelFetch(uEdram, p, PARITY_HOST_SAMPLE_1).xy;
  uvec2 c = texelFetch(uEdram, p, PARITY_HOST_SAMPLE_2).xy;
  uvec2 d = texelFetch(uEdram, p, PARITY_HOST_SAMPLE_3).xy;
#elif PARITY_RESOLVE_SAMPLES == 2
  // Xenos 2x: samples are vertical, sample 0 on top (X1): sample s of pixel y is row 2y + s.
  uvec2 a = texelFetch(uEdram, ivec2(p.x, 2 * p.y), 0).xy;
  uvec2 b = texelFetch(uEdram, ivec2(p.x, 2 * p.y + 1), 0).xy;
  uvec2 c = a, d = a;
#else
  uvec2 a = texelFetch(uEdram, p, 0).xy;
  uvec2 b = a, c = a, d = a;
#endif
  oWord = uvec4(resolveComponent(uvec4(a.x, b.x, c.x, d.x)), resolveComponent(uvec4(a.y, b.y, c.y, d.y)), 0u, 0u);
  if (signLost) parityCount(0u);
  if (rangeClamped) parityCount(1u);
}
