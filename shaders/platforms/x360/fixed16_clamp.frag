#version 450
// Xbox 360 k_16_16_16_16 (X2): the blender clamps every blended result to the encode's range
// [0x8001, 0x7FFF] before storing it. The host surface holds s * 2^-15 in RGBA32F, which does not
// saturate, so GpuTargets clamps it after each blended pass with two draws of this constant:
// PARITY_CLAMP_BOUND -1 with a MAX blend, then +1 with a MIN blend (exact in fp32).
#ifndef PARITY_CLAMP_BOUND
#define PARITY_CLAMP_BOUND 1.0
#endif
layout(location = 0) out vec4 oBound;
void main() { oBound = vec4(PARITY_CLAMP_BOUND * (32767.0 / 32768.0)); }
