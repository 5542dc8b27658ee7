// Xbox 360 EDRAM resolves (X3): the only way out of EDRAM.
//
// A resolve copies a rectangle of a surface into a texture, converting each sample:
//   1. unpack to float (k_16_16: s * 32/32767, clamped below at -32; mainline Xenia at -1),
//   2. when averaging (copy_sample_select >= k01), sum 2 or 4 samples and fold 0.5 per doubling
//      into the factor,
//   3. multiply by 2^copy_dest_exp_bias,
//   4. pack to the destination format: unsigned k_16_16 = uint(saturate(f) * 65535 + 0.5), R low;
//      a signed k_16_16 destination follows the signed-resolve parameter (open question 1).
// Rectangles have 8x8-pixel granularity; packed mips (< 32x32) cannot be a destination; depth
// resolves do no conversion, averaging or exponent bias.
//
// The three ways to carry a [0, 1] DSF value through k_16_16 (paths A, B and C of X3 (3)) are
// modelled end to end, with their effective precision (log2 of the levels actually reachable).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "platforms/common/diagnostics.h"
#include "platforms/common/platform_params.h"
#include "platforms/x360/edram.h"

namespace parity::platforms::x360 {

// RB_COPY_DEST_INFO.copy_dest_format: the texture ColorFormat codes a resolve can write (subset;
// values as in xenos.h ColorFormat).
enum class ColorFormat : uint8_t {
  k_8_8_8_8 = 6,
  k_16_16 = 25,
  k_16_16_16_16 = 26,
};

// Texture-fetch format codes of the EDRAM-range variants (X2: "Not usable as a texture, also
// has -32...32 range").
inline constexpr uint32_t kTextureFormat_16_16_EDRAM = 13;
inline constexpr uint32_t kTextureFormat_16_16_16_16_EDRAM = 21;

// D3D format words (X3 (1)) and their fields. [inferred in the pack] bits 0-5 texture format,
// 6-7 endian, 8 tiled, 9-16 the four 2-bit sign fields (1 = signed).
inline constexpr uint32_t kD3DFMT_V16U16 = 0x2D20AB99;       // k_16_16, all four sign fields signed
inline constexpr uint32_t kD3DFMT_G16R16 = 0x2D200199;       // k_16_16, unsigned
inline constexpr uint32_t kD3DFMT_G16R16_EDRAM = 0x2D20AB8D;  // texture format 13
struct D3DFormatFields {
  uint32_t textureFormat = 0;
  uint32_t endian = 0;
  bool tiled = false;
  uint32_t signs[4] = {0, 0, 0, 0};  // x, y, z, w
};
D3DFormatFields decodeD3DFormatWord(uint32_t word);

// RB_COPY_DEST_INFO.copy_dest_number (xenos.h SurfaceNumberFormat).
enum class SurfaceNumberFormat : uint8_t {
  kUnsignedRepeatingFraction = 0,
  kSignedRepeatingFraction = 1,  // Microsoft-style: scale factor 2^(n-1) - 1
};

// copy_sample_select.
enum class CopySampleSelect : uint8_t { k0 = 0, k1, k2, k3, k01, k23, k0123 };

inline constexpr uint32_t kResolveAlignmentPixels = 8;  // X3: GPU_RESOLVE_ALIGNMENT
inline constexpr uint32_t kResolveMinMipSize = 32;      // X3: no resolve to packed mips

struct ResolveRect {
  int32_t x = 0, y = 0;
  uint32_t width = 0, height = 0;
};

struct ResolveRequest {
  ResolveRect rect;  // in surface pixels
  // Destination format; nullopt copies in the source's own format (no conversion requested).
  std::optional<ColorFormat> destFormat;
  SurfaceNumberFormat destNumber = SurfaceNumberFormat::kUnsignedRepeatingFraction;
  int destExpBias = 0;  // copy_dest_exp_bias, signed 6 bits
  CopySampleSelect sampleSelect = CopySampleSelect::k0;
  // Size of the destination mip level; 0 means the rectangle's size.
  uint32_t destMipWidth = 0, destMipHeight = 0;
};

// A surface as a port allocates what it resolves (X3): padded to the 8-pixel resolve granularity,
// so that a resolve of the whole surface copies the aligned rectangle (0, 0) - (padded width,
// padded height) and later passes use the visible region; the destination texture at least
// 32x32, so that it has no packed mip level. The request of that whole-surface resolve.
uint32_t resolveAlignedSize(uint32_t pixels);
ResolveRequest wholeSurfaceResolve(uint32_t width, uint32_t height);

// E_RESOLVE_ALIGNMENT, E_RESOLVE_PACKED_MIP, E_DEPTH_RESOLVE_CONVERT for one resolve.
void checkResolveRequest(const EdramSurface& source, const ResolveRequest& request, DiagnosticList& out);

// --- Per-component pipeline ---------------------------------------------------------------------

// Step 1: k_16_16 sample to float, max(s * 32/32767, clamp) (X2 range notes).
float unpackFixed16ForResolve(int16_t s, const PlatformParams& params = {});
// Steps 2-3: sum the selected samples and multiply by 2^bias / count (fp32, in that order).
float averageAndBias(std::span<const float> samples, int destExpBias);
// Step 4, unsigned: uint(saturate(f) * 65535 + 0.5) (XePackR16G16UNorm).
uint16_t packUnorm16(float f);
// Step 4, unsigned 8-bit destination: uint(saturate(f) * 255 + 0.5).
uint8_t packUnorm8(float f);

struct ResolvedComponent {
  float value = 0.0f;       // after averaging and exponent bias (before packing)
  uint16_t word = 0;        // destination bits
  bool signLost = false;    // negative value packed into an unsigned destination
  bool rangeClamped = false;  // |value| > 1 packed into a UNORM destination
};

// One k_16_16 component through steps 1-4 into a k_16_16 destination.
ResolvedComponent resolveFixed16Component(std::span<const int16_t> samples, int destExpBias,
                                          SurfaceNumberFormat destNumber, const PlatformParams& params = {});

// Texture fetch of a resolved k_16_16 texel (fetch constant sign fields and exp_adjust):
// unsigned word/65535; signed Microsoft-style max(s/32767, -1); both times 2^exp_adjust.
float fetchFixed16Unsigned(uint16_t word, int expAdjust = 0);
float fetchFixed16Signed(uint16_t word, int expAdjust = 0);

// --- Whole-surface resolve ------------------------------------------------------------------

struct ResolvedTexture {
  uint32_t width = 0, height = 0;
  ColorFormat format = ColorFormat::k_8_8_8_8;
  SurfaceNumberFormat number = SurfaceNumberFormat::kUnsignedRepeatingFraction;
  // One word per texel, row-major, components low first (k_8_8_8_8: R in bits 0-7; k_16_16: R in
  // bits 0-15; k_16_16_16_16: R, G in the low dword, B, A in the high dword).
  std::vector<uint64_t> texels;
};

// Resolves `request.rect` of a colour surface (k_8_8_8_8, k_16_16 or k_16_16_16_16) from EDRAM
// memory. Runs checkResolveRequest, and reports W_RESOLVE_SIGN_LOSS and W_RESOLVE_RANGE_CLAMP
// with texel counts. k_8_8_8_8 sources store R in bits 0-7 (the model's convention).
ResolvedTexture resolveSurface(const EdramMemory& edram, const EdramSurface& source, const ResolveRequest& request,
                               DiagnosticList& out, const PlatformParams& params = {});

// --- DSF paths A, B, C (X3 (3)) -----------------------------------------------------------------

struct DsfPathSpec {
  std::string_view name;
  std::string_view description;
  float shaderScale = 1.0f, shaderOffset = 0.0f;  // shader writes c = scale * v + offset
  int colorExpBias = 0;                           // RB_COLOR_INFO.color_exp_bias
  SurfaceNumberFormat destNumber = SurfaceNumberFormat::kUnsignedRepeatingFraction;
  int destExpBias = 0;       // copy_dest_exp_bias
  bool fetchSigned = false;  // texture fetch sign fields
  int fetchExpAdjust = 0;
  float sampleAdd = 0.0f, sampleMul = 1.0f;  // the sampling shader returns v' = (t + add) * mul
};

DsfPathSpec dsfPath(DsfResolvePath path);

struct DsfPathResult {
  int16_t edram = 0;           // int16 in EDRAM
  ResolvedComponent resolved;  // after the resolve
  float sampled = 0.0f;        // t, what the texture fetch returns
  float reconstructed = 0.0f;  // v', what the sampling shader hands on
};

DsfPathResult runDsfPath(const DsfPathSpec& path, float v, const PlatformParams& params = {});

struct PathPrecision {
  uint32_t levels = 0;  // distinct destination words reachable from v in [0, 1]
  double bits = 0.0;    // log2(levels)
  int roundedBits = 0;  // bits rounded to nearest: A = 10, B = 15, C = 16
};

PathPrecision dsfPathPrecision(const DsfPathSpec& path, const PlatformParams& params = {});

// W_RESOLVE_PRECISION when the path's rounded effective precision is below 16 bits.
void checkDsfPathPrecision(std::string_view target, const DsfPathSpec& path, DiagnosticList& out,
                           const PlatformParams& params = {});

}  // namespace parity::platforms::x360
