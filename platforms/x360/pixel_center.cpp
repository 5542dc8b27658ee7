#include "platforms/x360/pixel_center.h"

#include <cmath>
#include <string>

namespace parity::platforms::x360 {

PixelCenter pixelCenterFor(bool halfPixelOffset, const PlatformParams& params) {
  bool half = params.halfPixelOffsetMapping == HalfPixelOffsetMapping::TrueMeansPixCenterHalf ? halfPixelOffset
                                                                                             : !halfPixelOffset;
  return half ? PixelCenter::kOGLHalf : PixelCenter::kD3DZero;
}

ScreenPoint pixelSamplePoint(int32_t px, int32_t py, PixelCenter center) {
  float o = center == PixelCenter::kOGLHalf ? 0.5f : 0.0f;
  return {static_cast<float>(px) + o, static_cast<float>(py) + o};
}

float hostWindowOffset(PixelCenter center) { return center == PixelCenter::kD3DZero ? 0.5f : 0.0f; }

ScreenPoint quadUvAtPixel(const ScreenQuad& q, int32_t px, int32_t py, PixelCenter center) {
  ScreenPoint p = pixelSamplePoint(px, py, center);
  float tx = (p.x - q.x0) / (q.x1 - q.x0);
  float ty = (p.y - q.y0) / (q.y1 - q.y0);
  return {q.u0 + tx * (q.u1 - q.u0), q.v0 + ty * (q.v1 - q.v0)};
}

bool quadCoversPixel(const ScreenQuad& q, int32_t px, int32_t py, PixelCenter center) {
  ScreenPoint p = pixelSamplePoint(px, py, center);
  return q.x0 <= p.x && p.x < q.x1 && q.y0 <= p.y && p.y < q.y1;
}

int32_t pointTexel(float u, uint32_t size) { return static_cast<int32_t>(std::floor(u * static_cast<float>(size))); }

LinearFootprint linearFootprint(float u, float v, uint32_t width, uint32_t height) {
  float x = u * static_cast<float>(width) - 0.5f;
  float y = v * static_cast<float>(height) - 0.5f;
  LinearFootprint f;
  f.x0 = static_cast<int32_t>(std::floor(x));
  f.y0 = static_cast<int32_t>(std::floor(y));
  f.fx = x - std::floor(x);
  f.fy = y - std::floor(y);
  return f;
}

PixelRect resolveRectFromVertices(ScreenPoint a, ScreenPoint b, PixelCenter center) {
  float o = center == PixelCenter::kD3DZero ? 0.5f : 0.0f;
  auto edge = [&](float v) {
    int32_t fixed = static_cast<int32_t>(std::lround((v + o) * 256.0f));  // 16.8 fixed point
    return (fixed + 127) >> 8;                                            // top-left rule
  };
  return {edge(a.x), edge(a.y), edge(b.x), edge(b.y)};
}

void checkScreenSpaceDraw(std::string_view draw, std::span<const ScreenVertex> vertices, uint32_t targetWidth,
                          uint32_t targetHeight, PixelCenter center, DiagnosticList& out) {
  if (center != PixelCenter::kD3DZero || vertices.empty()) return;
  const float eps = 1e-6f;
  for (const ScreenVertex& v : vertices) {
    bool integer = v.x == std::floor(v.x) && v.y == std::floor(v.y);
    bool uvIsPosOverSize = std::fabs(v.u - v.x / static_cast<float>(targetWidth)) <= eps &&
                           std::fabs(v.v - v.y / static_cast<float>(targetHeight)) <= eps;
    if (!integer || !uvIsPosOverSize) return;
  }
  const std::string name(draw);
  out.report("W_D3D9_PIXEL_CENTER", {name},
             name + " is a screen-space draw with PIX_CENTER = 0 (D3D9 centres), vertices on integer positions and "
                    "UV = pos / size: every pixel samples a texel corner; offset the vertices by -0.5 or set "
                    "D3DRS_HALFPIXELOFFSET (X5)");
}

void checkPassPixelCenters(std::string_view pass, std::span<const PixelCenter> drawCenters, DiagnosticList& out) {
  for (std::size_t i = 1; i < drawCenters.size(); ++i) {
    if (drawCenters[i] != drawCenters[0]) {
      const std::string name(pass);
      out.report("I_HALFPIXEL_MODE_CHANGE", {name},
                 name + ": PIX_CENTER changes between draws " + std::to_string(i - 1) + " and " + std::to_string(i) +
                     " of the pass (breaks resolution-scaled emulation, X5)");
      return;
    }
  }
}

}  // namespace parity::platforms::x360
