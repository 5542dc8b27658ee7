#version 450
// Xbox 360 resolve of a 32-bpp k_8_8_8_8 or k_32_FLOAT MSAA surface, no exponent bias (X3):
//  * by default (copy_sample_select k0123) the samples unpacked and averaged. k_8_8_8_8
//    (PARITY_RESOLVE_UNORM8 1; an R8 target lives in its red) averages the stored bytes and packs
//    with round half up, as Xenia's XePackR8G8B8A8UNorm does (saturate(f) * 255 + 0.5), in
//    integers so that no float rounding moves a tie; k_32_FLOAT sums the floats in guest sample
//    order ((s0 + s1) + s2) + s3 and halves twice. Guest sample s is host sample
//    PARITY_HOST_SAMPLE_s of the attachment.
//    PARITY_RESOLVE_7E3 1: k_2_10_10_10_FLOAT, the samples' 7e3 values summed in that order,
//    halved twice and stored as 7e3 again.
//  * PARITY_RESOLVE_SAMPLE h (one sample selected, host sample h): a bit copy of that sample.
#ifndef PARITY_RESOLVE_UNORM8
#define PARITY_RESOLVE_UNORM8 1
#endif
#ifndef PARITY_RESOLVE_7E3
#define PARITY_RESOLVE_7E3 0
#endif
#if PARITY_RESOLVE_7E3
#include "float7e3.glsl"
#endif
#ifndef PARITY_HOST_SAMPLE_0
#define PARITY_HOST_SAMPLE_0 0
#define PARITY_HOST_SAMPLE_1 1
#define PARITY_HOST_SAMPLE_2 2
#define PARITY_HOST_SAMPLE_3 3
#endif
layout(binding = 0) uniform sampler2DMS uEdram;
layout(location = 0) out vec4 oColor;

vec4 storedSample(int hostSample) { return texelFetch(uEdram, ivec2(gl_FragCoord.xy), hostSample); }

void main() {
#if defined(PARITY_RESOLVE_SAMPLE)
  oColor = storedSample(PARITY_RESOLVE_SAMPLE);
#elif PARITY_RESOLVE_UNORM8
  uvec4 sum = uvec4(0u);
  for (int s = 0; s < 4; ++s) {
    const int host[4] = int[4](PARITY_HOST_SAMPLE_0, PARITY_HOST_SAMPLE_1, PARITY_HOST_SAMPLE_2, PARITY_HOST_SAMPLE_3);
    sum += uvec4(roundEven(clamp(storedSample(host[s]), 0.0, 1.0) * 255.0));
  }
  oColor = vec4((sum + 2u) / 4u) / 255.0;  // n / 255 converts back to exactly n
#else
  precise vec4 sum = ((storedSample(PARITY_HOST_SAMPLE_0) + storedSample(PARITY_HOST_SAMPLE_1)) +
                      storedSample(PARITY_HOST_SAMPLE_2)) +
                     storedSample(PARITY_HOST_SAMPLE_3);
  precise vec4 value = sum * 0.25;
#if PARITY_RESOLVE_7E3
  oColor = parityX360Quantise7e3(value);
#else
  oColor = value;
#endif
#endif
}
