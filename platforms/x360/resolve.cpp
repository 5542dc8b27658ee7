#include "platforms/x360/resolve.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "platforms/x360/fixed16.h"

namespace parity::platforms::x360 {

namespace {

std::vector<uint32_t> selectedSamples(CopySampleSelect select, MsaaSamples msaa) {
  std::vector<uint32_t> samples;
  switch (select) {
    case CopySampleSelect::k0: samples = {0}; break;
    case CopySampleSelect::k1: samples = {1}; break;
    case CopySampleSelect::k2: samples = {2}; break;
    case CopySampleSelect::k3: samples = {3}; break;
    case CopySampleSelect::k01: samples = {0, 1}; break;
    case CopySampleSelect::k23: samples = {2, 3}; break;
    case CopySampleSelect::k0123: samples = {0, 1, 2, 3}; break;
  }
  // Like Xenia's SanitizeCopySampleSelect: samples the surface does not have are dropped.
  std::erase_if(samples, [&](uint32_t s) { return s >= sampleCount(msaa); });
  if (samples.empty()) samples = {0};
  return samples;
}

bool isAveraging(CopySampleSelect select) { return select >= CopySampleSelect::k01; }

uint32_t componentCount(ColorFormat format) { return format == ColorFormat::k_16_16 ? 2 : 4; }

ColorFormat naturalDestination(const EdramSurface& s) {
  switch (s.colorFormat) {
    case ColorRenderTargetFormat::k_8_8_8_8: return ColorFormat::k_8_8_8_8;
    case ColorRenderTargetFormat::k_16_16: return ColorFormat::k_16_16;
    case ColorRenderTargetFormat::k_16_16_16_16: return ColorFormat::k_16_16_16_16;
    default: throw std::invalid_argument("resolve model supports k_8_8_8_8, k_16_16 and k_16_16_16_16 sources");
  }
}

// Step 4 for a k_16_16 destination component. `raw` is the single unaveraged int16 when the
// source is k_16_16 and no averaging happened.
ResolvedComponent packFixed16Destination(float value, std::optional<int16_t> raw, int destExpBias,
                                         SurfaceNumberFormat destNumber, const PlatformParams& params) {
  ResolvedComponent r;
  r.value = value;
  const bool signedDest = destNumber == SurfaceNumberFormat::kSignedRepeatingFraction &&
                          params.signedK16Resolve != SignedK16Resolve::UnsignedSaturate;
  if (!signedDest) {
    r.word = packUnorm16(value);
    r.signLost = value < 0.0f;
    r.rangeClamped = std::fabs(value) > 1.0f;
    return r;
  }
  if (params.signedK16Resolve == SignedK16Resolve::PreserveRawInt16 && raw && destExpBias == 0) {
    r.word = static_cast<uint16_t>(*raw);  // the raw int16 is kept (open question 1, pack default)
    return r;
  }
  // EDRAM-style re-encode: x 32767/32, clamped to +-32, rounded half away from zero.
  r.word = static_cast<uint16_t>(encodeFixed16(value, 0).value);
  return r;
}

}  // namespace

D3DFormatFields decodeD3DFormatWord(uint32_t word) {
  D3DFormatFields f;
  f.textureFormat = word & 0x3Fu;
  f.endian = (word >> 6) & 3u;
  f.tiled = (word >> 8) & 1u;
  for (int i = 0; i < 4; ++i) f.signs[i] = (word >> (9 + 2 * i)) & 3u;
  return f;
}

uint32_t resolveAlignedSize(uint32_t pixels) {
  return (pixels + kResolveAlignmentPixels - 1) / kResolveAlignmentPixels * kResolveAlignmentPixels;
}

ResolveRequest wholeSurfaceResolve(uint32_t width, uint32_t height) {
  ResolveRequest r;
  r.rect = {0, 0, resolveAlignedSize(width), resolveAlignedSize(height)};
  r.destMipWidth = std::max(r.rect.width, kResolveMinMipSize);
  r.destMipHeight = std::max(r.rect.height, kResolveMinMipSize);
  return r;
}

void checkResolveRequest(const EdramSurface& source, const ResolveRequest& request, DiagnosticList& out) {
  const ResolveRect& rect = request.rect;
  auto aligned = [](int64_t v) { return v % int64_t(kResolveAlignmentPixels) == 0; };
  if (!aligned(rect.x) || !aligned(rect.y) || !aligned(rect.width) || !aligned(rect.height)) {
    out.report("E_RESOLVE_ALIGNMENT", {source.name},
               "resolve of " + source.name + " rectangle (" + std::to_string(rect.x) + ", " + std::to_string(rect.y) +
                   ") " + std::to_string(rect.width) + "x" + std::to_string(rect.height) +
                   " is not aligned to 8 pixels (X3, GPU_RESOLVE_ALIGNMENT)");
  }
  if ((request.destMipWidth != 0 && request.destMipWidth < kResolveMinMipSize) ||
      (request.destMipHeight != 0 && request.destMipHeight < kResolveMinMipSize)) {
    out.report("E_RESOLVE_PACKED_MIP", {source.name},
               "resolve of " + source.name + " into a " + std::to_string(request.destMipWidth) + "x" +
                   std::to_string(request.destMipHeight) +
                   " mip level: the GPU cannot resolve to packed mips (smaller than 32x32, X3)");
  }
  if (source.isDepth) {
    std::string what;
    if (request.destFormat) what += " format conversion";
    if (isAveraging(request.sampleSelect)) what += " sample averaging";
    if (request.destExpBias != 0) what += " exponent bias";
    if (!what.empty()) {
      out.report("E_DEPTH_RESOLVE_CONVERT", {source.name},
                 "depth resolve of " + source.name + " requests" + what + "; depth resolves only copy (X3)");
    }
  }
}

float unpackFixed16ForResolve(int16_t s, const PlatformParams& params) {
  float lowest = params.k16UnpackClamp == K16UnpackClamp::Minus1 ? -1.0f : -32.0f;
  return std::max(decodeFixed16(s), lowest);
}

float averageAndBias(std::span<const float> samples, int destExpBias) {
  float sum = 0.0f;
  for (float s : samples) sum += s;
  int halvings = samples.size() >= 4 ? 2 : samples.size() >= 2 ? 1 : 0;
  return sum * std::ldexp(1.0f, destExpBias - halvings);
}

uint16_t packUnorm16(float f) {
  float saturated = std::clamp(std::isnan(f) ? 0.0f : f, 0.0f, 1.0f);
  return static_cast<uint16_t>(saturated * 65535.0f + 0.5f);
}

uint8_t packUnorm8(float f) {
  float saturated = std::clamp(std::isnan(f) ? 0.0f : f, 0.0f, 1.0f);
  return static_cast<uint8_t>(saturated * 255.0f + 0.5f);
}

ResolvedComponent resolveFixed16Component(std::span<const int16_t> samples, int destExpBias,
                                          SurfaceNumberFormat destNumber, const PlatformParams& params) {
  std::vector<float> unpacked;
  for (int16_t s : samples) unpacked.push_back(unpackFixed16ForResolve(s, params));
  float value = averageAndBias(unpacked, destExpBias);
  std::optional<int16_t> raw;
  if (samples.size() == 1) raw = samples[0];
  return packFixed16Destination(value, raw, destExpBias, destNumber, params);
}

float fetchFixed16Unsigned(uint16_t word, int expAdjust) {
  return std::ldexp(static_cast<float>(word) / 65535.0f, expAdjust);
}

float fetchFixed16Signed(uint16_t word, int expAdjust) {
  float t = std::max(static_cast<float>(static_cast<int16_t>(word)) / 32767.0f, -1.0f);
  return std::ldexp(t, expAdjust);
}

ResolvedTexture resolveSurface(const EdramMemory& edram, const EdramSurface& source, const ResolveRequest& request,
                               DiagnosticList& out, const PlatformParams& params) {
  checkResolveRequest(source, request, out);
  ResolvedTexture tex;
  tex.width = request.rect.width;
  tex.height = request.rect.height;
  tex.number = request.destNumber;
  const std::vector<uint32_t> samples = selectedSamples(request.sampleSelect, source.msaa);
  tex.texels.reserve(std::size_t(tex.width) * tex.height);

  if (source.isDepth) {
    // Depth resolves copy the stored word of one sample.
    tex.format = ColorFormat::k_8_8_8_8;  // 32-bit container
    for (uint32_t y = 0; y < tex.height; ++y)
      for (uint32_t x = 0; x < tex.width; ++x)
        tex.texels.push_back(edram.readSample(source, request.rect.x + x, request.rect.y + y, samples[0], params));
    return tex;
  }

  const ColorFormat srcNatural = naturalDestination(source);
  tex.format = request.destFormat.value_or(srcNatural);
  const uint32_t components = componentCount(srcNatural);
  if (componentCount(tex.format) != components)
    throw std::invalid_argument("resolve model: destination must have the source's component count");
  const bool srcFixed16 = srcNatural != ColorFormat::k_8_8_8_8;

  uint32_t signLostTexels = 0, clampedTexels = 0;
  for (uint32_t y = 0; y < tex.height; ++y) {
    for (uint32_t x = 0; x < tex.width; ++x) {
      // Gather the selected samples, component by component.
      std::vector<std::vector<int16_t>> raw(components);
      std::vector<std::vector<float>> unpacked(components);
      for (uint32_t s : samples) {
        uint64_t word = edram.readSample(source, request.rect.x + x, request.rect.y + y, s, params);
        for (uint32_t c = 0; c < components; ++c) {
          if (srcFixed16) {
            int16_t v = static_cast<int16_t>((word >> (16 * c)) & 0xFFFFu);
            raw[c].push_back(v);
            unpacked[c].push_back(unpackFixed16ForResolve(v, params));
          } else {
            unpacked[c].push_back(static_cast<float>((word >> (8 * c)) & 0xFFu) / 255.0f);
          }
        }
      }
      uint64_t texel = 0;
      bool signLost = false, clamped = false;
      for (uint32_t c = 0; c < components; ++c) {
        float value = averageAndBias(unpacked[c], request.destExpBias);
        if (tex.format == ColorFormat::k_8_8_8_8) {
          texel |= uint64_t(packUnorm8(value)) << (8 * c);
          signLost |= value < 0.0f;
          clamped |= std::fabs(value) > 1.0f;
        } else {
          std::optional<int16_t> single;
          if (srcFixed16 && raw[c].size() == 1) single = raw[c][0];
          ResolvedComponent r = packFixed16Destination(value, single, request.destExpBias, request.destNumber, params);
          texel |= uint64_t(r.word) << (16 * c);
          signLost |= r.signLost;
          clamped |= r.rangeClamped;
        }
      }
      signLostTexels += signLost ? 1 : 0;
      clampedTexels += clamped ? 1 : 0;
      tex.texels.push_back(texel);
    }
  }
  if (signLostTexels && srcFixed16) {
    out.report("W_RESOLVE_SIGN_LOSS", {source.name},
               std::to_string(signLostTexels) + " texel(s) of " + source.name + " (" + source.formatLabel() +
                   ") are negative and clamp to 0 in the unsigned destination (copy_dest_number = 0, X3)");
  }
  if (clampedTexels) {
    out.report("W_RESOLVE_RANGE_CLAMP", {source.name},
               std::to_string(clampedTexels) + " texel(s) of " + source.name + " have |f * 2^" +
                   std::to_string(request.destExpBias) + "| > 1 and clamp in the UNORM destination (X3)");
  }
  return tex;
}

namespace {
// One row per DsfResolvePath, in the enum's order.
constexpr std::array kDsfPaths = {
    DsfPathSpec{.name = "C",  // PaperSignedC
                .description = "paper: c = 64v - 32, sign-preserving resolve, signed k_16_16 fetch, v' = (t + 1) / 2",
                .shaderScale = 64.0f, .shaderOffset = -32.0f,
                .destNumber = SurfaceNumberFormat::kSignedRepeatingFraction, .fetchSigned = true, .sampleAdd = 1.0f,
                .sampleMul = 0.5f},
    DsfPathSpec{.name = "B",  // XdkBiasB
                .description = "XDK idiom: color_exp_bias +5, D3DRESOLVE_EXPONENTBIAS(-5) into unsigned k_16_16",
                .colorExpBias = 5, .destExpBias = -5},
    DsfPathSpec{.name = "A",  // NaiveA
                .description = "naive: color_exp_bias 0, resolve bias 0 into unsigned k_16_16"},
};
static_assert(kDsfPaths.size() == std::size_t(DsfResolvePath::NaiveA) + 1);
}  // namespace

DsfPathSpec dsfPath(DsfResolvePath path) { return kDsfPaths[std::size_t(path)]; }

DsfPathResult runDsfPath(const DsfPathSpec& path, float v, const PlatformParams& params) {
  DsfPathResult r;
  float c = v * path.shaderScale + path.shaderOffset;
  r.edram = encodeFixed16(c, path.colorExpBias).value;
  const int16_t samples[] = {r.edram};
  r.resolved = resolveFixed16Component(samples, path.destExpBias, path.destNumber, params);
  r.sampled = path.fetchSigned ? fetchFixed16Signed(r.resolved.word, path.fetchExpAdjust)
                               : fetchFixed16Unsigned(r.resolved.word, path.fetchExpAdjust);
  r.reconstructed = (r.sampled + path.sampleAdd) * path.sampleMul;
  return r;
}

PathPrecision dsfPathPrecision(const DsfPathSpec& path, const PlatformParams& params) {
  // v is continuous over [0, 1] and the encode is monotonic, so every int16 between the
  // encodes of the end points is reachable; count the distinct destination words they give.
  int lo = encodeFixed16(0.0f * path.shaderScale + path.shaderOffset, path.colorExpBias).value;
  int hi = encodeFixed16(1.0f * path.shaderScale + path.shaderOffset, path.colorExpBias).value;
  if (lo > hi) std::swap(lo, hi);
  std::vector<bool> seen(65536, false);
  PathPrecision p;
  for (int s = lo; s <= hi; ++s) {
    const int16_t samples[] = {static_cast<int16_t>(s)};
    uint16_t word = resolveFixed16Component(samples, path.destExpBias, path.destNumber, params).word;
    if (!seen[word]) {
      seen[word] = true;
      ++p.levels;
    }
  }
  p.bits = std::log2(static_cast<double>(p.levels));
  p.roundedBits = static_cast<int>(std::lround(p.bits));
  return p;
}

void checkDsfPathPrecision(std::string_view target, const DsfPathSpec& path, DiagnosticList& out,
                           const PlatformParams& params) {
  PathPrecision p = dsfPathPrecision(path, params);
  if (p.roundedBits < 16) {
    const std::string name(target);
    out.report("W_RESOLVE_PRECISION", {name},
               name + " through path " + std::string(path.name) + " (" + std::string(path.description) + ") reaches " +
                   std::to_string(p.levels) + " levels = " + std::to_string(p.roundedBits) +
                   " effective bits < 16 (X3)");
  }
}

}  // namespace parity::platforms::x360
