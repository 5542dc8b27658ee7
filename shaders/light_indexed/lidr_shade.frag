#version 450
// Light-indexed forward pass (Trebilco 2008, pass 3): the geometry drawn again with forward
// shading, the local lights looked up by the indices the light volume pass packed at this pixel.
// Ambient and the directional light as in the forward shader (eq. 3.5, 3.6), then each indexed
// point/spot light (eq. 3.7, 3.8) from the light tables:
//   lightColors (RGBA8, one texel per index): rgb intensity / LIDR_COLOR_SCALE;
//   lightData (RGBA32F, one column per index): row 0 position and 1 / radius (the paper's table),
//     row 1 spot direction and cos(outer), row 2 cos(inner), type, radius.
// Index 0 is the null light (black, never used). Positions are in world space, where the
// forward reference shades, so the same phong.glsl arithmetic applies.
// Second output: the lights that reached this pixel (the overlap count target, written by the
// light volume shader with additive blending) but did not fit the packing, as a count / 255.
//
// Packing: LIDR_PACKING_SORT, LIDR_PACKING_MAX or LIDR_PACKING_BITS (default) with
// LIDR_CHANNELS and LIDR_INDEX_BITS (default 4 channels of 8-bit indices).
#include "parity_math.glsl"
#include "scene_data.glsl"
#include "phong.glsl"
#include "normal_mapping.glsl"
#include "lidr_unpack.glsl"

#if !defined(LIDR_PACKING_SORT) && !defined(LIDR_PACKING_MAX) && !defined(LIDR_PACKING_BITS)
#define LIDR_PACKING_BITS 1
#endif
#ifndef LIDR_CHANNELS
#define LIDR_CHANNELS 4
#endif
#ifndef LIDR_INDEX_BITS
#define LIDR_INDEX_BITS 8
#endif
#ifndef LIDR_DROPPED_SCALE  // what each sample's lost-light count is multiplied by (the samples)
#define LIDR_DROPPED_SCALE 1.0
#endif
#ifndef LIDR_COLOR_SCALE
#define LIDR_COLOR_SCALE 2.0
#endif

// The index slots the packing can fill (lidr_unpack.glsl): the loop over the indices stops there
// instead of at LIDR_MAX_INDICES. The slots beyond hold the null light, which adds nothing, but a
// loop of 16 over the dynamically indexed array made GL's forward pass three to four times
// slower than Vulkan's on llvmpipe (docs/BENCH.md).
#if defined(LIDR_PACKING_SORT) || defined(LIDR_PACKING_MAX)
#define LIDR_SLOTS 4u
#else
#define LIDR_SLOTS min(8u / (uint(LIDR_INDEX_BITS) / uint(LIDR_CHANNELS)), LIDR_MAX_INDICES)
#endif

layout(set = 0, binding = 2) uniform sampler2D diffuseTexture;
layout(set = 0, binding = 3) uniform sampler2D lightIndexA;
#if defined(LIDR_PACKING_BITS) && LIDR_CHANNELS > 4
layout(set = 0, binding = 4) uniform sampler2D lightIndexB;
#endif
layout(set = 0, binding = 5) uniform sampler2D lightColors;
layout(set = 0, binding = 6) uniform sampler2D lightData;
layout(set = 0, binding = 7) uniform sampler2D overlapCount;

layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;

layout(location = 0) out vec4 outColor;
layout(location = 1) out vec4 outDropped;

void main() {
  vec3 N = shadingNormal(inNormal, inWorldPos, inUv);
  vec3 C = normalize3(frame.cameraPos.xyz - inWorldPos);
  vec3 diffuseColor = material.diffuse.rgb;
  if ((material.flags.x & MATERIAL_DIFFUSE_TEXTURE) != 0u) diffuseColor = diffuseColor * texture(diffuseTexture, inUv).rgb;
  vec3 specularColor = material.specular.rgb;
  float power = material.specular.w;

  vec3 color = diffuseColor * frame.ambient.rgb;  // eq. 3.5
  color += phongTerms(N, frame.directionalDir.xyz, C, diffuseColor, specularColor, power) *
           frame.directionalColor.rgb;  // eq. 3.6

  ivec2 pixel = ivec2(gl_FragCoord.xy);
  uint indices[LIDR_MAX_INDICES];
#if defined(LIDR_PACKING_SORT)
  uint found = lidrUnpackSort(texelFetch(lightIndexA, pixel, 0), indices);
#elif defined(LIDR_PACKING_MAX)
  uint found = lidrUnpackMax(texelFetch(lightIndexA, pixel, 0), indices);
#else
#if LIDR_CHANNELS > 4
  vec4 packedB = texelFetch(lightIndexB, pixel, 0);
#else
  vec4 packedB = vec4(0.0);
#endif
  uint found = lidrUnpackBits(texelFetch(lightIndexA, pixel, 0), packedB, uint(LIDR_CHANNELS), uint(LIDR_INDEX_BITS), indices);
#endif

#ifdef LIDR_EVERY_LIGHT
  // Reference shading: every light of the table (multi-light forward), indices unused.
  uint tableLights = min(frame.counts.x, uint(textureSize(lightColors, 0).x) - 1u);
  for (uint index = 1u; index <= tableLights; ++index) {
#else
  for (uint i = 0u; i < LIDR_SLOTS; ++i) {
    uint index = indices[i];
    if (index == 0u) continue;  // the null light
#endif
    vec4 positionInvRadius = texelFetch(lightData, ivec2(int(index), 0), 0);
    vec4 spot = texelFetch(lightData, ivec2(int(index), 1), 0);
    vec4 extra = texelFetch(lightData, ivec2(int(index), 2), 0);
    // Row material.flags.y: the surface's light table (lights constrained to surfaces are black
    // in the tables of the surfaces they must not reach; row 0 holds every light).
    vec3 lightColor = texelFetch(lightColors, ivec2(int(index), int(material.flags.y)), 0).rgb * LIDR_COLOR_SCALE;
    vec3 toSurface = inWorldPos - positionInvRadius.xyz;
    float d = length3(toSurface);
    // k = 2 / radius (scene::Light::attenuationK) = 2 * (1 / radius), exactly, in fp32.
    float A = attenuation(d, 2.0 * positionInvRadius.w, extra.z);
    if (A == 0.0) continue;
    vec3 L = toSurface / d;
    float F = 1.0;
    if (floatBitsToUint(extra.y) == LIGHT_SPOT) F = spotFactor(spot.xyz, L, spot.w, extra.x);  // eq. 3.12
    color += phongTerms(N, L, C, diffuseColor, specularColor, power) * lightColor * (A * F);
  }
  outColor = vec4(color, 1.0);

  uint reached = uint(texelFetch(overlapCount, pixel, 0).r * 255.0 + 0.5);
  outDropped = vec4(float(reached > found ? reached - found : 0u) * LIDR_DROPPED_SCALE / 255.0, 0.0, 0.0, 1.0);
}
