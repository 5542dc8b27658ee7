#include "techniques/light_indexed/lidr_packing.h"

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

namespace parity::techniques {

std::string BitPackingLayout::label() const {
  return std::to_string(overlaps()) + "x" + std::to_string(maxLights());
}

const std::vector<BitPackingLayout>& bitPackingRows() {
  static const std::vector<BitPackingLayout> rows = {
      {1, 8}, {2, 8}, {4, 8}, {8, 8}, {8, 8, 2},    // 1, 2, 4, 8, 16 overlaps of 255 lights
      {1, 4}, {2, 4}, {4, 4}, {4, 4, 2},            // 2, 4, 8, 16 overlaps of 15 lights
      {2, 16}, {4, 16}, {8, 16}, {16, 16},          // 1, 2, 4, 8 overlaps of 65535 lights
  };
  return rows;
}

const BitPackingLayout* findBitPackingRow(const std::string& label) {
  for (const BitPackingLayout& row : bitPackingRows())
    if (row.label() == label) return &row;
  return nullptr;
}

ChannelBytes bitPackingChunks(const BitPackingLayout& layout, uint32_t index) {
  ChannelBytes out{};
  uint32_t b = layout.chunkBits(), mask = (1u << b) - 1;
  for (uint32_t c = 0; c < layout.channels; ++c) out[c] = static_cast<uint8_t>(((index >> (b * c)) & mask) << (8 - b));
  return out;
}

ChannelBytes simulateBitPacking(const BitPackingLayout& layout, const std::vector<uint32_t>& drawOrder) {
  ChannelBytes dst{};
  uint32_t written = 0;
  for (uint32_t index : drawOrder) {
    if (written == layout.overlaps()) break;  // the stencil test fails from here on
    uint32_t base = (written / layout.overlapsPerGroup()) * layout.targetsPerGroup() * 4;
    ChannelBytes src = bitPackingChunks(layout, index);
    // Exact: the bits shifted out are zero while fewer than overlapsPerGroup() lights were written.
    for (uint32_t c = 0; c < layout.channels; ++c)
      dst[base + c] = static_cast<uint8_t>(src[c] + (dst[base + c] >> layout.chunkBits()));
    ++written;
  }
  return dst;
}

UnpackedIndices unpackBitsPaper(const BitPackingLayout& layout, const ChannelBytes& bytes) {
  UnpackedIndices out{};
  // Indices of more than 8 bits are read as two table coordinates of 8 bits each (the paper's
  // 256 x 256 light table); up to 8 bits, as the paper's listing with NUM_LIGHTS = 2^indexBits.
  const float tableSize = static_cast<float>(1u << std::min(layout.indexBits, 8u));
  const uint32_t b = layout.chunkBits();
  const float shift = 1.0f / static_cast<float>(1u << b);
  // unpackConst of channel c within a group, for the index byte its chunk lies in (chunks never
  // straddle a byte: chunkBits divides 8).
  float unpackLow[16] = {}, unpackHigh[16] = {};
  for (uint32_t c = 0; c < layout.channels; ++c) {
    uint32_t bitOffset = b * c, indexByte = bitOffset / 8;
    float k = static_cast<float>(1u << (bitOffset + b - 8 * indexByte)) / tableSize;
    (indexByte == 0 ? unpackLow : unpackHigh)[c] = k;
  }
  float floorValues[16] = {};
  for (uint32_t c = 0; c < 16; ++c) floorValues[c] = std::ceil((static_cast<float>(bytes[c]) / 255.0f) * 254.5f);
  const uint32_t tpg = layout.targetsPerGroup();
  for (uint32_t g = 0; g < layout.groups; ++g)
    for (uint32_t i = 0; i < layout.overlapsPerGroup(); ++i) {
      float low = 0.0f, high = 0.0f;
      for (uint32_t t = 0; t < tpg; ++t) {
        float fraction[4];
        for (uint32_t k = 0; k < 4; ++k) {
          float& f = floorValues[(g * tpg + t) * 4 + k];
          float packed = f * shift;
          f = std::floor(packed);
          fraction[k] = packed - f;
        }
        const float* lo = unpackLow + t * 4;
        const float* hi = unpackHigh + t * 4;
        // dot4 in parity_math.glsl's order.
        low += ((fraction[0] * lo[0] + fraction[1] * lo[1]) + fraction[2] * lo[2]) + fraction[3] * lo[3];
        high += ((fraction[0] * hi[0] + fraction[1] * hi[1]) + fraction[2] * hi[2]) + fraction[3] * hi[3];
      }
      out[g * layout.overlapsPerGroup() + i] =
          static_cast<uint32_t>(low * tableSize) + (static_cast<uint32_t>(high * tableSize) << 8);
    }
  return out;
}

UnpackedIndices unpackBitsInteger(const BitPackingLayout& layout, const ChannelBytes& bytes) {
  UnpackedIndices out{};
  uint32_t b = layout.chunkBits(), mask = (1u << b) - 1;
  for (uint32_t g = 0; g < layout.groups; ++g) {
    uint32_t base = g * layout.targetsPerGroup() * 4;
    for (uint32_t i = 0; i < layout.overlapsPerGroup(); ++i)
      for (uint32_t c = 0; c < layout.channels; ++c)
        out[g * layout.overlapsPerGroup() + i] |= ((bytes[base + c] >> (b * i)) & mask) << (b * c);
  }
  return out;
}

std::array<uint8_t, 4> simulateMaxPacking(const std::vector<uint32_t>& drawOrder) {
  std::array<uint8_t, 4> dst{};
  for (size_t i = 0; i < drawOrder.size(); ++i) {
    uint8_t index = static_cast<uint8_t>(drawOrder[i]), inverted = static_cast<uint8_t>(255 - drawOrder[i]);
    size_t pair = i < 2 ? 0 : 2;  // pass 1 lets two lights in, pass 2 the rest
    dst[pair] = std::max(dst[pair], index);
    dst[pair + 1] = std::max(dst[pair + 1], inverted);
  }
  return dst;
}

UnpackedIndices unpackMax(const std::array<uint8_t, 4>& rgba) {
  UnpackedIndices out{};
  uint32_t r = rgba[0], g = rgba[1], b = rgba[2], a = rgba[3];
  out[0] = r;
  out[1] = (r != 0 && 255 - g != r) ? 255 - g : 0;
  out[2] = b;
  out[3] = (b != 0 && 255 - a != b) ? 255 - a : 0;
  return out;
}

ChannelSort sortLightsIntoChannels(const std::vector<scene::Light>& lights, uint32_t maxLights) {
  ChannelSort sort;
  uint32_t n = std::min<uint32_t>(static_cast<uint32_t>(lights.size()), maxLights);
  for (uint32_t l = 0; l < n; ++l) {
    bool placed = false;
    for (std::vector<uint32_t>& channel : sort.channels) {
      bool overlaps = false;
      for (uint32_t other : channel) {
        // Bounding spheres (a spot's cone lies inside its sphere): conservative.
        float reach = lights[l].radius + lights[other].radius;
        glm::vec3 d = lights[l].position - lights[other].position;
        if (glm::dot(d, d) < reach * reach) {
          overlaps = true;
          break;
        }
      }
      if (!overlaps) {
        channel.push_back(l);
        placed = true;
        break;
      }
    }
    if (!placed) sort.unplaced.push_back(l);
  }
  return sort;
}

}  // namespace parity::techniques
