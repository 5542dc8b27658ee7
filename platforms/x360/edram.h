// Xbox 360 EDRAM: geometry, surface sizes, placement, addressing and the placement rules.
//
// X1 of the reference pack: 10 MiB of EDRAM = 2048 tiles of 80x16 32-bit samples (5120 B).
// Render targets live only there; a surface is a base tile plus a pitch (in tiles) shared by
// every target bound for a draw (RB_SURFACE_INFO), and EDRAM addressing wraps from tile 2047
// to tile 0. X4 adds inferred lighting's rules: G-buffers may not overlap, the L-buffer may
// alias G-buffer colour tiles (after their resolve) but never the depth/stencil tiles.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "platforms/common/diagnostics.h"
#include "platforms/common/platform_params.h"

namespace parity::platforms::x360 {

// X1: xenos.h L414-418.
inline constexpr uint32_t kEdramTileWidthSamples = 80;
inline constexpr uint32_t kEdramTileHeightSamples = 16;
inline constexpr uint32_t kEdramTileCount = 2048;
inline constexpr uint32_t kEdramTileSizeDwords = kEdramTileWidthSamples * kEdramTileHeightSamples;  // 1280
inline constexpr uint32_t kEdramTileSizeBytes = kEdramTileSizeDwords * 4;                          // 5120
inline constexpr uint32_t kEdramSizeBytes = kEdramTileCount * kEdramTileSizeBytes;                  // 10 MiB

// RB_SURFACE_INFO.msaa_samples (X1).
enum class MsaaSamples : uint8_t { k1X = 0, k2X = 1, k4X = 2 };
uint32_t sampleCount(MsaaSamples msaa);

// RB_COLOR_INFO.color_format (X1, X2; values as in xenos.h ColorRenderTargetFormat).
enum class ColorRenderTargetFormat : uint8_t {
  k_8_8_8_8 = 0,
  k_8_8_8_8_GAMMA = 1,
  k_2_10_10_10 = 2,
  k_2_10_10_10_FLOAT = 3,
  k_16_16 = 4,        // fixed point -32...32 (X2)
  k_16_16_16_16 = 5,  // fixed point -32...32, 64 bpp (X2)
  k_16_16_FLOAT = 6,
  k_16_16_16_16_FLOAT = 7,
  k_2_10_10_10_AS_10_10_10_10 = 10,
  k_2_10_10_10_FLOAT_AS_16_16_16_16 = 12,
  k_32_FLOAT = 14,
  k_32_32_FLOAT = 15,
};

enum class DepthRenderTargetFormat : uint8_t { kD24S8 = 0, kD24FS8 = 1 };

std::string_view formatName(ColorRenderTargetFormat format);
std::string_view formatName(DepthRenderTargetFormat format);
// X2: the 64-bpp colour formats are k_16_16_16_16, k_16_16_16_16_FLOAT and k_32_32_FLOAT.
bool isColorRenderTargetFormat64bpp(ColorRenderTargetFormat format);

// X1, GetSurfacePitchTiles: ceil((pitch_px << (msaa >= 4x)) / 80) << is64bpp.
uint32_t surfacePitchTiles(uint32_t pitchPx, MsaaSamples msaa, bool is64bpp);
// X1, XGSurfaceSize: ceil(h_samples / 16) * ceil(w_samples / 80) * (1 or 2), where 2x doubles the
// height in samples and 4x doubles both.
uint32_t surfaceSizeTiles(uint32_t widthPx, uint32_t heightPx, MsaaSamples msaa, bool is64bpp);

// What a surface is used for, for X4's rules. Depth is "the depth G-buffer" in the paper, so an
// inferred-lighting depth surface has role GBuffer and isDepth set.
enum class SurfaceRole : uint8_t { Plain = 0, GBuffer, LBuffer };

struct EdramSurface {
  std::string name;
  bool isDepth = false;
  ColorRenderTargetFormat colorFormat = ColorRenderTargetFormat::k_8_8_8_8;  // when !isDepth
  DepthRenderTargetFormat depthFormat = DepthRenderTargetFormat::kD24S8;     // when isDepth
  uint32_t baseTile = 0;   // RB_COLOR_INFO.color_base / RB_DEPTH_INFO.depth_base, 0..2047
  uint32_t pitchPx = 0;    // RB_SURFACE_INFO.surface_pitch (shared by the targets of a draw)
  uint32_t heightPx = 0;   // rows used (the hardware has no height register; the draw decides)
  MsaaSamples msaa = MsaaSamples::k1X;  // RB_SURFACE_INFO.msaa_samples (shared)
  int colorExpBias = 0;    // RB_COLOR_INFO.color_exp_bias, signed 6 bits (X2)
  SurfaceRole role = SurfaceRole::Plain;

  bool is64bpp() const { return !isDepth && isColorRenderTargetFormat64bpp(colorFormat); }
  uint32_t pitchTiles() const { return surfacePitchTiles(pitchPx, msaa, is64bpp()); }
  uint32_t sizeTiles() const { return surfaceSizeTiles(pitchPx, heightPx, msaa, is64bpp()); }
  std::string formatLabel() const;  // "k_16_16" or "D24S8"
};

// [base, base + count) taken modulo 2048 (X1 wrap-around).
struct TileRange {
  uint32_t base = 0;
  uint32_t count = 0;
};

TileRange tileRange(const EdramSurface& surface);
bool tileRangesIntersect(TileRange a, TileRange b);
// "[1440, 2160)" or, when it wraps, "[1440, 2160) = [1440, 2048) + [0, 112)".
std::string formatTileRange(TileRange range);

// Position of sample `sample` of pixel (x, y) in the surface's sample grid (before tiling): the
// first half of the X1 address formula. Mainline: sx = (x << (msaa>=4x)) + ((s>>1)&1),
// sy = (y << (msaa>=2x)) + (s&1); 2x samples are vertical with sample 0 on top.
struct SampleCoord {
  uint32_t sx = 0, sy = 0;
};
SampleCoord edramSampleCoord(MsaaSamples msaa, uint32_t x, uint32_t y, uint32_t sample,
                             const PlatformParams& params = {});

// X1: guest 2x sample 0 (top) is host D3D10 2x sample 1 (draw_util.h L317-334); 4x keeps its
// index (no remap is documented).
uint32_t hostSampleIndex(MsaaSamples msaa, uint32_t guestSample);

// X1, open question 2: sub-sample positions of the host sample index in 1/16 px (D3D10.1
// standard: 2x {(4,4),(-4,-4)}; 4x {(-2,-6),(6,-2),(-6,2),(2,6)}; 1x at the centre).
struct SampleOffset16 {
  int32_t x = 0, y = 0;
};
SampleOffset16 hostSamplePosition16(MsaaSamples msaa, uint32_t hostSample);

// X1 address formula (Xenia mainline edram.xesli XeEdramOffsetBytes): byte offset of sample
// `sample` of pixel (x, y) of `surface` in EDRAM, after the wrap. Honours the 4x sample-order
// and 64-bpp layout parameters (open questions 2 and 3).
uint32_t edramByteOffset(const EdramSurface& surface, uint32_t x, uint32_t y, uint32_t sample,
                         const PlatformParams& params = {});

// Places the surfaces one after another from `firstTile` (bases wrap modulo 2048); returns the
// unwrapped end tile (first + total tiles), which exceeds 2048 when they do not fit.
uint32_t placeContiguous(std::span<EdramSurface> surfaces, uint32_t firstTile = 0);

// Places surface i at the lowest base tile where it intersects no earlier surface j with
// liveTogether(i, j), without wrapping; where none fits (or when reuse(i) is false) it goes after
// the surfaces placed so far, as placeContiguous does. X4: an L-buffer may take the tiles of
// G-buffer colour targets that are resolved (dead) before it is rendered.
void placeReusingDeadTiles(std::span<EdramSurface> surfaces, const std::function<bool(size_t)>& reuse,
                           const std::function<bool(size_t, size_t)>& liveTogether);

// --- Rules ------------------------------------------------------------------------------------

// X1: E_EDRAM_SURFACE_TOO_LARGE, W_EDRAM_WRAP for one surface.
void checkSurface(const EdramSurface& surface, DiagnosticList& out);

// X1 + X4 for surfaces whose contents are live at the same time (bound targets, plus any
// surface that must survive until a later resolve or depth test): per-surface checks, the total
// budget (more than 2048 tiles cannot be placed without overlap), and every intersecting pair.
// The code of a pair follows X4 where it applies: two G-buffers -> E_GBUF_OVERLAP, L-buffer and
// depth -> E_LBUF_DEPTH_ALIAS, L-buffer and a still-live G-buffer colour target ->
// E_USE_BEFORE_RESOLVE; otherwise E_EDRAM_OVERLAP.
void checkLiveSurfaces(std::string_view when, std::span<const EdramSurface> live, DiagnosticList& out);

// X1 pass rules for the targets bound to one draw: shared pitch and MSAA
// (E_MRT_SURFACE_INFO_MISMATCH), distinct bases (W_RT_SAME_BASE), then checkLiveSurfaces.
void checkBoundTargets(std::string_view pass, std::span<const EdramSurface> bound, DiagnosticList& out);

// X4: the inferred-lighting layout. The geometry pass binds the G-buffer colour targets and
// depth (none may overlap); the light pass binds the L-buffer and depth (stencil optimisation),
// after the G-buffer colour targets have been resolved, so the L-buffer may alias them but not
// depth. Roles are taken from the layout, not from the surfaces' own role fields.
struct InferredLightingLayout {
  std::vector<EdramSurface> gbufferColor;
  EdramSurface depth;
  EdramSurface lbuffer;
};
void checkInferredLightingLayout(const InferredLightingLayout& layout, DiagnosticList& out);

// --- Memory -----------------------------------------------------------------------------------

// The 10 MiB of EDRAM as bytes. Dwords are stored little-endian (host order, as Xenia keeps
// them); 64-bpp samples are two consecutive dwords, low dword first.
class EdramMemory {
 public:
  EdramMemory();
  uint32_t readDword(uint32_t byteOffset) const;
  void writeDword(uint32_t byteOffset, uint32_t value);
  // One sample of a surface: 32 bits, or 64 bits for 64-bpp surfaces.
  uint64_t readSample(const EdramSurface& surface, uint32_t x, uint32_t y, uint32_t sample,
                      const PlatformParams& params = {}) const;
  void writeSample(const EdramSurface& surface, uint32_t x, uint32_t y, uint32_t sample, uint64_t value,
                   const PlatformParams& params = {});
  std::span<const uint8_t> bytes() const { return bytes_; }

 private:
  std::vector<uint8_t> bytes_;
};

}  // namespace parity::platforms::x360
