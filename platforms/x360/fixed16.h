// Xenos k_16_16 / k_16_16_16_16 colour targets: signed fixed point with range -32...32 (X2).
//
// Each component is a two's-complement int16 s with value s * 32/32767, so 0x7FFF = +32 and
// 0x8001 = -32. Components are packed low half first (R in bits 0-15, G in 16-31; B and A the
// same way in the second dword of a 64-bpp sample). The encode scales the shader output by
// 2^color_exp_bias, turns NaN into 0, clamps to [-32, 32] and rounds half away from zero
// (Xenia's interlock path, SPIR-V and DXBC translators).
//
// Arithmetic is fp32 in the order the pack gives, so the GPU path can evaluate the same
// expressions and compare bit for bit.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "platforms/common/diagnostics.h"
#include "platforms/common/platform.h"
#include "platforms/common/platform_params.h"

namespace parity::platforms::x360 {

inline constexpr float kFixed16Range = 32.0f;          // X2: "Fixed point -32...32"
inline constexpr float kFixed16Scale = 32767.0f / 32.0f;  // 1023.96875, exact in fp32

// c * 2^bias (exact for the powers of two a 6-bit signed field allows).
float applyExpBias(float value, int expBias);

struct Fixed16Encoded {
  int16_t value = 0;
  bool clamped = false;  // |v * 2^bias| > 32
  bool wasNaN = false;   // NaN stored as 0 ("NaN to 0, not to -32")
};

// X2 encode: c' = c * 2^color_exp_bias; c'' = clamp(isnan(c') ? 0 : c', -32, 32);
// s = trunc(c'' * 32767/32 + (c'' < 0 ? -0.5 : +0.5)).
Fixed16Encoded encodeFixed16(float shaderOutput, int colorExpBias = 0);
// X2 decode: s * 32/32767, unclamped (0x8000 gives -32.000977). fp32, (s * 32) / 32767.
float decodeFixed16(int16_t s);

// X2 blending (ADD, factors ONE): the blender reads the stored destination, which holds a
// clamped fixed-point value, adds the shader output and stores the encode of the sum, clamped
// again. So every blend clamps: 20 + 20 stores +32, and a further -20 then gives 12, not 20.
Fixed16Encoded blendAddFixed16(int16_t destination, float shaderOutput, int colorExpBias = 0);

// Bits: R in bits 0-15, G in 16-31 (Xenia bitFieldInsert(r, g, 16, 16)).
uint32_t packFixed16x2(int16_t r, int16_t g);
std::array<int16_t, 2> unpackFixed16x2(uint32_t word);
// 64 bpp: R, G in the low dword; B, A in the high dword.
uint64_t packFixed16x4(int16_t r, int16_t g, int16_t b, int16_t a);
std::array<int16_t, 4> unpackFixed16x4(uint64_t word);

// X2 (2): ways an emulator stores a k_16_16 target on a host (Xenia's options). The GPU path
// of this harness is always Snorm16Div32-like (kGpuK16HostStorage): k_16_16 as RG16_SNORM whose
// bits are the guest int16, k_16_16_16_16 as RGBA32F s * 2^-15, both the value divided by 32.
enum class K16HostStorage : uint8_t {
  Snorm16Div32 = 0,  // RG16_SNORM, shader output x 2^(bias-5); bits equal guest int16
  Snorm16Clamp1,     // RG16_SNORM without the /32: range truncated to -1..1, blending correct inside it
  Interlock,         // fragment-shader-interlock / compute EDRAM: exact encode, decode and blending
};
inline constexpr K16HostStorage kGpuK16HostStorage = K16HostStorage::Snorm16Div32;

// X2 (2), host storage on the GPU path: the factor the host shader multiplies the guest output
// by before writing RG16_SNORM. With Snorm16Div32 it is 2^(bias - 5), so the host SNORM bits
// equal the guest int16 bits; the resolve then folds +5 back into its exponent bias.
float hostOutputScale(int colorExpBias, K16HostStorage storage);
int hostResolveExpBiasFold(K16HostStorage storage);

// X2 (3) aliasing round trip: through an SNORM float view 0x8000 becomes 0x8001 (SNORM has two
// representations of -1), which is why Xenia transfers k_16_16 through R16G16_UINT, and the GPU
// path reads k_16_16 surfaces through an RG16_UINT view (GpuTargets).
uint16_t transferThroughSnorm16(uint16_t word);

// --- Rules (X2 (4)) ---------------------------------------------------------------------------

// Encodes two-channel shader outputs (r, g interleaved) for `target` and reports
// W_FIXED16_RANGE_CLAMP / W_FIXED16_NAN with pixel counts, and W_FIXED16_PRECISION when every
// output lies in [0, 1] with bias 0.
std::vector<uint32_t> encodeFixed16x2Image(std::string_view target, std::span<const float> rg, int colorExpBias,
                                           DiagnosticList& out);

// W_FIXED16_PRECISION for a shader whose outputs span [minOutput, maxOutput].
void checkFixed16OutputRange(std::string_view target, float minOutput, float maxOutput, int colorExpBias,
                             DiagnosticList& out);

// W_FIXED16_MULT_BLEND: DEST_COLOR / SRC_COLOR factors while the host divides by 32.
void checkFixed16Blend(std::string_view target, const BlendState& blend, K16HostStorage storage, DiagnosticList& out);

}  // namespace parity::platforms::x360
