#version 450
// A-buffer resolve (Ferko 2012 §4.1): the pixel's samples are its fragments; sorted by depth and
// blended back to front over the opaque image. Samples no fragment reached hold opacity 0 (the
// clear) and drop out.
#ifndef ABUFFER_SAMPLES
#define ABUFFER_SAMPLES 4
#endif
#include "platform.glsl"
// Read sample by sample as the platform allows (x360: its per-sample resolves).
layout(set = 0, binding = 4) uniform PARITY_SAMPLES_SAMPLER fragmentColors;  // Rgba16Hdr
layout(set = 0, binding = 5) uniform PARITY_SAMPLES_SAMPLER fragmentDepths;
layout(set = 0, binding = 6) uniform sampler2D opaqueImage;  // the platform's Rgba16Hdr read texture

layout(location = 0) out vec4 outColor;

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec4 colors[ABUFFER_SAMPLES];
  float depths[ABUFFER_SAMPLES];
  int n = 0;
  for (int s = 0; s < ABUFFER_SAMPLES; ++s) {
    vec4 c = parityReadRgba16Hdr(parityFetchSample(fragmentColors, p, s));
    if (c.a <= 0.0) continue;
    float d = parityFetchSample(fragmentDepths, p, s).r;
    int j = n++;
    // Insertion sort, farthest first.
    while (j > 0 && depths[j - 1] < d) {
      colors[j] = colors[j - 1];
      depths[j] = depths[j - 1];
      --j;
    }
    colors[j] = c;
    depths[j] = d;
  }
  vec3 result = parityReadRgba16Hdr(texelFetch(opaqueImage, p, 0)).rgb;
  for (int i = 0; i < n; ++i) result = mix(result, colors[i].rgb, colors[i].a);
  outColor = vec4(result, 1.0);
}
