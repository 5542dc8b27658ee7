#version 450
// Reinhard global tone mapping (Reinhard et al. 2002, eq. 2-3): L scaled by key / log-average,
// Ld = L / (1 + L), colours scaled by Ld / L; bloom added before the mapping, summed over the
// bright image's mip levels (each bilinearly upsampled).
#include "platform.glsl"  // hdrImage is the platform's Rgba16Hdr read texture

layout(set = 0, binding = 4) uniform sampler2D hdrImage;
layout(set = 0, binding = 5) uniform sampler2D bloom;
layout(set = 0, binding = 9, std430) readonly buffer Result { vec4 result; };

layout(push_constant, std430) uniform Tonemap {
  vec4 params;  // x: key a, y: bloom strength, z: mip levels of `bloom`
} tonemap;

layout(location = 0) out vec4 outColor;

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec2 uv = gl_FragCoord.xy / vec2(textureSize(hdrImage, 0));
  vec3 c = parityReadRgba16Hdr(texelFetch(hdrImage, p, 0)).rgb;
  vec3 b = vec3(0.0);
  int levels = int(tonemap.params.z);
  for (int l = 0; l < levels; ++l) b += textureLod(bloom, uv, float(l)).rgb;
  c += b * (tonemap.params.y / float(max(levels, 1)));
  float L = 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
  float scaled = tonemap.params.x / max(result.x, 1e-6) * L;
  float Ld = scaled / (1.0 + scaled);
  outColor = vec4(L > 0.0 ? c * (Ld / L) : vec3(0.0), 1.0);
}
