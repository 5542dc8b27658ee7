#include "platforms/ps3/depth_read.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>

namespace parity::platforms::ps3 {

namespace {

float byteValue(float c) { return std::floor(255.0f * c + 0.5f); }

float d24OverMax(uint32_t d24) { return static_cast<float>(static_cast<double>(d24) / 16777215.0); }

std::string hex4(uint32_t v) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "0x%04X", static_cast<unsigned>(v & 0xFFFFu));
  return buf;
}

Argb identityView(uint32_t depth24, uint8_t stencil) {
  auto b = depthStencilMemoryBytes(depth24, stencil);
  return {b[0] / 255.0f, b[1] / 255.0f, b[2] / 255.0f, b[3] / 255.0f};
}

}  // namespace

std::array<uint8_t, 4> depthStencilMemoryBytes(uint32_t depth24, uint8_t stencil) {
  uint32_t word = (depth24 & 0xFFFFFFu) << 8 | stencil;
  return {static_cast<uint8_t>(word >> 24), static_cast<uint8_t>(word >> 16), static_cast<uint8_t>(word >> 8),
          static_cast<uint8_t>(word)};
}

uint32_t depth24BitsOfFloat(float depth) { return (std::bit_cast<uint32_t>(depth) >> 7) & 0xFFFFFFu; }

Rgba sampleDepthAsArgb8(uint32_t depth24, uint8_t stencil, uint32_t remap) {
  return toRgba(applyRemap(remap, identityView(depth24, stencil)));
}

float texDepth2DPrecise(const Rgba& t, const PlatformParams& params) {
  float hi = byteValue(t.r), mid = byteValue(t.g), lo = byteValue(t.b);
  if (params.texDepth2DPrecise == TexDepth2DPrecise::Fp32PreciseFactorsDp3) {
    // _depth_factor_precise = (0x3b800001, 0x37800001, 0x33800001) on the integer bytes.
    const float f0 = std::bit_cast<float>(0x3b800001u);
    const float f1 = std::bit_cast<float>(0x37800001u);
    const float f2 = std::bit_cast<float>(0x33800001u);
    return hi * f0 + mid * f1 + lo * f2;
  }
  uint32_t d24 = static_cast<uint32_t>(hi) << 16 | static_cast<uint32_t>(mid) << 8 | static_cast<uint32_t>(lo);
  return d24OverMax(d24);
}

float texDepth2D(const Rgba& t) {
  // _depth_factor = (0x3f7f0000, 0x3b7f0000, 0x377f0000) = (255/256, 255/65536, 255/16777216).
  const float f0 = std::bit_cast<float>(0x3f7f0000u);
  const float f1 = std::bit_cast<float>(0x3b7f0000u);
  const float f2 = std::bit_cast<float>(0x377f0000u);
  return t.r * f0 + t.g * f1 + t.b * f2;
}

float decodeDepthArgByHand(const Rgba& t) {
  uint32_t d24 = static_cast<uint32_t>(byteValue(t.a)) << 16 | static_cast<uint32_t>(byteValue(t.r)) << 8 |
                 static_cast<uint32_t>(byteValue(t.g));
  return d24OverMax(d24);
}

void checkDepthAsColorRead(const DepthAsColorRead& r, DiagnosticList& out) {
  const bool rgb = r.channels == DepthDecodeChannels::Rgb;
  const uint32_t expected = rgb ? kRemapBarg : kRemapIdentity;
  if ((r.remap & 0xFFFFu) != expected) {
    out.report("E_DEPTH_AS_COLOR_REMAP", {r.surface},
               "depth surface " + r.surface + " is decoded via " + (rgb ? ".rgb" : ".arg") + " with remap " +
                   hex4(r.remap) + "; it needs " + hex4(expected) + (rgb ? " (BARG)" : " (identity)") + " (P4)");
  }
  if (r.minFilter != Filter::Nearest || r.magFilter != Filter::Nearest) {
    out.report("W_DEPTH_AS_COLOR_FILTER", {r.surface},
               "depth surface " + r.surface + " is sampled as ARGB8 with " +
                   std::string(filterName(r.minFilter != Filter::Nearest ? r.minFilter : r.magFilter)) +
                   " filtering; filtering mixes depth bytes, NEAREST is enforced (P4)");
  }
  // Which memory byte feeds each decoded channel: the stencil byte is input B.
  const int outs[3] = {rgb ? kR : kA, rgb ? kG : kR, rgb ? kB : kG};
  for (int o : outs) {
    if (remapSource(r.remap, o) == kB) {
      out.report("W_DEPTH_STENCIL_IN_DECODE", {r.surface},
                 "the stencil byte of " + r.surface + " feeds the depth decode (remap " + hex4(r.remap) + ", P4)");
      break;
    }
  }
  if (r.boundForDepthWrite) {
    out.report("W_DEPTH_FEEDBACK", {r.surface},
               "depth surface " + r.surface + " is sampled while bound for depth writes (P4)");
  }
}

float readDepthAsColor(const DepthSurfaceImage& image, float u, float v, const DepthAsColorRead& read,
                       const PlatformParams& params) {
  // Point filtering enforced: floor(U * size), clamped.
  auto texel = [](float c, uint32_t size) {
    int32_t i = static_cast<int32_t>(std::floor(c * static_cast<float>(size)));
    return static_cast<uint32_t>(std::clamp<int32_t>(i, 0, static_cast<int32_t>(size) - 1));
  };
  uint32_t x = texel(u, image.width), y = texel(v, image.height);
  std::size_t i = std::size_t(y) * image.width + x;
  Rgba t = sampleDepthAsArgb8(image.depth24[i], image.stencil.empty() ? 0 : image.stencil[i], read.remap);
  return read.channels == DepthDecodeChannels::Rgb ? texDepth2DPrecise(t, params) : decodeDepthArgByHand(t);
}

std::array<float, 3> filterDepthBytes(uint32_t depth24a, uint32_t depth24b, float w) {
  Rgba a = sampleDepthAsArgb8(depth24a, 0, kRemapBarg);
  Rgba b = sampleDepthAsArgb8(depth24b, 0, kRemapBarg);
  return {a.r * (1.0f - w) + b.r * w, a.g * (1.0f - w) + b.g * w, a.b * (1.0f - w) + b.b * w};
}

}  // namespace parity::platforms::ps3
