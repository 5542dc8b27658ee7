#version 450
// DX10 (D1): the copy of a single-sample depth surface into an R24X8 texture, the only way a
// shader may read depth on FL10.0. Output: the 24-bit depth word, X8 = 0.
#include "../common/depth24.glsl"
layout(binding = 0) uniform sampler2D uDepth;
layout(location = 0) out uint oR24X8;
void main() { oR24X8 = parityDepthToD24(texelFetch(uDepth, ivec2(gl_FragCoord.xy), 0).x); }
