#include "platforms/ps3/packed16.h"

#include <algorithm>
#include <cmath>

namespace parity::platforms::ps3 {

namespace {

float clamp01(float v) { return std::clamp(std::isnan(v) ? 0.0f : v, 0.0f, 1.0f); }

uint8_t baseFormat(uint8_t format) { return static_cast<uint8_t>(format & ~(kTextureFlagLN | kTextureFlagUN)); }

float factorValue(BlendFactor f, const Argb& src, const Argb& dst, int channel, float constantAlpha) {
  switch (f) {
    case BlendFactor::Zero: return 0.0f;
    case BlendFactor::One: return 1.0f;
    case BlendFactor::SrcColor: return src[channel];
    case BlendFactor::OneMinusSrcColor: return 1.0f - src[channel];
    case BlendFactor::SrcAlpha: return src[kA];
    case BlendFactor::OneMinusSrcAlpha: return 1.0f - src[kA];
    case BlendFactor::DestColor: return dst[channel];
    case BlendFactor::OneMinusDestColor: return 1.0f - dst[channel];
    case BlendFactor::DestAlpha: return dst[kA];
    case BlendFactor::OneMinusDestAlpha: return 1.0f - dst[kA];
    case BlendFactor::ConstantAlpha: return constantAlpha;
  }
  return 0.0f;
}

Argb normalised(const Argb8Bytes& b) {
  return {b[0] / 255.0f, b[1] / 255.0f, b[2] / 255.0f, b[3] / 255.0f};
}

}  // namespace

uint16_t quantizeUnorm16(float x) { return static_cast<uint16_t>(std::floor(clamp01(x) * 65535.0f + 0.5f)); }

uint8_t ropUnorm8(float c) { return static_cast<uint8_t>(std::floor(clamp01(c) * 255.0f + 0.5f)); }

Argb packTwo16ShaderOutput(float x, float y) {
  uint16_t x16 = quantizeUnorm16(x), y16 = quantizeUnorm16(y);
  return {static_cast<float>(x16 >> 8) / 255.0f, static_cast<float>(x16 & 0xFFu) / 255.0f,
          static_cast<float>(y16 >> 8) / 255.0f, static_cast<float>(y16 & 0xFFu) / 255.0f};
}

Argb8Bytes packTwo16InArgb8(float x, float y) {
  Argb out = packTwo16ShaderOutput(x, y);
  return {ropUnorm8(out[kA]), ropUnorm8(out[kR]), ropUnorm8(out[kG]), ropUnorm8(out[kB])};
}

uint32_t argb8Word(const Argb8Bytes& b) {
  return uint32_t(b[0]) << 24 | uint32_t(b[1]) << 16 | uint32_t(b[2]) << 8 | uint32_t(b[3]);
}

std::array<uint16_t, 2> y16x16Words(const Argb8Bytes& b) {
  return {static_cast<uint16_t>(b[0] << 8 | b[1]), static_cast<uint16_t>(b[2] << 8 | b[3])};
}

std::optional<Rgba> sampleY16X16(const Argb8Bytes& bytes, uint32_t remap, std::string_view texture,
                                 DiagnosticList* out) {
  std::optional<uint32_t> rewritten = rewriteY16X16Remap(remap, texture, out);
  if (!rewritten) return std::nullopt;
  auto words = y16x16Words(bytes);
  // The host view is RG16 with X (the first word) in R and Y in G; A and B do not exist.
  Argb texel{0.0f, static_cast<float>(words[0]) / 65535.0f, static_cast<float>(words[1]) / 65535.0f, 0.0f};
  return toRgba(applyRemap(*rewritten, texel));
}

Rgba sampleArgb8(const Argb8Bytes& bytes, uint32_t remap) { return toRgba(applyRemap(remap, normalised(bytes))); }

std::array<uint16_t, 2> hostRg16FromBgra8(uint32_t w) {
  uint32_t swapped = (w & 0xFFFFu) << 16 | (w & 0xFFFF0000u) >> 16;  // bswap_u16_u32
  return {static_cast<uint16_t>(swapped & 0xFFFFu), static_cast<uint16_t>(swapped >> 16)};
}

Argb filterArgb8(const Argb8Bytes& t0, const Argb8Bytes& t1, float w) {
  Argb a = normalised(t0), b = normalised(t1), out{};
  for (int c = 0; c < 4; ++c) out[c] = a[c] * (1.0f - w) + b[c] * w;
  return out;
}

float decodePacked16RoundPerByte(float hi, float lo) {
  return std::floor(255.0f * hi + 0.5f) * 256.0f + std::floor(255.0f * lo + 0.5f);
}

float decodePacked16Linear(float hi, float lo) { return 65280.0f * hi + 255.0f * lo; }

float filterY16(uint16_t v0, uint16_t v1, float w) {
  return static_cast<float>(v0) * (1.0f - w) + static_cast<float>(v1) * w;
}

Argb8Bytes blendArgb8(const Argb8Bytes& srcBytes, const Argb8Bytes& dstBytes, const BlendState& blend) {
  if (!blend.enabled) return srcBytes;
  Argb src = normalised(srcBytes), dst = normalised(dstBytes);
  Argb8Bytes out{};
  for (int c = 0; c < 4; ++c) {
    BlendFactor fs = c == kA ? blend.srcAlpha : blend.srcColor;
    BlendFactor fd = c == kA ? blend.dstAlpha : blend.dstColor;
    float v = src[c] * factorValue(fs, src, dst, c, blend.constantAlpha) +
              dst[c] * factorValue(fd, src, dst, c, blend.constantAlpha);
    out[c] = ropUnorm8(v);
  }
  return out;
}

void checkPackedTargetDraw(const PackedTargetDraw& d, DiagnosticList& out) {
  if (!d.packed16x2) return;
  if (d.blend.enabled) {
    out.report("E_PACKED_BLEND", {d.target},
               "blending is enabled on " + d.target +
                   ", a packed16x2 target: the high and low bytes of each 16-bit value blend independently and no "
                   "channel is left for coverage (P3)");
  }
  const bool xSplit = bool(d.writeMask & kWriteA) != bool(d.writeMask & kWriteR);
  const bool ySplit = bool(d.writeMask & kWriteG) != bool(d.writeMask & kWriteB);
  if (xSplit || ySplit) {
    out.report("W_PACKED_PARTIAL_WRITEMASK", {d.target},
               "the colour write mask of " + d.target + " covers only some bytes of a packed 16-bit value (" +
                   (xSplit ? "A/R" : "G/B") + " split, P3)");
  }
  if (d.alphaTest) {
    out.report("E_PACKED_ALPHA_TEST", {d.target},
               "alpha test on a draw into " + d.target +
                   ": its alpha channel holds the high byte of a packed 16-bit value, not coverage (P3)");
  }
}

void checkPackedResolve(std::string_view target, bool packed16x2, uint32_t samples, bool averaging, DiagnosticList& out) {
  if (packed16x2 && samples > 1 && averaging) {
    const std::string name(target);
    out.report("E_PACKED_MSAA_RESOLVE", {name},
               "the MSAA resolve of " + name + " averages " + std::to_string(samples) +
                   " samples of a packed16x2 target: it averages bytes, not 16-bit values (P3)");
  }
}

void checkPackedTextureRead(const PackedTextureRead& r, DiagnosticList& out) {
  const uint8_t view = baseFormat(r.viewFormat);
  if (view == kTextureY16X16) {
    rewriteY16X16Remap(r.remap, r.texture, &out);
    if (r.sourceIsRenderTarget) {
      out.report("I_TYPELESS_COPY", {r.texture},
                 r.texture + " was rendered as A8R8G8B8 and is read as Y16_X16: the host needs a typeless copy that "
                             "swaps the 16-bit halves (P2)");
    }
    return;
  }
  if (!r.packed16x2 || view != kTextureA8R8G8B8) return;
  out.report("W_PACKED_VIEW_MISMATCH", {r.texture},
             r.texture + " holds packed16x2 data but is sampled as A8R8G8B8 instead of Y16_X16 (P2)");
  if (r.filter != Filter::Nearest && r.decodeRoundsPerByte) {
    out.report("W_PACKED_FILTER", {r.texture},
               std::string(filterName(r.filter)) + " filtering of the A8R8G8B8 view of " + r.texture +
                   " mixes bytes before the per-byte decode; use the Y16_X16 view or point sampling (P2)");
  }
}

}  // namespace parity::platforms::ps3
