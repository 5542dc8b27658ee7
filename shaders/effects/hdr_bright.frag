#version 450
// Bloom source: the HDR image whose exposed luminance (key / log-average x L, the value the
// tone mapping maps) is above a threshold (the excess kept), or, for the lower levels, the level
// above averaged 2x2 (a box filter building the chain). Every level is a Rgba16Hdr target: read
// and written through the platform's mapping, as the accumulation it starts from.
#include "platform.glsl"

layout(set = 0, binding = 4) uniform sampler2D source;
#include "hdr_log_average.glsl"

layout(push_constant, std430) uniform Bright {
  vec4 params;  // x: threshold; y: 1 for the threshold pass, 0 for a downsample; z: key a
} bright;

layout(location = 0) out vec4 outColor;

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  if (bright.params.y > 0.5) {
    vec3 c = parityReadRgba16Hdr(texelFetch(source, min(2 * p, textureSize(source, 0) - 1), 0)).rgb;  // level 0 is half size
    float L = (0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b) * (bright.params.z / max(logAverageLuminance(), 1e-6));
    outColor = parityWriteRgba16Hdr(vec4(L > bright.params.x ? c * ((L - bright.params.x) / L) : vec3(0.0), 1.0));
    return;
  }
  ivec2 lim = textureSize(source, 0) - 1;
  vec3 s = parityReadRgba16Hdr(texelFetch(source, min(2 * p, lim), 0)).rgb +
           parityReadRgba16Hdr(texelFetch(source, min(2 * p + ivec2(1, 0), lim), 0)).rgb +
           parityReadRgba16Hdr(texelFetch(source, min(2 * p + ivec2(0, 1), lim), 0)).rgb +
           parityReadRgba16Hdr(texelFetch(source, min(2 * p + ivec2(1, 1), lim), 0)).rgb;
  outColor = parityWriteRgba16Hdr(vec4(s * 0.25, 1.0));
}
