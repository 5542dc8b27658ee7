// Unpacking of the light index texture, for the three packing schemes of Trebilco 2008
// (§"Light Index Packing"). Index 0 is the null light. Mirrored bit for bit on the CPU by
// techniques/light_indexed/lidr_packing.cpp (tests/technique_light_indexed_test.cpp checks both
// against integer bit logic over every table row).
#ifndef PARITY_LIDR_UNPACK_GLSL
#define PARITY_LIDR_UNPACK_GLSL
#include "parity_math.glsl"

#define LIDR_MAX_INDICES 16u

// An RGBA8 texel (k / 255 per channel) back to its bytes.
uvec4 lidrBytes(vec4 texel) { return uvec4(texel * 255.0 + 0.5); }

// CPU sorting: one index per channel, written directly (no unpacking).
uint lidrUnpackSort(vec4 texel, out uint indices[LIDR_MAX_INDICES]) {
  uvec4 b = lidrBytes(texel);
  uint n = 0u;
  for (uint c = 0u; c < 4u; ++c) {
    indices[c] = b[c];
    if (b[c] != 0u) ++n;
  }
  for (uint c = 4u; c < LIDR_MAX_INDICES; ++c) indices[c] = 0u;
  return n;
}

// Multi-pass MAX blend: pass 1 wrote (index, 1 - index) into red/green for the first two lights,
// pass 2 the same into blue/alpha for the rest. Index1 = red, Index2 = 1 - green (ignored if equal
// to Index1), Index3 = blue, Index4 = 1 - alpha (ignored if equal to Index3). The paper's list
// names blue for Index2 and green for Index3, which contradicts its own write step (index and
// 1 - index into red and green); the write step is followed here. A pair that no light wrote
// stays at its clear value 0, whose inverted channel would read as index 255: it is ignored when
// its plain channel is 0, the null light.
uint lidrUnpackMax(vec4 texel, out uint indices[LIDR_MAX_INDICES]) {
  uvec4 b = lidrBytes(texel);
  for (uint c = 0u; c < LIDR_MAX_INDICES; ++c) indices[c] = 0u;
  indices[0] = b.r;
  indices[1] = (b.r != 0u && 255u - b.g != b.r) ? 255u - b.g : 0u;
  indices[2] = b.b;
  indices[3] = (b.b != 0u && 255u - b.a != b.b) ? 255u - b.a : 0u;
  uint n = 0u;
  for (uint c = 0u; c < 4u; ++c)
    if (indices[c] != 0u) ++n;
  return n;
}

// Bit shifting (blend ONE, CONSTANT_COLOR with constant 2^-chunkBits): `channels` 8-bit channels
// (1, 2, 4, or 8 over two RGBA8 targets a and b) hold 8 / chunkBits overlapping indices of
// `indexBits` bits (4: 15 lights, 8: 255 lights), each split into chunkBits = indexBits /
// channels bits per channel; the oldest light ends in the lowest bits. The paper's float
// unpacking, generalised from its 4 x 2-bit listing (NUM_LIGHTS = 2^indexBits,
// unpackConst[c] = 2^(chunkBits (c + 1)) / NUM_LIGHTS, shift = 2^-chunkBits):
//   floorValues = ceil(packed * 254.5);
//   for each overlap i: packed = floorValues * shift; floorValues = floor(packed);
//                       lightIndex[i] = dot(packed - floorValues, unpackConst);
// lightIndex is index / NUM_LIGHTS (a light table coordinate); every step is exact in fp32.
// Returns the indices in write order, oldest first, zeros where fewer lights were written.
uint lidrUnpackBits(vec4 packedA, vec4 packedB, uint channels, uint indexBits, out uint indices[LIDR_MAX_INDICES]) {
  uint chunkBits = indexBits / channels;
  uint overlaps = 8u / chunkBits;
  // Powers of two from integer shifts: exact, where a driver's exp2 may approximate.
  float numLights = float(1u << indexBits);
  float shift = 1.0 / float(1u << chunkBits);
  vec4 unpackA = vec4(0.0), unpackB = vec4(0.0);
  for (uint c = 0u; c < channels; ++c) {
    float k = float(1u << (chunkBits * (c + 1u))) / numLights;
    if (c < 4u) unpackA[c] = k;
    else unpackB[c - 4u] = k;
  }
  vec4 floorA = ceil(packedA * 254.5), floorB = ceil(packedB * 254.5);
  uint n = 0u;
  for (uint i = 0u; i < LIDR_MAX_INDICES; ++i) {
    indices[i] = 0u;
    if (i >= overlaps) continue;
    vec4 pa = floorA * shift, pb = floorB * shift;
    floorA = floor(pa);
    floorB = floor(pb);
    float lightIndex = dot4(pa - floorA, unpackA) + dot4(pb - floorB, unpackB);
    indices[i] = uint(lightIndex * numLights);
    if (indices[i] != 0u) ++n;
  }
  return n;
}

// Every row of the paper's table, generalising lidrUnpackBits: `groups` sets of
// (channels + 3) / 4 RGBA8 targets (packed[0..3]); group 2 holds the lights written after group 1
// was full (the 16-overlap rows). Indices of 16 bits (65535 lights) are read, as the paper
// advises, as two 8-bit light table coordinates: the dot is taken once with the constants of
// the channels holding the low index byte and once with those of the high byte (a chunk never
// straddles a byte, chunkBits dividing 8), each exact in fp32; the index returned is
// low + 256 high, the texel (low, high) of a 256 x 256 table. Up to 8 bits this is
// lidrUnpackBits. Indices in write order per group, group 1 first.
uint lidrUnpackBitsRows(vec4 packed[4], uint channels, uint indexBits, uint groups, out uint indices[LIDR_MAX_INDICES]) {
  uint chunkBits = indexBits / channels;
  uint perGroup = 8u / chunkBits;
  uint targetsPerGroup = (channels + 3u) / 4u;
  float tableSize = float(1u << min(indexBits, 8u));
  float shift = 1.0 / float(1u << chunkBits);
  vec4 unpackLow[4], unpackHigh[4], floorValues[4];
  for (uint t = 0u; t < 4u; ++t) {
    unpackLow[t] = vec4(0.0);
    unpackHigh[t] = vec4(0.0);
    floorValues[t] = ceil(packed[t] * 254.5);
  }
  for (uint c = 0u; c < channels; ++c) {
    uint bitOffset = chunkBits * c, indexByte = bitOffset / 8u;
    float k = float(1u << (bitOffset + chunkBits - 8u * indexByte)) / tableSize;
    if (indexByte == 0u) unpackLow[c / 4u][c % 4u] = k;
    else unpackHigh[c / 4u][c % 4u] = k;
  }
  for (uint i = 0u; i < LIDR_MAX_INDICES; ++i) indices[i] = 0u;
  uint n = 0u;
  for (uint g = 0u; g < groups; ++g) {
    for (uint i = 0u; i < perGroup; ++i) {
      float low = 0.0, high = 0.0;
      for (uint t = 0u; t < targetsPerGroup; ++t) {
        uint target = g * targetsPerGroup + t;
        vec4 p = floorValues[target] * shift;
        floorValues[target] = floor(p);
        vec4 fraction = p - floorValues[target];
        low += dot4(fraction, unpackLow[t]);
        high += dot4(fraction, unpackHigh[t]);
      }
      uint index = uint(low * tableSize) + (uint(high * tableSize) << 8u);
      indices[g * perGroup + i] = index;
      if (index != 0u) ++n;
    }
  }
  return n;
}

#endif
