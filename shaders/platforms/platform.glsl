// Platform layer entry point for technique shaders: includes the snippets of the platform the
// harness selected through its defines (platforms/platform_layer.h documents the contract:
// parityWriteRg16, parityReadRg16, parityReadDepth, PARITY_RG16_SAMPLER, PARITY_DEPTH_SAMPLER,
// PARITY_DEPTH_ARRAY_SAMPLER, PARITY_DEPTH_TEXEL, parityWriteRgba16Hdr, parityReadRgba16Hdr, and the exact-write pair
// PARITY_RG16_BITS_TYPE / parityWriteRg16Bits for GpuTargets::writeTarget(), PARITY_SAMPLES_SAMPLER /
// parityFetchSample). Without a platform define the reference platform is used.
#ifndef PARITY_PLATFORM_GLSL
#define PARITY_PLATFORM_GLSL

#if defined(PARITY_PLATFORM_X360)
#include "x360/targets.glsl"
#elif defined(PARITY_PLATFORM_PS3)
#include "ps3/targets.glsl"
#elif defined(PARITY_PLATFORM_DX10)
#include "dx10/targets.glsl"
#else
#include "reference/targets.glsl"
#endif

// A multisampled target read sample by sample (LogicalTarget::readSamples): the hosts sample the
// MSAA texture itself; x360 reads the layers its per-sample resolves wrote (x360/targets.glsl).
#ifndef PARITY_SAMPLES_SAMPLER
#define PARITY_SAMPLES_SAMPLER sampler2DMS
#define parityFetchSample(t, p, s) texelFetch(t, p, s)
#endif

#endif
