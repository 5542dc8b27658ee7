// Light index packing of light-indexed deferred rendering (Trebilco 2008, §"Light Index
// Packing"): what each scheme writes, what the blender makes of it, and how the forward pass
// unpacks it. The unpack functions mirror shaders/light_indexed/lidr_unpack.glsl operation for
// operation (fp32), so the tests can hold both against plain integer bit logic.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace parity::techniques {

enum class LidrPacking { Sort, Max, Bits };

// One row of the paper's bit-packing table: a light volume writes `channels` 8-bit channels (R, RG,
// RGBA or two RGBA8 targets), each holding chunkBits() bits of an `indexBits`-bit index, so that
// overlapsPerGroup() indices fit. The 16-overlap rows take `groups` = 2 such sets of targets, the
// second for the lights after the first set is full (the stencil, as in the MAX scheme: two
// passes of the light volumes). 16-bit indices (65535 lights) are read as two 8-bit halves that
// address a 256 x 256 light table, as the paper advises.
struct BitPackingLayout {
  uint32_t channels = 4;
  uint32_t indexBits = 8;
  uint32_t groups = 1;
  uint32_t chunkBits() const { return indexBits / channels; }
  uint32_t overlapsPerGroup() const { return 8 / chunkBits(); }
  uint32_t overlaps() const { return groups * overlapsPerGroup(); }
  uint32_t maxLights() const { return (1u << indexBits) - 1; }  // index 0 is the null light
  uint32_t targetsPerGroup() const { return (channels + 3) / 4; }
  uint32_t targets() const { return groups * targetsPerGroup(); }
  float blendConstant() const { return 1.0f / static_cast<float>(1u << chunkBits()); }
  std::string label() const;  // "4x255": overlaps x scene lights
};

// Every row of the paper's table: 2, 4, 8, 16 overlaps of 15 lights; 1, 2, 4, 8, 16 of 255;
// 1, 2, 4, 8 of 65535.
const std::vector<BitPackingLayout>& bitPackingRows();
// The row with that label ("4x255"), or null.
const BitPackingLayout* findBitPackingRow(const std::string& label);

constexpr uint32_t kMaxUnpackedIndices = 16;
using UnpackedIndices = std::array<uint32_t, kMaxUnpackedIndices>;
// Up to four RGBA8 targets: target A's RGBA, then B's, C's, D's. Group g's channels start at
// g * targetsPerGroup() * 4.
using ChannelBytes = std::array<uint8_t, 16>;

// Bits: the colour a light volume outputs for `index` (each chunk in the channel's top bits), as
// bytes in group 0's channels; the shader outputs byte / 255.
ChannelBytes bitPackingChunks(const BitPackingLayout& layout, uint32_t index);
// Bits: the channel bytes after blending the lights in draw order (dst = src + dst * 2^-chunk),
// the first overlapsPerGroup() into group 0, the next into group 1, writes beyond overlaps() held
// back by the stencil.
ChannelBytes simulateBitPacking(const BitPackingLayout& layout, const std::vector<uint32_t>& drawOrder);
// Bits: the paper's float unpacking (ceil(packed * 254.5), shift, floor, dot), per group, oldest
// light first; for 16-bit indices the dot is taken per index byte (the two table coordinates).
UnpackedIndices unpackBitsPaper(const BitPackingLayout& layout, const ChannelBytes& bytes);
// Bits: the same by integer shifts and masks, for checking.
UnpackedIndices unpackBitsInteger(const BitPackingLayout& layout, const ChannelBytes& bytes);

// Max: the RGBA bytes after the two MAX-blend passes with the stencil letting the first two
// lights into red/green and the rest into blue/alpha.
std::array<uint8_t, 4> simulateMaxPacking(const std::vector<uint32_t>& drawOrder);
// Max: Index1 = R, Index2 = 255 - G unless equal to Index1 (or R is 0), Index3 = B,
// Index4 = 255 - A unless equal to Index3 (or B is 0); 0 where ignored.
UnpackedIndices unpackMax(const std::array<uint8_t, 4>& rgba);

// CPU sorting: lights (scene order, the first maxLights) placed into four arrays, each light in
// the first array where its bounding sphere meets no other light's; `unplaced` did not fit.
struct ChannelSort {
  std::array<std::vector<uint32_t>, 4> channels;  // scene light indices
  std::vector<uint32_t> unplaced;
};
ChannelSort sortLightsIntoChannels(const std::vector<scene::Light>& lights, uint32_t maxLights = 255);

}  // namespace parity::techniques
