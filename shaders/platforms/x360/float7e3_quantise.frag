#version 450
// Xbox 360 k_2_10_10_10_FLOAT (7e3, X2): the blender stores every blended result in 7e3. The
// host surface (RGBA32F) holds the unrounded sums, so GpuTargets rounds them to 7e3 after each
// blended pass: a copy of the surface read back through this pass (sample by sample when 4x).
#include "float7e3.glsl"
#ifdef PARITY_QUANTISE_MSAA
layout(binding = 0) uniform sampler2DMS uSurface;
#define STORED texelFetch(uSurface, ivec2(gl_FragCoord.xy), gl_SampleID)
#else
layout(binding = 0) uniform sampler2D uSurface;
#define STORED texelFetch(uSurface, ivec2(gl_FragCoord.xy), 0)
#endif
layout(location = 0) out vec4 oValue;
void main() { oValue = parityX360Quantise7e3(STORED); }
