#version 450
// Xbox 360 resolve of a k_16_16_16_16 surface (the Rgba16Hdr light buffer) into a signed
// k_16_16_16_16 texture with no exponent bias (X3). EDRAM host storage: RGBA32F s * 2^-15,
// possibly the sum of several blended writes, so the encode's clamp to [0x8001, 0x7FFF] is
// applied first. Output: RGBA32F float(s), the host stand-in for the 16-bit signed texture.
//  * One sample: the raw int16 is kept (the signed-resolve parameter's default).
//  * PARITY_RESOLVE_SAMPLES 4 (copy_sample_select k0123): each sample unpacked to s * 32/32767,
//    clamped below at PARITY_K16_UNPACK_MIN, summed in guest order ((f0 + f1) + f2) + f3, times
//    2^-2, then re-encoded EDRAM-style (x 32767/32, clamp +-32, half away from zero) as the
//    model's signed destination does for averaged data. Guest sample s is host sample
//    PARITY_HOST_SAMPLE_s of the MSAA attachment.
//  * PARITY_RESOLVE_SAMPLE h (copy_sample_select of one sample, host sample h): its raw int16.
#include "fixed16.glsl"
#ifndef PARITY_RESOLVE_SAMPLES
#define PARITY_RESOLVE_SAMPLES 1
#endif
#ifndef PARITY_K16_UNPACK_MIN
#define PARITY_K16_UNPACK_MIN -32.0
#endif
#ifndef PARITY_HOST_SAMPLE_0
#define PARITY_HOST_SAMPLE_0 0
#define PARITY_HOST_SAMPLE_1 1
#define PARITY_HOST_SAMPLE_2 2
#define PARITY_HOST_SAMPLE_3 3
#endif
#if PARITY_RESOLVE_SAMPLES == 4 || defined(PARITY_RESOLVE_SAMPLE)
layout(binding = 0) uniform sampler2DMS uEdram;
#else
layout(binding = 0) uniform sampler2D uEdram;
#endif
layout(location = 0) out vec4 oWords;

vec4 storedWords(int sampleIndex) {
  vec4 f = texelFetch(uEdram, ivec2(gl_FragCoord.xy), sampleIndex);
  return clamp(roundEven(f * 32768.0), vec4(-32767.0), vec4(32767.0));
}

#if PARITY_RESOLVE_SAMPLES == 4
vec4 unpack(vec4 s) {
  uvec4 raw = uvec4(ivec4(s)) & 0xFFFFu;
  return max(vec4(parityX360DecodeFixed16(raw.x), parityX360DecodeFixed16(raw.y), parityX360DecodeFixed16(raw.z),
                  parityX360DecodeFixed16(raw.w)),
             vec4(PARITY_K16_UNPACK_MIN));
}
#endif

void main() {
#if PARITY_RESOLVE_SAMPLES == 4
  precise vec4 sum = ((unpack(storedWords(PARITY_HOST_SAMPLE_0)) + unpack(storedWords(PARITY_HOST_SAMPLE_1))) +
                      unpack(storedWords(PARITY_HOST_SAMPLE_2))) +
                     unpack(storedWords(PARITY_HOST_SAMPLE_3));
  precise vec4 value = ldexp(sum, ivec4(-2));
  oWords = vec4(parityX360EncodeFixed16(value.x, 0), parityX360EncodeFixed16(value.y, 0),
                parityX360EncodeFixed16(value.z, 0), parityX360EncodeFixed16(value.w, 0));
#elif defined(PARITY_RESOLVE_SAMPLE)
  oWords = storedWords(PARITY_RESOLVE_SAMPLE);
#else
  oWords = storedWords(0);
#endif
}
