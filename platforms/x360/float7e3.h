// Xenos k_2_10_10_10_FLOAT colour targets: the "7e3" HDR format (X2's 32-bpp alternative to
// k_16_16_16_16). R, G and B are unsigned 10-bit floats, 3 exponent bits (bias 3) over 7
// mantissa bits, with denormals: values in [0, 31.875], 8 significant bits, normal from 0.25 up;
// alpha is 2-bit unorm. The conversions are Xenia's (after DirectXTex's): negative and NaN
// inputs store 0, inputs at or above 31.875 store 0x3FF, the rest round to the nearest 7e3 value,
// ties to even. Word layout: R in bits 0-9, G 10-19, B 20-29, A 30-31.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "platforms/common/diagnostics.h"

namespace parity::platforms::x360 {

inline constexpr float kFloat7e3Max = 31.875f;

uint32_t encodeFloat7e3(float value);   // -> 10 bits
float decodeFloat7e3(uint32_t bits);    // the low 10 bits -> value
float quantiseFloat7e3(float value);    // decode(encode(value))
uint32_t encodeUnorm2(float value);     // alpha: round(saturate(a) * 3)

uint32_t packFloat7e3x3Unorm2(const std::array<float, 4>& rgba);
std::array<float, 4> unpackFloat7e3x3Unorm2(uint32_t word);

// The words a k_2_10_10_10_FLOAT surface `target` stores for shader outputs (RGBA interleaved),
// reporting W_FLOAT7E3_RANGE_CLAMP with the count of pixels whose colour lies outside
// [0, kFloat7e3Max] or is NaN: what GpuTargets' 7e3 store pass counts on the GPU.
std::vector<uint32_t> encodeFloat7e3Image(std::string_view target, std::span<const float> rgba, DiagnosticList& out);

}  // namespace parity::platforms::x360
