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
      {1, 8}, {2, 8}, {4, 8}, {8, 8},  // 1, 2, 4, 8 overlaps of 255 lights
      {1, 4}, {2, 4}, {4, 4},          // 2, 4, 8 overlaps of 15 lights
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
    ChannelBytes src = bitPackingChunks(layout, index);
    // Exact: the bits shifted out are zero while fewer than overlaps() lights were written.
    for (uint32_t c = 0; c < layout.channels; ++c) dst[c] = static_cast<uint8_t>(src[c] + (dst[c] >> layout.chunkBits()));
    ++written;
  }
  return dst;
}

UnpackedIndices unpackBitsPaper(const BitPackingLayout& layout, const ChannelBytes& bytes) {
  UnpackedIndices out{};
  const float numLights = static_cast<float>(1u << layout.indexBits);
  const float shift = 1.0f / static_cast<float>(1u << layout.chunkBits());
  float unpackConst[8] = {};
  float floorValues[8] = {};
  for (uint32_t c = 0; c < layout.channels; ++c) {
    unpackConst[c] = static_cast<float>(1u << (layout.chunkBits() * (c + 1))) / numLights;
    float packed = static_cast<float>(bytes[c]) / 255.0f;  // the texel as sampled
    floorValues[c] = std::ceil(packed * 254.5f);
  }
  for (uint32_t i = 0; i < layout.overlaps(); ++i) {
    float fraction[8];
    for (uint32_t c = 0; c < 8; ++c) {
      float packed = floorValues[c] * shift;
      floorValues[c] = std::floor(packed);
      fraction[c] = packed - floorValues[c];
    }
    // dot4(target A) + dot4(target B), in parity_math.glsl's order.
    float dotA = ((fraction[0] * unpackConst[0] + fraction[1] * unpackConst[1]) + fraction[2] * unpackConst[2]) +
                 fraction[3] * unpackConst[3];
    float dotB = ((fraction[4] * unpackConst[4] + fraction[5] * unpackConst[5]) + fraction[6] * unpackConst[6]) +
                 fraction[7] * unpackConst[7];
    float lightIndex = dotA + dotB;
    out[i] = static_cast<uint32_t>(lightIndex * numLights);
  }
  return out;
}

UnpackedIndices unpackBitsInteger(const BitPackingLayout& layout, const ChannelBytes& bytes) {
  UnpackedIndices out{};
  uint32_t b = layout.chunkBits(), mask = (1u << b) - 1;
  for (uint32_t i = 0; i < layout.overlaps(); ++i)
    for (uint32_t c = 0; c < layout.channels; ++c) out[i] |= ((bytes[c] >> (b * i)) & mask) << (b * c);
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
