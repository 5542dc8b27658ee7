#version 450
// Xbox 360 k_16_16_16_16 (X2): the render backend stores every write and blend as fixed point
// clamped to [-32, 32] ([0x8001, 0x7FFF]), NaN as 0. The host surface (RGBA32F, s * 2^-15) keeps
// what the shaders and the blender left unclamped, so after each pass that draws into it
// GpuTargets stores it again through this pass, reading a copy of the surface (sample by sample
// when 4x), and counts the samples it changes: lane 0 beyond the range (W_FIXED16_RANGE_CLAMP),
// lane 1 NaN (W_FIXED16_NAN).
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
  const float bound = 32767.0 / 32768.0;
  vec4 v = STORED;
  bvec4 nan = isnan(v);
  vec4 finite = mix(v, vec4(0.0), nan);  // a bvec mix selects: NaN -> 0
  if (any(greaterThan(abs(finite), vec4(bound)))) parityCount(0u);
  if (any(nan)) parityCount(1u);
  oValue = clamp(finite, vec4(-bound), vec4(bound));
}
