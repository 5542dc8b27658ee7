#version 450
// Geometry pass (§2.1) at the L-buffer resolution: normals (eq. 1), DSF data, specular power.
// Alpha polygons (material.flags.z = stipple pattern 1..3) write only the texels of their 2x2
// pattern (§4) and are alpha-tested (§6: no lighting samples where they are fully transparent);
// they are drawn double-sided and keep the normal they were authored with, so they are lit on
// that side from whichever side they are seen.
#include "parity_math.glsl"
#include "scene_data.glsl"
#include "normal_encoding.glsl"
#include "normal_mapping.glsl"
#include "platform.glsl"
#include "inferred.glsl"

layout(set = 0, binding = 2) uniform sampler2D diffuseTexture;

layout(location = 0) in vec3 inViewNormal;
layout(location = 1) in float inLinearDepth;
layout(location = 2) in vec2 inUv;
layout(location = 3) flat in uint inNormalGroup;
layout(location = 4) in vec3 inViewPos;

layout(location = 0) out vec4 outNormals;
layout(location = 1) out vec4 outDsf;
layout(location = 2) out vec4 outSpecular;

void main() {
  uint pattern = material.flags.z;
  vec3 n = shadingNormal(inViewNormal, inViewPos, inUv);  // before the discards: it takes derivatives
  if (pattern != 0u) {
    uvec2 texel = uvec2(gl_FragCoord.xy) & 1u;
    if (texel != uvec2(pattern & 1u, pattern >> 1)) discard;
    float alpha = uintBitsToFloat(material.flags.w);
    if ((material.flags.x & MATERIAL_DIFFUSE_TEXTURE) != 0u) alpha *= texture(diffuseTexture, inUv).a;
    if (alpha <= 0.0) discard;
  }
  // Eq. 1 is singular at n = (0, 0, -1) (§2.1). Opaque polygons facing away are culled, but an
  // alpha polygon seen from behind keeps its authored normal (a window lit from the far side):
  // nudge that one direction off the singularity.
  if (n.z < -0.99999) n = normalize3(n + vec3(1e-2, 0.0, 0.0));
  outNormals = parityWriteRg16(encodeNormalHalfSphere(n));
  outDsf = parityWriteRg16(vec2(inLinearDepth, dsfIdToUnorm(dsfId(material.flags.y, inNormalGroup))));
  // Integral powers up to 255 are exact in 8 bits (k / 255).
  outSpecular = vec4(clamp(floor(material.specular.w + 0.5), 0.0, 255.0) / 255.0, 0.0, 0.0, 1.0);
}
