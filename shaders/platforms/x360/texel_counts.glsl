// A platform pass that counts the samples it changes (platforms/texel_counters.h): lane L of the
// pass's slot (pushed by GpuTargets) gains 1 for every sample that breaks the rule of lane L.
// PARITY_COUNT 0 (a GpuTargets without a PlatformDevice): nothing is counted.
#ifndef PARITY_X360_TEXEL_COUNTS_GLSL
#define PARITY_X360_TEXEL_COUNTS_GLSL
#ifndef PARITY_COUNT
#define PARITY_COUNT 0
#endif
#if PARITY_COUNT
layout(std430, binding = 15) buffer ParityTexelCounts { uint parityTexelCounts[]; };
layout(push_constant) uniform ParityCountSlot { uint slot; } parityCountSlot;
void parityCount(uint lane) { atomicAdd(parityTexelCounts[parityCountSlot.slot * 4u + lane], 1u); }
#else
void parityCount(uint lane) {}
#endif
#endif
