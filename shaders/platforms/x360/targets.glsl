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

ivec2 parityX360EncodeDsf(vec2 v) {
  precise vec2 c = v * PARITY_DSF_SCALE + PARITY_DSF_OFFSET;
  return ivec2(parityX360EncodeFixed16(c.x, PARITY_COLOR_EXP_BIAS), parityX360EncodeFixed16(c.y, PARITY_COLOR_EXP_BIAS));
}
// Exact path: the int16 bits through the RG16_UINT view of the RG16_SNORM storage (Xenia's
// UINT transfer view); no float -> snorm conversion decides them.
#define PARITY_RG16_BITS_TYPE uvec4
uvec4 parityWriteRg16Bits(vec2 v) { return uvec4(uvec2(parityX360EncodeDsf(v)) & 0xFFFFu, 0u, 0u); }
// Blendable path into the RG16_SNORM attachment: (s +- 0.25) / 32767, a quarter step away from
// zero, so nearest, nearest-even and truncating (toward zero) conversions all store s; s/32767
// itself can land just below s after the driver's multiply and truncate to s - 1.
vec4 parityWriteRg16(vec2 v) {
  vec2 s = vec2(parityX360EncodeDsf(v));
  return vec4((s + sign(s) * 0.25) / 32767.0, 0.0, 1.0);
}
#define PARITY_RG16_SAMPLER sampler2D
vec2 parityReadRg16(vec4 texel) {
  precise vec2 v = (texel.xy + PARITY_DSF_SAMPLE_ADD) * PARITY_DSF_SAMPLE_MUL;
  return v;
}
#define PARITY_DEPTH_SAMPLER usampler2D
#define PARITY_DEPTH_ARRAY_SAMPLER usampler2DArray  // a layered depth target (shadow cube faces)
#define PARITY_DEPTH_TEXEL uvec4
float parityReadDepth(uvec4 texel) { return float(texel.x >> 8) / 16777215.0; }

// A multisampled target read per sample: the layers of its per-sample resolves (copy_sample_select).
#define PARITY_SAMPLES_SAMPLER sampler2DArray
#define parityFetchSample(t, p, s) texelFetch(t, ivec3(p, s), 0)

// Rgba16Hdr (light accumulation) is k_16_16_16_16: signed fixed point -32...32 (X2), colour
// exponent bias 0, steps of 32/32767 = 9.766e-4 (15 bits over [0, 32)).
// Write: the shader rounds v to its fixed-point step s as the model does (round half away from
// zero) and stores s * 2^-15 in the RGBA32F host surface: exact in fp32, and the blender's sum of
// two such values is exact too, so ADD blending of (s1, s2) stores s1 + s2 just as the EDRAM
// blender re-encoding (decode(dst) + src) does for an integer dst. Linear scaling only:
// multiplicative blend factors (DEST_COLOR) would see values / 32768 * 32767 / 32
// (W_FIXED16_MULT_BLEND). The clamp to +-32 and NaN -> 0 of every write and blend is the store
// pass GpuTargets records after each pass that draws into the surface
// (GpuTargets::clampFixedPoint), which counts the samples it changes (W_FIXED16_RANGE_CLAMP,
// W_FIXED16_NAN): so the shader writes beyond the range and NaN as they are.
// Read: the resolve keeps the raw int16 (signed k_16_16_16_16, RGBA32F float(s) on the host);
// the signed fetch with exp_adjust +5 returns max(s / 32767, -1) * 32.
#if defined(PARITY_X360_HDR_7E3)
// Rgba16Hdr as k_2_10_10_10_FLOAT (x360.hdr_format): the shader writes floats; the render
// backend stores 7e3 (GpuTargets::quantiseFloat7e3 after each pass that writes, blends summed in
// fp32 first); the resolve copies the 7e3 values, which the fetch returns as they are.
#include "float7e3.glsl"
vec4 parityWriteRgba16Hdr(vec4 v) { return v; }
vec4 parityReadRgba16Hdr(vec4 texel) { return texel; }
#else
vec4 parityWriteRgba16Hdr(vec4 v) {
  precise vec4 t = trunc(v * 1023.96875 + mix(vec4(0.5), vec4(-0.5), lessThan(v, vec4(0.0))));
  return t * (1.0 / 32768.0);
}
vec4 parityReadRgba16Hdr(vec4 texel) {
  precise vec4 t = max(texel / 32767.0, vec4(-1.0));
  return t * 32.0;
}
#endif
