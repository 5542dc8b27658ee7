// PS3: reading a D24S8 depth buffer through an A8R8G8B8 view with the BARG remap and
// texDepth2D_precise (P4).
//
// Memory holds the big-endian word (depth24 << 8) | stencil, bytes [D_hi, D_mid, D_lo, S]. Viewed
// as A8R8G8B8 with the identity remap, A = D_hi, R = D_mid, G = D_lo, B = stencil. The BARG remap
// 0xAA93 (A <- B, R <- A, G <- R, B <- G) gives R = D_hi, G = D_mid, B = D_lo, A = stencil, which
// is what texDepth2D / texDepth2D_precise read (one XYZ fetch plus one DP3). The precise variant
// rounds each byte, floor(255 c + 0.5), and returns D24 / 16777215 (to 1 ULP; open question 4).
// Filtering the byte view mixes bytes, so point filtering is enforced (RPCS3 and a Source-engine
// PS3 layer both force NEAREST).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "platforms/common/diagnostics.h"
#include "platforms/common/platform.h"
#include "platforms/common/platform_params.h"
#include "platforms/ps3/remap.h"

namespace parity::platforms::ps3 {

// [D_hi, D_mid, D_lo, S] for the stored word (depth24 << 8) | stencil.
std::array<uint8_t, 4> depthStencilMemoryBytes(uint32_t depth24, uint8_t stencil);
// DEPTH24_D8_FLOAT: the 24 stored bits are f32 bits [7..30].
uint32_t depth24BitsOfFloat(float depth);

// The depth texel fetched through the A8R8G8B8 view and `remap`, as the shader sees it.
Rgba sampleDepthAsArgb8(uint32_t depth24, uint8_t stencil, uint32_t remap = kRemapBarg);

// texDepth2D_precise on a fetched texel (reads .rgb). The result depends on the decode parameter.
float texDepth2DPrecise(const Rgba& texel, const PlatformParams& params = {});
// texDepth2D on a fetched texel: dot(.rgb, (255/256, 255/65536, 255/16777216)) in fp32, i.e.
// D24 / 2^24.
float texDepth2D(const Rgba& texel);
// The hand-written decode on the un-remapped layout (identity remap, reads .arg):
// rawval = floor(255 * .arg + 0.5); D24 / 16777215.
float decodeDepthArgByHand(const Rgba& texel);

enum class DepthDecodeChannels : uint8_t { Rgb = 0, Arg };

struct DepthAsColorRead {
  std::string surface;
  uint32_t remap = kRemapBarg;
  DepthDecodeChannels channels = DepthDecodeChannels::Rgb;
  Filter minFilter = Filter::Nearest;
  Filter magFilter = Filter::Nearest;
  bool boundForDepthWrite = false;
};

// E_DEPTH_AS_COLOR_REMAP, W_DEPTH_AS_COLOR_FILTER, W_DEPTH_STENCIL_IN_DECODE (derived from the
// remap: a decoded channel reads the stencil byte), W_DEPTH_FEEDBACK.
void checkDepthAsColorRead(const DepthAsColorRead& read, DiagnosticList& out);

// A D24S8 surface in the CPU model: row-major depth24 and stencil.
struct DepthSurfaceImage {
  uint32_t width = 0, height = 0;
  std::vector<uint32_t> depth24;
  std::vector<uint8_t> stencil;
};

// Reads depth at normalised (u, v) as the PS3 layer does: the texel is fetched with point
// filtering whatever filter was asked for (enforced), remapped and decoded per `read`.
float readDepthAsColor(const DepthSurfaceImage& image, float u, float v, const DepthAsColorRead& read,
                       const PlatformParams& params = {});

// The filter trap: bilinear filtering of the byte view between two texels with weight w of the
// second, as normalised (R, G, B) after the BARG remap.
std::array<float, 3> filterDepthBytes(uint32_t depth24a, uint32_t depth24b, float w);

}  // namespace parity::platforms::ps3
