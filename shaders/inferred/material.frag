#version 450
// Material pass (§2.3) at the output resolution: the material is applied to lighting inferred
// from the L-buffer.
//  * Opaque polygons (material.flags.z = 0): the discontinuity sensitive filter (§3). The four
//    L-buffer texels regular bilinear filtering would use are point sampled together with their
//    DSF data; a texel counts only when its object ID and normal-group ID equal this polygon's and
//    its linear depth is within the threshold; the bilinear weights of the texels that count are
//    renormalised. When none counts, regular bilinear filtering (the paper's fall-back).
//    INFERRED_PLAIN_BILINEAR: always regular bilinear (to measure what the filter buys).
//  * Alpha polygons (flags.z = stipple pattern 1..3): a small cone filter over the four nearest
//    texels of their stipple pattern (§4), DSF-checked in the same way.
// The specular colour is the stored intensity times the chromaticity of the diffuse light
// (§2.2), which is exact wherever one light colour dominates a pixel.
#include "parity_math.glsl"
#include "scene_data.glsl"
#include "platform.glsl"
#include "inferred.glsl"

layout(set = 0, binding = 2) uniform sampler2D diffuseTexture;
layout(set = 0, binding = 4) uniform sampler2D lBuffer;
layout(set = 0, binding = 5) uniform PARITY_RG16_SAMPLER gDsf;

layout(location = 0) in vec3 inViewNormal;
layout(location = 1) in float inLinearDepth;
layout(location = 2) in vec2 inUv;
layout(location = 3) flat in uint inNormalGroup;

layout(location = 0) out vec4 outColor;

// A matching sample keeps at least this weight, so that a match at a bilinear weight of 0 (the
// pixel exactly on a texel row) still beats the fall-back.
const float kMinMatchWeight = 1e-4;
// Cone filter radius in L-buffer texels: the farthest of the four nearest stipple samples is at
// most 2 * sqrt(2) = 2.83 texels away.
const float kConeRadius = 3.0;

vec4 lightAt(ivec2 t) { return parityReadRgba16Hdr(texelFetch(lBuffer, t, 0)); }

bool sameSurface(ivec2 t, uint id) {
  vec2 dsf = parityReadRg16(texelFetch(gDsf, t, 0));
  return dsfIdFromUnorm(dsf.y) == id && abs(dsf.x - inLinearDepth) <= inferred.dsf.x * inLinearDepth;
}

void main() {
  ivec2 size = ivec2(inferred.sizes.zw);
  // This pixel's centre in L-buffer texel coordinates (texel centres at integers), through the
  // shared normalised device coordinates of both resolutions.
  vec2 u = gl_FragCoord.xy * inferred.sizes.zw / inferred.sizes.xy - 0.5;
  uint id = dsfId(material.flags.y, inNormalGroup);
  uint pattern = material.flags.z;
  const ivec2 corner[4] = ivec2[4](ivec2(0, 0), ivec2(1, 0), ivec2(0, 1), ivec2(1, 1));

  vec4 matched = vec4(0.0), all = vec4(0.0);
  float matchedWeight = 0.0, allWeight = 0.0;
  if (pattern == 0u) {
    vec2 base = floor(u);
    vec2 f = u - base;
    for (int i = 0; i < 4; ++i) {
      ivec2 t = clamp(ivec2(base) + corner[i], ivec2(0), size - 1);
      vec2 w2 = mix(1.0 - f, f, vec2(corner[i]));
      float w = w2.x * w2.y;
      vec4 L = lightAt(t);
      all += w * L;
      allWeight += w;
#ifndef INFERRED_PLAIN_BILINEAR
      if (sameSurface(t, id)) {
        matched += (w + kMinMatchWeight) * L;
        matchedWeight += w + kMinMatchWeight;
      }
#endif
    }
  } else {
    ivec2 offset = ivec2(pattern & 1u, pattern >> 1);
    // Nearest four texels of the pattern: a 2x2 block of the pattern's own grid (spacing 2).
    ivec2 base = ivec2(floor((u - vec2(offset)) * 0.5));
    for (int i = 0; i < 4; ++i) {
      ivec2 t = offset + 2 * (base + corner[i]);
      // Stay on the pattern inside the buffer.
      t = ivec2(t.x < 0 ? t.x + 2 : t.x >= size.x ? t.x - 2 : t.x, t.y < 0 ? t.y + 2 : t.y >= size.y ? t.y - 2 : t.y);
      vec2 d = u - vec2(t);
      float w = max(0.0, 1.0 - sqrt(dot2(d, d)) / kConeRadius);
      vec4 L = lightAt(t);
      all += w * L;
      allWeight += w;
      if (sameSurface(t, id)) {
        matched += (w + kMinMatchWeight) * L;
        matchedWeight += w + kMinMatchWeight;
      }
    }
  }
  vec4 light = matchedWeight > 0.0 ? matched / matchedWeight : all / max(allWeight, 1e-6);

  vec3 diffuseColor = material.diffuse.rgb;
  float alpha = pattern == 0u ? 1.0 : uintBitsToFloat(material.flags.w);
  if ((material.flags.x & MATERIAL_DIFFUSE_TEXTURE) != 0u) {
    vec4 t = texture(diffuseTexture, inUv);
    diffuseColor = diffuseColor * t.rgb;
    if (pattern != 0u) alpha *= t.a;
  }
  // Specular colour from the diffuse light's chromaticity; the ambient term (diffuse only, the
  // same everywhere) is left out of it.
  vec3 directLight = max(light.rgb - frame.ambient.rgb, vec3(0.0));
  float luminance = lightLuminance(directLight);
  vec3 specularLight = luminance > 1e-6 ? light.a * directLight / luminance : vec3(light.a);
  vec3 color = diffuseColor * light.rgb + material.specular.rgb * specularLight;
  outColor = vec4(color, alpha);
}
