#include "platforms/x360/fixed16.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace parity::platforms::x360 {

float applyExpBias(float value, int expBias) { return std::ldexp(value, expBias); }

Fixed16Encoded encodeFixed16(float shaderOutput, int colorExpBias) {
  Fixed16Encoded e;
  float c = applyExpBias(shaderOutput, colorExpBias);
  if (std::isnan(c)) {
    e.wasNaN = true;
    c = 0.0f;
  }
  if (c > kFixed16Range || c < -kFixed16Range) e.clamped = true;
  c = std::clamp(c, -kFixed16Range, kFixed16Range);
  float t = c * kFixed16Scale + (c < 0.0f ? -0.5f : 0.5f);
  e.value = static_cast<int16_t>(std::trunc(t));
  return e;
}

float decodeFixed16(int16_t s) { return static_cast<float>(s) * 32.0f / 32767.0f; }

Fixed16Encoded blendAddFixed16(int16_t destination, float shaderOutput, int colorExpBias) {
  return encodeFixed16(decodeFixed16(destination) + applyExpBias(shaderOutput, colorExpBias), 0);
}

uint32_t packFixed16x2(int16_t r, int16_t g) { return uint32_t(uint16_t(r)) | uint32_t(uint16_t(g)) << 16; }

std::array<int16_t, 2> unpackFixed16x2(uint32_t word) {
  return {static_cast<int16_t>(word & 0xFFFFu), static_cast<int16_t>(word >> 16)};
}

uint64_t packFixed16x4(int16_t r, int16_t g, int16_t b, int16_t a) {
  return uint64_t(packFixed16x2(r, g)) | uint64_t(packFixed16x2(b, a)) << 32;
}

std::array<int16_t, 4> unpackFixed16x4(uint64_t word) {
  auto lo = unpackFixed16x2(static_cast<uint32_t>(word));
  auto hi = unpackFixed16x2(static_cast<uint32_t>(word >> 32));
  return {lo[0], lo[1], hi[0], hi[1]};
}

float hostOutputScale(int colorExpBias, K16HostStorage storage) {
  // snorm16_render_target_full_range: "Remap from -32...32 to -1...1 by dividing the output
  // values by 32" (X2 (2)).
  return std::ldexp(1.0f, storage == K16HostStorage::Snorm16Div32 ? colorExpBias - 5 : colorExpBias);
}

int hostResolveExpBiasFold(K16HostStorage storage) { return storage == K16HostStorage::Snorm16Div32 ? 5 : 0; }

uint16_t transferThroughSnorm16(uint16_t word) {
  // SNORM decode max(s/32767, -1), then encode round(f * 32767).
  float f = std::max(static_cast<float>(static_cast<int16_t>(word)) / 32767.0f, -1.0f);
  return static_cast<uint16_t>(static_cast<int16_t>(std::lround(f * 32767.0f)));
}

std::vector<uint32_t> encodeFixed16x2Image(std::string_view target, std::span<const float> rg, int colorExpBias,
                                           DiagnosticList& out) {
  std::vector<uint32_t> words;
  words.reserve(rg.size() / 2);
  uint32_t clampedPixels = 0, nanPixels = 0;
  float lo = std::numeric_limits<float>::infinity(), hi = -std::numeric_limits<float>::infinity();
  for (std::size_t i = 0; i + 1 < rg.size(); i += 2) {
    Fixed16Encoded r = encodeFixed16(rg[i], colorExpBias);
    Fixed16Encoded g = encodeFixed16(rg[i + 1], colorExpBias);
    clampedPixels += (r.clamped || g.clamped) ? 1 : 0;
    nanPixels += (r.wasNaN || g.wasNaN) ? 1 : 0;
    for (float v : {rg[i], rg[i + 1]}) {
      if (std::isnan(v)) continue;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
    words.push_back(packFixed16x2(r.value, g.value));
  }
  const std::string name(target);
  if (clampedPixels) {
    out.report("W_FIXED16_RANGE_CLAMP", {name},
               std::to_string(clampedPixels) + " pixel(s) of " + name + " exceed |v * 2^" + std::to_string(colorExpBias) +
                   "| > 32 and clamp to +-32 (k_16_16, X2)");
  }
  if (nanPixels) {
    out.report("W_FIXED16_NAN", {name},
               std::to_string(nanPixels) + " pixel(s) of " + name + " write NaN, stored as 0 (k_16_16, X2)");
  }
  if (lo <= hi) checkFixed16OutputRange(target, lo, hi, colorExpBias, out);
  return words;
}

void checkFixed16OutputRange(std::string_view target, float minOutput, float maxOutput, int colorExpBias,
                             DiagnosticList& out) {
  if (colorExpBias == 0 && minOutput >= 0.0f && maxOutput <= 1.0f) {
    const std::string name(target);
    out.report("W_FIXED16_PRECISION", {name},
               name + " writes only [0, 1] with color_exp_bias 0 to a -32...32 k_16_16 target: 1025 levels, "
                      "about 10 effective bits (X2)");
  }
}

void checkFixed16Blend(std::string_view target, const BlendState& blend, K16HostStorage storage, DiagnosticList& out) {
  if (!blend.enabled || storage != K16HostStorage::Snorm16Div32) return;
  auto multiplicative = [](BlendFactor f) {
    return f == BlendFactor::SrcColor || f == BlendFactor::OneMinusSrcColor || f == BlendFactor::DestColor ||
           f == BlendFactor::OneMinusDestColor;
  };
  if (multiplicative(blend.srcColor) || multiplicative(blend.dstColor) || multiplicative(blend.srcAlpha) ||
      multiplicative(blend.dstAlpha)) {
    const std::string name(target);
    out.report("W_FIXED16_MULT_BLEND", {name},
               name + " blends with SRC_COLOR/DEST_COLOR factors while the host stores k_16_16 as SNORM divided by "
                      "32: the result is wrong by a factor of 32 (X2)");
  }
}

}  // namespace parity::platforms::x360
