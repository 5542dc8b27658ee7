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

// One row of the paper's bit-packing table: `channels` 8-bit channels (up to two RGBA8 targets)
// hold overlaps() indices of `indexBits` bits, each split into chunkBits() bits per channel.
struct BitPackingLayout {
  uint32_t channels = 4;
  uint32_t indexBits = 8;
  uint32_t chunkBits() const { return indexBits / channels; }
  uint32_t overlaps() const { return 8 / chunkBits(); }
  uint32_t maxLights() const { return (1u << indexBits) - 1; }  // index 0 is the null light
  uint32_t targets() const { return channels > 4 ? 2 : 1; }
  float blendConstant() const { return 1.0f / static_cast<float>(1u << chunkBits()); }
  std::string label() const;  // "4x255": overlaps x scene lights
};

// The rows implemented: 1, 2, 4, 8 overlaps with 255 lights; 2, 4, 8 with 15 lights.
const std::vector<BitPackingLayout>& bitPackingRows();
// The row with that label ("4x255"), or null.
const BitPackingLayout* findBitPackingRow(const std::string& label);

constexpr uint32_t kMaxUnpackedIndices = 8;
using UnpackedIndices = std::array<uint32_t, kMaxUnpackedIndices>;
using ChannelBytes = std::array<uint8_t, 8>;  // target A's RGBA, then target B's RGBA

// Bits: the colour a light volume outputs for `index` (each chunk in the channel's top bits), as
// bytes; the shader outputs byte / 255.
ChannelBytes bitPackingChunks(const BitPackingLayout& layout, uint32_t index);
// Bits: the channel bytes after blending the lights in draw order (dst = src + dst * 2^-chunk),
// writes beyond overlaps() held back by the stencil as the technique does.
ChannelBytes simulateBitPacking(const BitPackingLayout& layout, const std::vector<uint32_t>& drawOrder);
// Bits: the paper's float unpacking (ceil(packed * 254.5), shift, floor, dot), oldest light first.
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
