// The local lights of one pixel's tile, summed as the forward shader sums them (eq. 3.7, 3.8,
// 3.11, 3.12 through phong.glsl), in the tile list's scene order.
#ifndef PARITY_TILED_LIGHTING_GLSL
#define PARITY_TILED_LIGHTING_GLSL
#include "parity_math.glsl"
#include "scene_data.glsl"
#include "phong.glsl"
#include "tile_lists.glsl"

layout(set = 0, binding = 8, std430) readonly buffer TileLightLists { uint tileData[]; };

// Adds to `color` light by light, as the forward shader does (the same roundings).
void addTileLights(inout vec3 color, ivec2 pixel, vec3 worldPos, vec3 N, vec3 C, vec3 diffuseColor, vec3 specularColor,
                   float power) {
  uint entry = tileEntry(pixel);
  uint count = tileData[entry];
  for (uint j = 0u; j < count; ++j) {
    Light light = lights[tileData[entry + 1u + j]];
    vec3 toSurface = worldPos - light.positionRadius.xyz;
    float d = length3(toSurface);
    float A = attenuation(d, light.colorK.w, light.positionRadius.w);
    if (A == 0.0) continue;
    vec3 L = toSurface / d;
    float F = 1.0;
    if (floatBitsToUint(light.directionType.w) == LIGHT_SPOT)
      F = spotFactor(light.directionType.xyz, L, light.cone.x, light.cone.y);  // eq. 3.12
    color += phongTerms(N, L, C, diffuseColor, specularColor, power) * light.colorK.rgb * (A * F);
  }
}

#endif
