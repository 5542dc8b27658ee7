// Xbox 360 (Xenos). Rg16Unorm is a k_16_16 EDRAM surface (signed fixed point -32...32, X2)
// brought out by a resolve (X3). The DSF path (A, B or C) is the platform's choice:
//   PARITY_DSF_SCALE / PARITY_DSF_OFFSET   shader output c = v * scale + offset
//   PARITY_COLOR_EXP_BIAS                  RB_COLOR_INFO.color_exp_bias
//   PARITY_DSF_SAMPLE_ADD / _MUL           the reading shader's v' = (t + add) * mul
// Host storage of the EDRAM surface: RG16_SNORM whose bits equal the guest int16 (the encode is
// done exactly here, then s / 32767 converts back to s). The resolved texture is RG16_UNORM
// (unsigned fetch, word / 65535) or RG16_SNORM (signed fetch, max(s / 32767, -1)).
// Depth: D24S8 resolved without conversion; the host keeps the word (D24 << 8) | S as R32_UINT.
#include "fixed16.glsl"
#ifndef PARITY_DSF_SCALE
#define PARITY_DSF_SCALE 64.0
#define PARITY_DSF_OFFSET -32.0
#define PARITY_COLOR_EXP_BIAS 0
#define PARITY_DSF_SAMPLE_ADD 1.0
#define PARITY_DSF_SAMPLE_MUL 0.5
#endif

vec4 parityWriteRg16(vec2 v) {
  precise vec2 c = v * PARITY_DSF_SCALE + PARITY_DSF_OFFSET;
  ivec2 s = ivec2(parityX360EncodeFixed16(c.x, PARITY_COLOR_EXP_BIAS), parityX360EncodeFixed16(c.y, PARITY_COLOR_EXP_BIAS));
  return vec4(vec2(s) / 32767.0, 0.0, 1.0);
}
#define PARITY_RG16_SAMPLER sampler2D
vec2 parityReadRg16(vec4 texel) {
  precise vec2 v = (texel.xy + PARITY_DSF_SAMPLE_ADD) * PARITY_DSF_SAMPLE_MUL;
  return v;
}
#define PARITY_DEPTH_SAMPLER usampler2D
#define PARITY_DEPTH_TEXEL uvec4
float parityReadDepth(uvec4 texel) { return float(texel.x >> 8) / 16777215.0; }
