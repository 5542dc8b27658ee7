#version 450
// A multisampled surface copied sample by sample (the RHI copies no multisampled texture): the
// copy GpuTargets' stores of a 4x surface read while they rewrite it.
layout(binding = 0) uniform sampler2DMS uSurface;
layout(location = 0) out vec4 oValue;
void main() { oValue = texelFetch(uSurface, ivec2(gl_FragCoord.xy), gl_SampleID); }
