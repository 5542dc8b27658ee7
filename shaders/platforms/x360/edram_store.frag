#version 450
// Xbox 360: one colour surface as it lies in EDRAM (X1). Each fragment is one dword of the
// surface's tile span (output R32_UINT, 1280 dwords = one 5120-byte tile per row, one row per
// tile counted from the surface's base); it inverts the address formula (Xenia mainline
// XeEdramOffsetBytes) to find the pixel, sample and half it holds and writes those bits:
//   tile = (sy / 16) * pitch_tiles + sx / tile_w; dword = (sy % 16) * tile_w + sx % tile_w,
//   doubled for 64 bpp (two dwords per sample, the low one first); tile_w = 80 >> is64bpp.
// Samples in the sample grid (PARITY_EDRAM_SAMPLE_ORDER, open question 2):
//   0 mainline: sx = (x << 1) + ((s >> 1) & 1), sy = (y << 1) + (s & 1)
//   1 canary:   sx = ((x & ~1) << 1) | (x & 1) | ((s & 1) << 1), sy = ((y & ~1) << 1) | (y & 1) | (s & 2)
// 64-bpp layout (PARITY_EDRAM_64BPP_LAYOUT, open question 3): 0 = Xenia's 40x16 samples per tile.
// Sources (PARITY_EDRAM_SOURCE): 0 k_16_16 through the RG16_UINT view (R low); 1 k_16_16_16_16
// held as RGBA32F s * 2^-15 (clamped to the encode's range, as the blender's re-encode does);
// 2 k_8_8_8_8 held as RGBA8 (R in bits 0-7); 3 D24S8, the stored word (D24 << 8) | stencil, in a
// depth tile whose two 40-column halves are swapped relative to colour (X1, xenos.h: "40x16-sample
// halves of each tile are swapped"); 4 k_32_FLOAT held as R32F (the float's bits). Samples outside
// the surface (pitch padding) are 0. 5 k_2_10_10_10_FLOAT held as RGBA32F 7e3 values (R bits
// 0-9, G 10-19, B 20-29, 2-bit A 30-31).
#ifndef PARITY_EDRAM_SOURCE
#define PARITY_EDRAM_SOURCE 0
#endif
#ifndef PARITY_EDRAM_MSAA4
#define PARITY_EDRAM_MSAA4 0
#endif
#ifndef PARITY_EDRAM_WIDTH
#define PARITY_EDRAM_WIDTH 80u
#define PARITY_EDRAM_HEIGHT 16u
#define PARITY_EDRAM_PITCH_TILES 1u
#endif
#ifndef PARITY_EDRAM_IS64
#define PARITY_EDRAM_IS64 0u
#endif
#ifndef PARITY_EDRAM_SAMPLE_ORDER
#define PARITY_EDRAM_SAMPLE_ORDER 0
#endif
#ifndef PARITY_EDRAM_64BPP_LAYOUT
#define PARITY_EDRAM_64BPP_LAYOUT 0
#endif
#ifndef PARITY_HOST_SAMPLE_0
#define PARITY_HOST_SAMPLE_0 0
#define PARITY_HOST_SAMPLE_1 1
#define PARITY_HOST_SAMPLE_2 2
#define PARITY_HOST_SAMPLE_3 3
#endif
#if PARITY_EDRAM_64BPP_LAYOUT != 0
#error "unknown 64-bpp EDRAM tile layout"
#endif

#if PARITY_EDRAM_SOURCE == 5
#include "float7e3.glsl"
#endif
#if PARITY_EDRAM_SOURCE == 3
#include "../common/depth24.glsl"
#if PARITY_EDRAM_MSAA4
layout(binding = 0) uniform sampler2DMS uSurface;
layout(binding = 1) uniform usampler2DMS uStencil;
#else
layout(binding = 0) uniform sampler2D uSurface;
layout(binding = 1) uniform usampler2D uStencil;
#endif
#elif PARITY_EDRAM_SOURCE == 0 && PARITY_EDRAM_MSAA4
layout(binding = 0) uniform usampler2DMS uSurface;
#elif PARITY_EDRAM_SOURCE == 0
layout(binding = 0) uniform usampler2D uSurface;
#elif PARITY_EDRAM_MSAA4
layout(binding = 0) uniform sampler2DMS uSurface;
#else
layout(binding = 0) uniform sampler2D uSurface;
#endif
layout(location = 0) out uint oDword;

// Low and high dword of one stored sample (the high one only for 64 bpp).
uvec2 storedSample(ivec2 p, int hostSample) {
#if PARITY_EDRAM_SOURCE == 0
  uvec2 rg = texelFetch(uSurface, p, hostSample).xy & 0xFFFFu;
  return uvec2(rg.x | (rg.y << 16), 0u);
#elif PARITY_EDRAM_SOURCE == 1
  vec4 f = texelFetch(uSurface, p, hostSample);
  uvec4 s = uvec4(ivec4(clamp(roundEven(f * 32768.0), vec4(-32767.0), vec4(32767.0)))) & 0xFFFFu;
  return uvec2(s.x | (s.y << 16), s.z | (s.w << 16));
#elif PARITY_EDRAM_SOURCE == 4
  return uvec2(floatBitsToUint(texelFetch(uSurface, p, hostSample).x), 0u);
#elif PARITY_EDRAM_SOURCE == 5
  vec4 v = texelFetch(uSurface, p, hostSample);
  uint a = uint(clamp(v.a, 0.0, 1.0) * 3.0 + 0.5);
  return uvec2(parityX360Encode7e3(v.r) | (parityX360Encode7e3(v.g) << 10) | (parityX360Encode7e3(v.b) << 20) | (a << 30),
               0u);
#elif PARITY_EDRAM_SOURCE == 3
  uint d24 = parityDepthToD24(texelFetch(uSurface, p, hostSample).x);
  return uvec2((d24 << 8) | (texelFetch(uStencil, p, hostSample).x & 255u), 0u);
#else
  uvec4 b = uvec4(roundEven(clamp(texelFetch(uSurface, p, hostSample), 0.0, 1.0) * 255.0));
  return uvec2(b.x | (b.y << 8) | (b.z << 16) | (b.w << 24), 0u);
#endif
}

int hostSampleOf(uint guestSample) {
  const int host[4] = int[4](PARITY_HOST_SAMPLE_0, PARITY_HOST_SAMPLE_1, PARITY_HOST_SAMPLE_2, PARITY_HOST_SAMPLE_3);
  return host[guestSample & 3u];
}

void main() {
  const uint tileWidth = 80u >> PARITY_EDRAM_IS64;
  uint dword = uint(gl_FragCoord.x), tile = uint(gl_FragCoord.y);
  uint inTile = dword >> PARITY_EDRAM_IS64, upper = dword & PARITY_EDRAM_IS64;
  uint column = inTile % tileWidth;
#if PARITY_EDRAM_SOURCE == 3
  column = column >= 40u ? column - 40u : column + 40u;  // depth: the tile's halves swapped
#endif
  uint sx = (tile % PARITY_EDRAM_PITCH_TILES) * tileWidth + column;
  uint sy = (tile / PARITY_EDRAM_PITCH_TILES) * 16u + inTile / tileWidth;
#if PARITY_EDRAM_MSAA4 && PARITY_EDRAM_SAMPLE_ORDER == 1
  uint x = ((sx >> 2) << 1) | (sx & 1u), y = ((sy >> 2) << 1) | (sy & 1u);
  uint s = ((sx >> 1) & 1u) | (sy & 2u);
#elif PARITY_EDRAM_MSAA4
  uint x = sx >> 1, y = sy >> 1;
  uint s = ((sx & 1u) << 1) | (sy & 1u);
#else
  uint x = sx, y = sy, s = 0u;
#endif
  if (x >= PARITY_EDRAM_WIDTH || y >= PARITY_EDRAM_HEIGHT) {
    oDword = 0u;
    return;
  }
  uvec2 v = storedSample(ivec2(x, y), hostSampleOf(s));
  oDword = upper == 0u ? v.x : v.y;
}
