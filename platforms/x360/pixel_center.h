// Xbox 360 pixel centres (X5): PA_SU_VTX_CNTL.PIX_CENTER and D3DRS_HALFPIXELOFFSET.
//
// With PIX_CENTER = kD3DZero (the D3D9 convention and the 360's default) pixel (x, y) is sampled
// at screen position (x, y); with kOGLHalf (D3D10 / GL / PS3) at (x + 0.5, y + 0.5). The state
// moves rasterisation sample points and attribute evaluation only; texel addressing is the same.
// A GL/Vulkan host, whose centres are at .5, emulates kD3DZero by adding 0.5 px to the guest's
// window positions (Xenia draw_util.cc, DXVK's viewport shift).
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

#include "platforms/common/diagnostics.h"
#include "platforms/common/platform_params.h"

namespace parity::platforms::x360 {

enum class PixelCenter : uint8_t {
  kD3DZero = 0,  // "Pixel center at vertex positions .0, like in Direct3D 9"
  kOGLHalf = 1,  // "Pixel center at vertex positions .5, like in OpenGL"
};

// D3DRS_HALFPIXELOFFSET -> PIX_CENTER under the mapping parameter (open question 5).
PixelCenter pixelCenterFor(bool halfPixelOffset, const PlatformParams& params = {});

struct ScreenPoint {
  float x = 0.0f, y = 0.0f;
};

// Guest screen position at which pixel (px, py) is sampled.
ScreenPoint pixelSamplePoint(int32_t px, int32_t py, PixelCenter center);
// What the host adds to guest window positions to reproduce `center` with .5 host centres.
float hostWindowOffset(PixelCenter center);

// An axis-aligned screen-space quad with texture coordinates at its corners.
struct ScreenQuad {
  float x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  float u0 = 0, v0 = 0, u1 = 1, v1 = 1;
};

// Interpolated (u, v) the pixel shader sees at pixel (px, py).
ScreenPoint quadUvAtPixel(const ScreenQuad& quad, int32_t px, int32_t py, PixelCenter center);
// Top-left rule for an axis-aligned rectangle: covered when x0 <= cx < x1 and y0 <= cy < y1.
bool quadCoversPixel(const ScreenQuad& quad, int32_t px, int32_t py, PixelCenter center);

// D3D10 texel selection (X5): point picks floor(U * size); linear picks floor(U * size - 0.5)
// and the next texel with weight frac(U * size - 0.5).
int32_t pointTexel(float u, uint32_t size);
struct LinearFootprint {
  int32_t x0 = 0, y0 = 0;  // first texel; the second is +1 (clamped by the caller)
  float fx = 0, fy = 0;    // weight of the second texel
};
LinearFootprint linearFootprint(float u, float v, uint32_t width, uint32_t height);

// X3 resolve rectangle from a RECTLIST's corner vertices: +0.5 when PIX_CENTER is D3D-style,
// 16.8 fixed point (round to nearest), top-left rule (x + 127) >> 8. Half-open pixel bounds.
struct PixelRect {
  int32_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};
PixelRect resolveRectFromVertices(ScreenPoint topLeft, ScreenPoint bottomRight, PixelCenter center);

// --- Rules (X5 (4)) ------------------------------------------------------------------------

struct ScreenVertex {
  float x = 0, y = 0;  // screen position in pixels
  float u = 0, v = 0;
};

// W_D3D9_PIXEL_CENTER: a screen-space draw with PIX_CENTER = 0 whose vertices sit on integer
// positions with UVs equal to pos / size (no compensating -0.5 offset).
void checkScreenSpaceDraw(std::string_view draw, std::span<const ScreenVertex> vertices, uint32_t targetWidth,
                          uint32_t targetHeight, PixelCenter center, DiagnosticList& out);
// I_HALFPIXEL_MODE_CHANGE: the pixel-centre state flips between the draws of one pass.
void checkPassPixelCenters(std::string_view pass, std::span<const PixelCenter> drawCenters, DiagnosticList& out);

}  // namespace parity::platforms::x360
