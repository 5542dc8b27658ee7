#version 450
// Tiled light culling (Andersson 2009, Olsson 2011; thesis §2.4, ch. 5): one 16 x 16 workgroup
// per tile. The tile's visible surface points (reconstructed from depth at the pixel centres,
// where the shading passes evaluate the lights) bound a world-space box; every light whose
// sphere (a spot's cone lies inside it) meets the box goes into the tile's list, in scene order.
#include "parity_math.glsl"
#include "scene_data.glsl"
#include "tile_lists.glsl"

#define MAX_LIGHTS 4096u

layout(local_size_x = TILE_SIZE, local_size_y = TILE_SIZE) in;

layout(set = 0, binding = 8, std430) writeonly buffer TileLightLists { uint tileData[]; };
#ifdef TILED_PLATFORM_DEPTH  // the scene depth, read as the platform reads depth
#include "platform.glsl"
layout(set = 0, binding = 4) uniform PARITY_DEPTH_SAMPLER surfaceDepth;
#define SURFACE_DEPTH(pixel) parityReadDepth(texelFetch(surfaceDepth, pixel, 0))
#else  // the pre-pass's float copy
layout(set = 0, binding = 4) uniform sampler2D surfaceDepth;
#define SURFACE_DEPTH(pixel) texelFetch(surfaceDepth, pixel, 0).r
#endif

shared uint boxMin[3], boxMax[3];
shared uint lightMask[MAX_LIGHTS / 32u];

// Float to uint preserving order, so atomicMin/Max on uints order the floats.
uint orderedBits(float f) {
  uint u = floatBitsToUint(f);
  return (u & 0x80000000u) != 0u ? ~u : u | 0x80000000u;
}
float fromOrderedBits(uint u) { return uintBitsToFloat((u & 0x80000000u) != 0u ? u & 0x7FFFFFFFu : ~u); }

void main() {
  uint local = gl_LocalInvocationIndex;
  if (local < 3u) {
    boxMin[local] = 0xFFFFFFFFu;
    boxMax[local] = 0u;
  }
  for (uint w = local; w < MAX_LIGHTS / 32u; w += uint(TILE_SIZE * TILE_SIZE)) lightMask[w] = 0u;
  barrier();

  ivec2 size = textureSize(surfaceDepth, 0);
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x < size.x && pixel.y < size.y) {
    float depth = SURFACE_DEPTH(pixel);
    if (depth < 1.0) {
      vec2 ndc = (vec2(pixel) + 0.5) / vec2(size) * 2.0 - 1.0;
      vec4 h = mul(frame.invViewProj, vec4(ndc, depth, 1.0));
      vec3 p = h.xyz / h.w;
      for (int k = 0; k < 3; ++k) {
        atomicMin(boxMin[k], orderedBits(p[k]));
        atomicMax(boxMax[k], orderedBits(p[k]));
      }
    }
  }
  barrier();

  bool empty = boxMin[0] > boxMax[0];
  vec3 lo = vec3(fromOrderedBits(boxMin[0]), fromOrderedBits(boxMin[1]), fromOrderedBits(boxMin[2]));
  vec3 hi = vec3(fromOrderedBits(boxMax[0]), fromOrderedBits(boxMax[1]), fromOrderedBits(boxMax[2]));
  uint lightCount = min(frame.counts.x, MAX_LIGHTS);
  if (!empty) {
    for (uint i = local; i < lightCount; i += uint(TILE_SIZE * TILE_SIZE)) {
      vec3 c = lights[i].positionRadius.xyz;
      float r = lights[i].positionRadius.w;
      vec3 outside = max(max(lo - c, c - hi), vec3(0.0));
      // Conservative against rounding in the box: a light exactly touching adds 0 anyway.
      if (dot3(outside, outside) <= r * r * 1.0001) atomicOr(lightMask[i / 32u], 1u << (i % 32u));
    }
  }
  barrier();

  // Compaction in scene order: each of the first words' invocations writes its lights after the
  // lights of the words before it.
  uint entry = (gl_WorkGroupID.y * tiles.params.y + gl_WorkGroupID.x) * tiles.params.x;
  uint words = (lightCount + 31u) / 32u;
  if (local < words) {
    uint offset = 0u;
    for (uint w = 0u; w < local; ++w) offset += uint(bitCount(lightMask[w]));
    uint bits = lightMask[local];
    while (bits != 0u) {
      int b = findLSB(bits);
      bits &= bits - 1u;
      tileData[entry + 1u + offset] = local * 32u + uint(b);
      ++offset;
    }
    if (local == words - 1u) tileData[entry] = offset;
  }
  if (words == 0u && local == 0u) tileData[entry] = 0u;
}
