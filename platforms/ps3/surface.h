// PS3 (RSX) colour surfaces and MRT rules (P1).
//
// RSX has no two-channel 16-bit colour surface, integer or float: that is the paper's starting
// point, and the PS3 layer answers such a request with an A8R8G8B8 surface holding two 16-bit
// values in its four bytes (packed16x2, P2). NV4097_SET_SURFACE_FORMAT holds one colour-format
// field for every MRT target, so in strict mode all targets share one format; the paper (and
// D3D9's generic rule) only asks for the same bits per pixel. Blend enables are per target, but
// one blend function applies to all.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "platforms/common/diagnostics.h"
#include "platforms/common/platform.h"
#include "platforms/common/platform_params.h"

namespace parity::platforms::ps3 {

// CELL_GCM_SURFACE_* colour formats (gcm_enums.h L934-947).
enum class SurfaceColorFormat : uint8_t {
  X1R5G5B5_Z1R5G5B5 = 1,
  X1R5G5B5_O1R5G5B5 = 2,
  R5G6B5 = 3,
  X8R8G8B8_Z8R8G8B8 = 4,
  X8R8G8B8_O8R8G8B8 = 5,
  A8R8G8B8 = 8,
  B8 = 9,
  G8B8 = 10,
  F_W16Z16Y16X16 = 11,  // FP16 x4, 64 bpp
  F_W32Z32Y32X32 = 12,  // 128 bpp
  F_X32 = 13,
  X8B8G8R8_Z8B8G8R8 = 14,
  X8B8G8R8_O8B8G8R8 = 15,
  A8B8G8R8 = 16,
};

std::string_view formatName(SurfaceColorFormat format);
// Bytes per pixel (TextureUtils.cpp L1436-1462).
uint32_t bytesPerPixel(SurfaceColorFormat format);

// What a technique asks for.
struct SurfaceRequest {
  std::string name;
  uint32_t channels = 4;
  uint32_t bitsPerChannel = 8;
  bool isFloat = false;
  // Whether a two-channel 16-bit unorm request may become a packed A8R8G8B8 surface (P2).
  bool allowPacking = true;
};

struct ColorSurface {
  std::string name;
  SurfaceColorFormat format = SurfaceColorFormat::A8R8G8B8;
  bool packed16x2 = false;  // two 16-bit values in the four bytes (P2)
  BlendState blend;
};

// The surface RSX really allocates, or nullopt. A 2x16-bit request without packing reports
// E_RSX_NO_RG16_SURFACE.
std::optional<ColorSurface> requestColorSurface(const SurfaceRequest& request, DiagnosticList& out);

// P1 for the targets bound together: E_MRT_FORMAT_MISMATCH (strict) / E_MRT_BPP_MISMATCH (same
// bpp), and W_MRT_SHARED_BLEND when blend-enabled targets ask for different functions.
void checkMrt(std::string_view pass, std::span<const ColorSurface> targets, Ps3MrtRule rule, DiagnosticList& out);
// W_MRT_SHARED_BLEND alone: the blend-enabled targets of one draw ask for different functions.
void checkSharedBlend(std::string_view pass, std::span<const ColorSurface> targets, DiagnosticList& out);

}  // namespace parity::platforms::ps3
