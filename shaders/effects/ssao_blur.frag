#version 450
// Separable cross-bilateral blur of the occlusion (Ferko 2012, §5.2): Gaussian weights times
// w = 1 / (delta + |d_center - d_current|) (eq. 3) with d the linear view depth, so occlusion
// does not leak across depth edges; normalised by the sum of weights. One axis per pass.
#include "ssao_common.glsl"

layout(set = 0, binding = 6) uniform sampler2D occlusion;

// A uniform block (one slot per axis), not push constants: scene_data.glsl's Material block is
// this stage's one push-constant block.
layout(set = 0, binding = 3, std140) uniform BlurParams {
  ivec4 axis;   // xy: step in reduced-resolution pixels, z: radius in taps
  vec4 params;  // x: delta, y: full/reduced resolution ratio, z: Gaussian sigma in taps
} blur;

layout(location = 0) out vec4 outOcclusion;

void main() {
  ivec2 c = ivec2(gl_FragCoord.xy);
  ivec2 size = textureSize(occlusion, 0);
  float ratio = blur.params.y;
  float dCenter = viewDepthAt(ivec2(vec2(c) * ratio));
  float sum = 0.0, weights = 0.0;
  for (int i = -blur.axis.z; i <= blur.axis.z; ++i) {
    ivec2 t = clamp(c + blur.axis.xy * i, ivec2(0), size - 1);
    float dCurrent = viewDepthAt(ivec2(vec2(t) * ratio));
    float g = exp(-float(i * i) / (2.0 * blur.params.z * blur.params.z));
    float w = g / (blur.params.x + abs(dCenter - dCurrent));
    sum += texelFetch(occlusion, t, 0).r * w;
    weights += w;
  }
  outOcclusion = vec4(sum / weights);
}
