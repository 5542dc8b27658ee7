#version 450
// Reinhard global tone mapping (Reinhard et al. 2002, eq. 2-3): L scaled by key / log-average,
// Ld = L / (1 + L), colours scaled by Ld / L; bloom added before the mapping, summed over the
// bright image's levels (each bilinearly upsampled; Rgba16Hdr read textures of the platform).
#include "platform.glsl"  // hdrImage is the platform's Rgba16Hdr read texture

layout(set = 0, binding = 4) uniform sampler2D hdrImage;
layout(set = 0, binding = 5) uniform sampler2D bloom0;
layout(set = 0, binding = 6) uniform sampler2D bloom1;
layout(set = 0, binding = 7) uniform sampler2D bloom2;
layout(set = 0, binding = 10) uniform sampler2D bloom3;
layout(set = 0, binding = 11) uniform sampler2D bloom4;
#include "hdr_log_average.glsl"

layout(push_constant, std430) uniform Tonemap {
  vec4 params;  // x: key a, y: bloom strength, z: bloom levels (1 to 5)
} tonemap;

layout(location = 0) out vec4 outColor;

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec2 uv = gl_FragCoord.xy / vec2(textureSize(hdrImage, 0));
  vec3 c = parityReadRgba16Hdr(texelFetch(hdrImage, p, 0)).rgb;
  vec3 b = vec3(0.0);
  int levels = int(tonemap.params.z);
  // The filter is linear in the texels, so the platform's read mapping (linear too) commutes with it.
  b += parityReadRgba16Hdr(textureLod(bloom0, uv, 0.0)).rgb;
  if (levels > 1) b += parityReadRgba16Hdr(textureLod(bloom1, uv, 0.0)).rgb;
  if (levels > 2) b += parityReadRgba16Hdr(textureLod(bloom2, uv, 0.0)).rgb;
  if (levels > 3) b += parityReadRgba16Hdr(textureLod(bloom3, uv, 0.0)).rgb;
  if (levels > 4) b += parityReadRgba16Hdr(textureLod(bloom4, uv, 0.0)).rgb;
  c += b * (tonemap.params.y / float(max(levels, 1)));
  float L = 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
  float scaled = tonemap.params.x / max(logAverageLuminance(), 1e-6) * L;
  float Ld = scaled / (1.0 + scaled);
  outColor = vec4(L > 0.0 ? c * (Ld / L) : vec3(0.0), 1.0);
}
