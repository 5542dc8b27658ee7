#version 450
// Depth peeling (Everitt 2001), the A-buffer's reference: pass k keeps, per pixel, the nearest
// translucent fragment behind layer k - 1 (depth test LESS on its own depth buffer, fragments
// not behind the previous layer discarded) and in front of the opaque surface.
#include "translucent_shading.glsl"
#include "platform.glsl"

layout(set = 0, binding = 4) uniform PARITY_DEPTH_SAMPLER previousLayerDepth;  // 0 before the first layer
layout(set = 0, binding = 5) uniform PARITY_DEPTH_SAMPLER opaqueDepth;  // read as the platform reads depth

layout(location = 0) out vec4 outColor;

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  if (gl_FragCoord.z <= parityReadDepth(texelFetch(previousLayerDepth, p, 0))) discard;
  if (gl_FragCoord.z >= parityReadDepth(texelFetch(opaqueDepth, p, 0))) discard;
  outColor = parityWriteRgba16Hdr(shadeTranslucent());  // the platform's Rgba16Hdr layer target
}
