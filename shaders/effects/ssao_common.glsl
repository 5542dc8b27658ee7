// G-buffer reads shared by the SSAO and blur passes: full-resolution depth and normals through the
// platform's read paths (DX10 depth reads, PS3 BARG depth, x360 resolves).
#ifndef PARITY_SSAO_COMMON_GLSL
#define PARITY_SSAO_COMMON_GLSL
#include "parity_math.glsl"
#include "scene_data.glsl"
#include "../platforms/platform.glsl"
#include "gbuffer.glsl"

layout(set = 0, binding = 4) uniform PARITY_DEPTH_SAMPLER gbufferDepth;
layout(set = 0, binding = 5) uniform PARITY_RG16_SAMPLER gbufferNormals;

ivec2 fullSize() { return textureSize(gbufferDepth, 0); }

float depthAt(ivec2 p) {
  p = clamp(p, ivec2(0), fullSize() - 1);
  return parityReadDepth(texelFetch(gbufferDepth, p, 0));
}

// World position of full-resolution pixel p (its centre).
vec3 positionAt(ivec2 p) {
  p = clamp(p, ivec2(0), fullSize() - 1);
  return worldPositionFromDepth(vec2(p) + 0.5, vec2(fullSize()), depthAt(p));
}

// Distance from the camera along the view axis: the linear depth the blur compares.
float viewDepthAt(ivec2 p) {
  vec3 w = positionAt(p);
  return -mul(frame.view, vec4(w, 1.0)).z;
}

#endif
