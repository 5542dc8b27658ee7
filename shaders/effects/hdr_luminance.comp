#version 450
// Log-average luminance by reduction (Reinhard et al. 2002, eq. 1: exp(mean(log(delta + L)))).
// Pass 0: one 16x16 workgroup per 16x16 block of the HDR image sums log(delta + L) of its pixels
// in shared memory (a tree reduction, fixed order, so the sum is deterministic) and writes one
// partial sum. Pass 1: one workgroup sums the partial sums the same way and writes the mean and
// the log-average. Push constant `mode` picks the pass.
#include "parity_math.glsl"
#include "platform.glsl"  // hdrImage is the platform's Rgba16Hdr read texture

layout(local_size_x = 256) in;

layout(set = 0, binding = 4) uniform sampler2D hdrImage;
layout(set = 0, binding = 8, std430) buffer Partials { float partial[]; };
// x: log-average luminance, y: mean of log(delta + L), z: pixels counted
layout(set = 0, binding = 9, std430) buffer Result { vec4 result; };

layout(push_constant, std430) uniform Reduce {
  uvec4 mode;  // x: 0 blocks, 1 partial sums; y: partial-sum count; z, w: image size
  vec4 params; // x: delta
} reduce;

shared float sums[256];

float luminance(vec3 c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

void main() {
  uint local = gl_LocalInvocationIndex;
  float value = 0.0;
  if (reduce.mode.x == 0u) {
    uvec2 blocks = (reduce.mode.zw + 15u) / 16u;
    uvec2 block = uvec2(gl_WorkGroupID.x % blocks.x, gl_WorkGroupID.x / blocks.x);
    uvec2 p = block * 16u + uvec2(local % 16u, local / 16u);
    if (all(lessThan(p, reduce.mode.zw)))
      value = log(reduce.params.x + max(luminance(parityReadRgba16Hdr(texelFetch(hdrImage, ivec2(p), 0)).rgb), 0.0));
  } else {
    for (uint i = local; i < reduce.mode.y; i += 256u) value += partial[i];
  }
  sums[local] = value;
  barrier();
  for (uint stride = 128u; stride > 0u; stride >>= 1u) {
    if (local < stride) sums[local] += sums[local + stride];
    barrier();
  }
  if (local == 0u) {
    if (reduce.mode.x == 0u) {
      partial[gl_WorkGroupID.x] = sums[0];
    } else {
      float count = float(reduce.mode.z * reduce.mode.w);
      float meanLog = sums[0] / count;
      result = vec4(exp(meanLog), meanLog, count, 0.0);
    }
  }
}
