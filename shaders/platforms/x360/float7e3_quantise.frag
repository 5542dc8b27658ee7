#version 450
// Xbox 360 k_2_10_10_10_FLOAT (7e3, X2): the render backend stores every write and blend in 7e3.
// The host surface (RGBA32F) holds the unrounded values, so after each pass that draws into it
// GpuTargets stores it again through this pass, reading a copy of the surface (sample by sample
// when 4x), and counts the samples whose colour lies outside 7e3's [0, 31.875] or is NaN
// (lane 0, W_FLOAT7E3_RANGE_CLAMP).
#include "float7e3.glsl"
#ifdef PARITY_STORE_MSAA
layout(binding = 0) uniform sampler2DMS uSurface;
#define STORED texelFetch(uSurface, ivec2(gl_FragCoord.xy), gl_SampleID)
#else
layout(binding = 0) uniform sampler2D uSurface;
#define STORED texelFetch(uSurface, ivec2(gl_FragCoord.xy), 0)
#endif
#include "texel_counts.glsl"
layout(location = 0) out vec4 oValue;
void main() {
  vec4 v = STORED;
  bvec3 nan = isnan(v.rgb);
  vec3 finite = mix(v.rgb, vec3(0.0), nan);
  if (any(nan) || any(lessThan(finite, vec3(0.0))) || any(greaterThan(finite, vec3(31.875)))) parityCount(0u);
  oValue = parityX360Quantise7e3(v);
}
