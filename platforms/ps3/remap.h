// RSX texture formats and the texture remap word (P2, P4).
//
// Remap encoding (color_utils.h L157-185): bits 0-7 are input selectors for the outputs
// (A, R, G, B), 2 bits each (0 = A, 1 = R, 2 = G, 3 = B); bits 8-15 the output control of
// (A, R, G, B), 2 bits each (0 = ZERO, 1 = ONE, 2 = REMAP); bit 16 the order (XYXY = 0,
// XXXY = 1). Identity is 0xAAE4. Channels here are ordered [A, R, G, B], which is also the
// memory order of an A8R8G8B8 texel (big-endian 0xAARRGGBB).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

#include "platforms/common/diagnostics.h"

namespace parity::platforms::ps3 {

// CELL_GCM_TEXTURE_* (gcm_enums.h L151, L162-169); LN and UN flags are OR-ed into the format.
inline constexpr uint8_t kTextureA8R8G8B8 = 0x85;
inline constexpr uint8_t kTextureY16X16 = 0x95;
inline constexpr uint8_t kTextureFlagLN = 0x20;  // linear layout
inline constexpr uint8_t kTextureFlagUN = 0x40;  // unnormalised coordinates

inline constexpr uint32_t kRemapIdentity = 0xAAE4;  // RSX_TEXTURE_REMAP_IDENTITY
inline constexpr uint32_t kRemapBarg = 0xAA93;      // A<-B, R<-A, G<-R, B<-G: reads depth as R = D_hi (P4)

enum class RemapFrom : uint8_t { A = 0, R = 1, G = 2, B = 3 };
enum class RemapOut : uint8_t { Zero = 0, One = 1, Remap = 2 };
enum class RemapOrder : uint8_t { XYXY = 0, XXXY = 1 };

// CELL_GCM_REMAP_MODE(order, inA, inR, inG, inB, outA, outR, outG, outB).
uint32_t makeRemap(RemapOrder order, RemapFrom inA, RemapFrom inR, RemapFrom inG, RemapFrom inB,
                   RemapOut outA = RemapOut::Remap, RemapOut outR = RemapOut::Remap, RemapOut outG = RemapOut::Remap,
                   RemapOut outB = RemapOut::Remap);

// Channels indexed [A, R, G, B].
using Argb = std::array<float, 4>;
inline constexpr int kA = 0, kR = 1, kG = 2, kB = 3;

// Memory bytes of one A8R8G8B8 texel, [A, R, G, B] at ascending addresses.
using Argb8Bytes = std::array<uint8_t, 4>;

// Host storage of every A8R8G8B8 surface the PS3 layer emulates, packed16x2 colour and the
// depth-as-ARGB8 bitcast alike: an RGBA8 texel whose two 16-bit words are the console's 16-bit
// halves, little-endian. So the host's RG16 view of the texel is the Y16_X16 view (P2: the
// typeless copy's 16-bit swap is folded into the storage), and host (r, g, b, a) hold console
// (R, A, B, G). One convention for colour and depth, so that a shader or a readback finds
// console channel A in the same host channel whichever surface it reads.
inline constexpr std::array<int, 4> kHostChannelOfConsole = {1, 0, 3, 2};  // indexed [A, R, G, B]
// Host RGBA8 bytes (r, g, b, a) of the console texel, and back.
std::array<uint8_t, 4> hostTexelOfArgb8(const Argb8Bytes& console);
Argb8Bytes argb8OfHostTexel(const std::array<uint8_t, 4>& host);
// A host colour write mask (bits r, g, b, a = 1, 2, 4, 8) as console mask bits (A, R, G, B =
// 8, 1, 2, 4, the kWrite* bits of packed16.h), and back.
uint8_t consoleWriteMaskOfHost(uint8_t hostMask);
uint8_t hostWriteMaskOfConsole(uint8_t consoleMask);

// What the shader sees, (r, g, b, a).
struct Rgba {
  float r = 0, g = 0, b = 0, a = 0;
};

// Applies a remap to a fetched texel; returns the outputs indexed [A, R, G, B].
Argb applyRemap(uint32_t remap, const Argb& in);
Rgba toRgba(const Argb& argb);

// The input channel ([A, R, G, B] index) feeding output `out` when its control is REMAP, else -1.
int remapSource(uint32_t remap, int out);

// Y16_X16 remap rewrite (RSXTexture.cpp L269-302): the low byte 0xE4 becomes 0x66 (R-G-R-G; 0x56,
// R-R-R-G, when the order bit is XXXY), 0x4E becomes 0x99 (0xA9), 0xEE becomes 0xAA, 0x44 becomes
// 0x55. Other low bytes "crash the system": nullopt, and E_Y16X16_REMAP_INVALID when `out` is
// given. [inferred] the "override" bit that selects 0x56 / 0xA9 is the order bit 16 (XXXY).
std::optional<uint32_t> rewriteY16X16Remap(uint32_t remap, std::string_view texture = {}, DiagnosticList* out = nullptr);

}  // namespace parity::platforms::ps3
