#version 450
// Screen-space ambient occlusion (Ferko 2012, §5.1) into a reduced-resolution target. For the
// surface point P of each pixel, sample points Q = P + r v in a sphere; v is one of 16 fixed
// vectors in the unit sphere reflected about a per-pixel random vector (a 4x4 texture repeated
// over the screen), and flipped into the normal's half-space so that no sample lies behind the
// surface (the paper's fix for self-occlusion of flat surfaces). Q is projected into the depth
// map; a surface in front of Q occludes with O(d) = 1 / (1 + d^2), d its distance from P in
// units of r. The output is 1 - the mean occlusion (1: unoccluded).
#include "ssao_common.glsl"

layout(set = 0, binding = 6) uniform sampler2D randomVectors;  // RGBA8, xyz * 2 - 1 = unit vector

// A uniform block, not push constants: scene_data.glsl's Material block is this stage's one
// push-constant block.
layout(set = 0, binding = 3, std140) uniform SsaoParams {
  vec4 params;  // x: radius r (world units), y: full/reduced resolution ratio
} ssao;

layout(location = 0) out vec4 outOcclusion;

const int kSamples = 16;
// Uniformly distributed in the unit ball, fixed (a deterministic set, lengths 0.2 .. 1).
const vec3 kKernel[kSamples] = vec3[](
    vec3(0.5381, 0.1856, 0.4319), vec3(0.1379, 0.2486, 0.4430), vec3(0.3371, 0.5679, -0.0057),
    vec3(-0.6999, -0.0451, -0.0019), vec3(0.0689, -0.1598, -0.8547), vec3(0.0560, 0.0069, -0.1843),
    vec3(-0.0146, 0.1402, 0.0762), vec3(0.0100, -0.1924, -0.0344), vec3(-0.3577, -0.5301, -0.4358),
    vec3(-0.3169, 0.1063, 0.0158), vec3(0.0103, -0.5869, 0.0046), vec3(-0.0897, -0.4940, 0.3287),
    vec3(0.7119, -0.0154, -0.0918), vec3(-0.0533, 0.0596, -0.5411), vec3(0.0352, -0.0631, 0.5460),
    vec3(-0.4776, 0.2847, -0.0271));

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy * ssao.params.y);
  float depth = depthAt(p);
  if (depth >= 1.0) {  // background: nothing to occlude
    outOcclusion = vec4(1.0);
    return;
  }
  vec3 P = positionAt(p);
  vec3 N = decodeWorldNormal(parityReadRg16(texelFetch(gbufferNormals, p, 0)));
  vec3 R = normalize3(texelFetch(randomVectors, ivec2(gl_FragCoord.xy) & 3, 0).xyz * 2.0 - 1.0);
  float r = ssao.params.x;
  vec3 cameraPos = frame.cameraPos.xyz;
  float occlusion = 0.0;
  for (int i = 0; i < kSamples; ++i) {
    vec3 v = reflect3(kKernel[i], R);
    if (dot3(v, N) < 0.0) v = -v;  // angle to the normal > pi/2: take -v
    vec3 Q = P + v * r;
    vec4 clip = mul(frame.viewProj, vec4(Q, 1.0));
    if (clip.w <= 0.0) continue;
    vec2 ndc = clip.xy / clip.w;
    if (any(greaterThan(abs(ndc), vec2(1.0)))) continue;
    ivec2 q = ivec2((ndc * 0.5 + 0.5) * vec2(fullSize()));
    if (depthAt(q) >= 1.0) continue;
    vec3 S = positionAt(q);  // the surface the depth map holds where Q projects
    // Occluded when that surface is nearer the camera than Q (a margin of 2% of r absorbs depth
    // quantisation).
    // S must also rise above P's tangent plane: on a plane seen at a grazing angle one depth
    // texel spans more than r, and the texel's centre can lie nearer the camera than Q although
    // it is the same plane.
    if (length3(S - cameraPos) < length3(Q - cameraPos) - 0.02 * r && dot3(S - P, N) > 0.05 * r) {
      float d = length3(S - P) / r;
      if (d < 2.0) occlusion += 1.0 / (1.0 + d * d);  // eq. 2; far surfaces (depth edges) do not count
    }
  }
  outOcclusion = vec4(1.0 - occlusion / float(kSamples));
}
