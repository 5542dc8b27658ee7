#version 450
// MSAA technique 2 of light-indexed deferred rendering (Trebilco 2008, "Light Volume Front
// Faces"): the light index texture is single-sample, so the light volumes are depth tested
// against the farthest of the pixel's samples. A volume in front of any sample's opaque surface
// is then in front of this depth too, and every sample finds the lights it can receive. Writes
// the depth for the test and keeps it readable as a colour.
#include "platform.glsl"
// The pre-pass's 4x surface depth, read sample by sample (on x360 its per-sample resolves).
layout(set = 0, binding = 4) uniform PARITY_SAMPLES_SAMPLER sampleDepths;

layout(location = 0) out float outDepth;

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  float farthest = parityFetchSample(sampleDepths, pixel, 0).r;
  for (int s = 1; s < 4; ++s) farthest = max(farthest, parityFetchSample(sampleDepths, pixel, s).r);
  outDepth = farthest;
  gl_FragDepth = farthest;
}
