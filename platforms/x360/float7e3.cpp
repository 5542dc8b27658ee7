#include "platforms/x360/float7e3.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace parity::platforms::x360 {

uint32_t encodeFloat7e3(float value) {
  uint32_t f = std::bit_cast<uint32_t>(value);
  // Negative values (sign bit set) and NaN store 0; 31.875 (0x41FF0000) and above saturate.
  if (std::isnan(value) || (f & 0x80000000u) != 0) return 0;
  f = std::min(f, 0x41FF0000u);
  uint32_t rebased;
  if (f < 0x3E800000u) {
    // Below 0.25 (7e3's smallest normal): a denormal, the mantissa with its implicit 1 shifted
    // right by how far the exponent is below 2^-2 (0 becomes 0).
    const uint32_t shift = 125u - (f >> 23);
    rebased = shift >= 32 ? 0 : (0x800000u | (f & 0x7FFFFFu)) >> shift;
  } else {
    rebased = f - 0x3E000000u;  // exponent bias 127 -> 3: subtract 124 << 23
  }
  // 23 -> 7 mantissa bits, round half to even.
  return ((rebased + 0x7FFFu + ((rebased >> 16) & 1u)) >> 16) & 0x3FFu;
}

float decodeFloat7e3(uint32_t bits) {
  bits &= 0x3FFu;
  uint32_t mantissa = bits & 0x7Fu, exponent = bits >> 7;
  if (bits == 0) return 0.0f;
  if (exponent == 0) {
    // Denormal: value = mantissa / 128 * 2^-2; normalise it into an fp32.
    const int lead = std::countl_zero(mantissa) - (32 - 7);  // zeros above the leading 1 in 7 bits
    exponent = uint32_t(1 - lead);
    mantissa = (mantissa << (lead + 1)) & 0x7Fu;
    return std::bit_cast<float>(((exponent + 124u - 1u) << 23) | (mantissa << 16));
  }
  return std::bit_cast<float>(((exponent + 124u) << 23) | (mantissa << 16));
}

float quantiseFloat7e3(float value) { return decodeFloat7e3(encodeFloat7e3(value)); }

uint32_t encodeUnorm2(float value) {
  const float a = std::isnan(value) ? 0.0f : std::clamp(value, 0.0f, 1.0f);
  return uint32_t(a * 3.0f + 0.5f);
}

uint32_t packFloat7e3x3Unorm2(const std::array<float, 4>& rgba) {
  return encodeFloat7e3(rgba[0]) | encodeFloat7e3(rgba[1]) << 10 | encodeFloat7e3(rgba[2]) << 20 |
         encodeUnorm2(rgba[3]) << 30;
}

std::array<float, 4> unpackFloat7e3x3Unorm2(uint32_t word) {
  return {decodeFloat7e3(word), decodeFloat7e3(word >> 10), decodeFloat7e3(word >> 20), float(word >> 30) / 3.0f};
}

std::vector<uint32_t> encodeFloat7e3Image(std::string_view target, std::span<const float> rgba, DiagnosticList& out) {
  std::vector<uint32_t> words;
  uint32_t clamped = 0;
  for (std::size_t i = 0; i + 3 < rgba.size(); i += 4) {
    bool outside = false;
    for (std::size_t c = 0; c < 3; ++c) outside = outside || !(rgba[i + c] >= 0.0f && rgba[i + c] <= kFloat7e3Max);
    clamped += outside ? 1 : 0;
    words.push_back(packFloat7e3x3Unorm2({rgba[i], rgba[i + 1], rgba[i + 2], rgba[i + 3]}));
  }
  if (clamped) {
    const std::string name(target);
    DiagnosticSite site;
    site.count = clamped;
    out.report("W_FLOAT7E3_RANGE_CLAMP", {name},
               std::to_string(clamped) + " pixel(s) of " + name +
                   " hold a colour outside k_2_10_10_10_FLOAT's [0, 31.875] (or NaN): stored as 0 below, 31.875 above (X2)",
               site);
  }
  return words;
}

}  // namespace parity::platforms::x360
