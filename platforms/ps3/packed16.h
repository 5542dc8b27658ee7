// PS3: two 16-bit values packed into an A8R8G8B8 surface and read back as Y16_X16 (P2), and
// what goes wrong when such a packed target is blended, filtered, partially written or averaged
// (P3).
//
// Write [inferred in the pack]: X16 = round(x * 65535); the shader outputs A = hi/255,
// R = lo/255 (and Y into G, B); the ROP converts with round(c * 255). Memory holds the
// big-endian word 0xAARRGGBB, bytes [A, R, G, B].
// Read: a Y16_X16 view reads two big-endian 16-bit words, so .r = (A*256 + R)/65535 and
// .g = (G*256 + B)/65535; the default remap gives .b = .r, .a = .g. On a host the byte view is
// BGRA8 and the 16-bit view RG16; the typeless copy between them swaps the 16-bit halves of each
// 32-bit word (RPCS3 cs_shuffle_32_16).
//
// "Packedness" is metadata the harness adds (packed16x2); hardware-faithful emulation does
// nothing special, so the blend and filter models below reproduce the corruption.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "platforms/common/diagnostics.h"
#include "platforms/common/platform.h"
#include "platforms/ps3/remap.h"

namespace parity::platforms::ps3 {

// X16 = round(x * 65535) (x clamped to [0, 1]).
uint16_t quantizeUnorm16(float x);
// ROP float -> unorm8: round(c * 255) (c clamped to [0, 1]).
uint8_t ropUnorm8(float c);

// What the packing shader outputs for (x, y), indexed [A, R, G, B]: (hiX, loX, hiY, loY) / 255.
Argb packTwo16ShaderOutput(float x, float y);
// The bytes in memory after the ROP.
Argb8Bytes packTwo16InArgb8(float x, float y);
// Big-endian word 0xAARRGGBB.
uint32_t argb8Word(const Argb8Bytes& bytes);
// The two 16-bit values in memory order: X16 = A*256 + R, Y16 = G*256 + B.
std::array<uint16_t, 2> y16x16Words(const Argb8Bytes& bytes);

// Sampling the bytes through a Y16_X16 view with `remap` (nullopt for an invalid remap).
std::optional<Rgba> sampleY16X16(const Argb8Bytes& bytes, uint32_t remap = kRemapIdentity,
                                 std::string_view texture = {}, DiagnosticList* out = nullptr);
// Sampling the bytes through the A8R8G8B8 view: [A, R, G, B] / 255, then the remap.
Rgba sampleArgb8(const Argb8Bytes& bytes, uint32_t remap = kRemapIdentity);

// Host side: the BGRA8 texel as a little-endian u32 (0xAARRGGBB) turned into RG16 by swapping
// the 16-bit halves: R16 = 0xAARR, G16 = 0xGGBB.
std::array<uint16_t, 2> hostRg16FromBgra8(uint32_t hostBgra8Word);

// --- Filter trap (P2 (3)) -------------------------------------------------------------------

// Bilinear interpolation of two ARGB8 texels with weight w of the second, per channel, in fp32
// on normalised values (what the texture unit returns for the byte view).
Argb filterArgb8(const Argb8Bytes& t0, const Argb8Bytes& t1, float w);
// Decoding a 16-bit value from normalised (hi, lo) channels: rounding each byte first,
// floor(255 c + 0.5), or purely linear 65280 hi + 255 lo. In 16-bit units.
float decodePacked16RoundPerByte(float hi, float lo);
float decodePacked16Linear(float hi, float lo);
// Bilinear interpolation through the Y16_X16 view: a real 16-bit filter, in 16-bit units.
float filterY16(uint16_t v0, uint16_t v1, float w);

// --- Blending (P3 (3)) ------------------------------------------------------------------------

// Per-channel unorm8 blending of the bytes, as the ROP does on an A8R8G8B8 target:
// c = src * fs + dst * fd in fp32, then round(c * 255). Colour factors apply to R, G, B and
// alpha factors to A.
Argb8Bytes blendArgb8(const Argb8Bytes& src, const Argb8Bytes& dst, const BlendState& blend);

// --- Rules (P2 (4), P3 (4)) -------------------------------------------------------------------

// Colour write mask bits.
inline constexpr uint8_t kWriteR = 1, kWriteG = 2, kWriteB = 4, kWriteA = 8, kWriteAll = 15;

struct PackedTargetDraw {
  std::string target;
  bool packed16x2 = true;
  BlendState blend;
  uint8_t writeMask = kWriteAll;
  bool alphaTest = false;
};
// E_PACKED_BLEND, W_PACKED_PARTIAL_WRITEMASK (the mask splits A/R or G/B), E_PACKED_ALPHA_TEST
// (alpha test against a channel that holds the high byte of a 16-bit value).
void checkPackedTargetDraw(const PackedTargetDraw& draw, DiagnosticList& out);

// E_PACKED_MSAA_RESOLVE: averaging the samples of a packed target averages bytes.
void checkPackedResolve(std::string_view target, bool packed16x2, uint32_t samples, bool averaging, DiagnosticList& out);

struct PackedTextureRead {
  std::string texture;
  bool packed16x2 = true;
  uint8_t viewFormat = kTextureY16X16;  // kTextureA8R8G8B8 or kTextureY16X16, flags allowed
  Filter filter = Filter::Nearest;
  bool decodeRoundsPerByte = true;  // the shader rebuilds values with floor(255 c + 0.5) per byte
  uint32_t remap = kRemapIdentity;
  bool sourceIsRenderTarget = true;  // the data was rendered (host keeps it as BGRA8)
};
// W_PACKED_VIEW_MISMATCH, W_PACKED_FILTER, E_Y16X16_REMAP_INVALID, I_TYPELESS_COPY.
void checkPackedTextureRead(const PackedTextureRead& read, DiagnosticList& out);

}  // namespace parity::platforms::ps3
