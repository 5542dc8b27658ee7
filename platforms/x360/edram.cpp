#include "platforms/x360/edram.h"

#include <algorithm>
#include <stdexcept>

namespace parity::platforms::x360 {

namespace {

uint32_t ceilDiv(uint32_t a, uint32_t b) { return (a + b - 1) / b; }

std::string describe(const EdramSurface& s) {
  return s.name + " " + formatTileRange(tileRange(s));
}

// X4 first, then X1 (see edram.h).
std::string_view overlapCode(const EdramSurface& a, const EdramSurface& b) {
  if (a.role == SurfaceRole::GBuffer && b.role == SurfaceRole::GBuffer) return "E_GBUF_OVERLAP";
  if ((a.role == SurfaceRole::LBuffer && b.isDepth) || (b.role == SurfaceRole::LBuffer && a.isDepth))
    return "E_LBUF_DEPTH_ALIAS";
  auto liveGbufferColor = [](const EdramSurface& s) { return s.role == SurfaceRole::GBuffer && !s.isDepth; };
  if ((a.role == SurfaceRole::LBuffer && liveGbufferColor(b)) || (b.role == SurfaceRole::LBuffer && liveGbufferColor(a)))
    return "E_USE_BEFORE_RESOLVE";
  return "E_EDRAM_OVERLAP";
}

std::string overlapReason(std::string_view code) {
  if (code == "E_GBUF_OVERLAP") return "none of the G-buffers can overlap (X4)";
  if (code == "E_LBUF_DEPTH_ALIAS") return "the L-buffer must not alias the depth tiles the light pass tests against (X4)";
  if (code == "E_USE_BEFORE_RESOLVE") return "the G-buffer colour target must be resolved before its tiles are reused (X4)";
  return "live surfaces may not share EDRAM tiles (X1)";
}

void reportPairs(std::string_view when, std::span<const EdramSurface> live, DiagnosticList& out) {
  for (std::size_t i = 0; i < live.size(); ++i) {
    for (std::size_t j = i + 1; j < live.size(); ++j) {
      const EdramSurface& a = live[i];
      const EdramSurface& b = live[j];
      if (!tileRangesIntersect(tileRange(a), tileRange(b))) continue;
      std::string_view code = overlapCode(a, b);
      out.report(code, {a.name, b.name},
                 describe(b) + " overlaps " + describe(a) + " in " + std::string(when) + ": " + overlapReason(code));
    }
  }
}

void reportBudget(std::string_view when, std::span<const EdramSurface> live, DiagnosticList& out) {
  uint64_t total = 0;
  std::string names;
  std::vector<std::string> targets;
  for (const EdramSurface& s : live) {
    total += s.sizeTiles();
    names += (names.empty() ? "" : " + ") + s.name + " (" + std::to_string(s.sizeTiles()) + ")";
    targets.push_back(s.name);
  }
  if (total > kEdramTileCount) {
    out.report("E_EDRAM_OVERLAP", std::move(targets),
               "EDRAM overflow in " + std::string(when) + ": " + names + " = " + std::to_string(total) +
                   " tiles > " + std::to_string(kEdramTileCount) + " tiles; no placement avoids an overlap (X1)");
  }
}

void checkSurfaceInfo(std::string_view pass, std::span<const EdramSurface> bound, DiagnosticList& out) {
  if (bound.empty()) return;
  const EdramSurface& first = bound[0];
  for (std::size_t i = 1; i < bound.size(); ++i) {
    const EdramSurface& s = bound[i];
    if (s.pitchPx != first.pitchPx || s.msaa != first.msaa) {
      out.report("E_MRT_SURFACE_INFO_MISMATCH", {first.name, s.name},
                 s.name + " (pitch " + std::to_string(s.pitchPx) + " px, " + std::to_string(sampleCount(s.msaa)) +
                     "x) and " + first.name + " (pitch " + std::to_string(first.pitchPx) + " px, " +
                     std::to_string(sampleCount(first.msaa)) + "x) are bound together in " + std::string(pass) +
                     ", but RB_SURFACE_INFO holds one pitch and one MSAA mode (X1)");
    }
  }
  for (std::size_t i = 0; i < bound.size(); ++i) {
    for (std::size_t j = i + 1; j < bound.size(); ++j) {
      if (bound[i].baseTile % kEdramTileCount == bound[j].baseTile % kEdramTileCount) {
        out.report("W_RT_SAME_BASE", {bound[i].name, bound[j].name},
                   bound[i].name + " and " + bound[j].name + " are bound in " + std::string(pass) +
                       " with the same base tile " + std::to_string(bound[i].baseTile) + " (X1)");
      }
    }
  }
}

}  // namespace

uint32_t sampleCount(MsaaSamples msaa) {
  switch (msaa) {
    case MsaaSamples::k1X: return 1;
    case MsaaSamples::k2X: return 2;
    case MsaaSamples::k4X: return 4;
  }
  return 1;
}

std::string_view formatName(ColorRenderTargetFormat format) {
  switch (format) {
    case ColorRenderTargetFormat::k_8_8_8_8: return "k_8_8_8_8";
    case ColorRenderTargetFormat::k_8_8_8_8_GAMMA: return "k_8_8_8_8_GAMMA";
    case ColorRenderTargetFormat::k_2_10_10_10: return "k_2_10_10_10";
    case ColorRenderTargetFormat::k_2_10_10_10_FLOAT: return "k_2_10_10_10_FLOAT";
    case ColorRenderTargetFormat::k_16_16: return "k_16_16";
    case ColorRenderTargetFormat::k_16_16_16_16: return "k_16_16_16_16";
    case ColorRenderTargetFormat::k_16_16_FLOAT: return "k_16_16_FLOAT";
    case ColorRenderTargetFormat::k_16_16_16_16_FLOAT: return "k_16_16_16_16_FLOAT";
    case ColorRenderTargetFormat::k_2_10_10_10_AS_10_10_10_10: return "k_2_10_10_10_AS_10_10_10_10";
    case ColorRenderTargetFormat::k_2_10_10_10_FLOAT_AS_16_16_16_16: return "k_2_10_10_10_FLOAT_AS_16_16_16_16";
    case ColorRenderTargetFormat::k_32_FLOAT: return "k_32_FLOAT";
    case ColorRenderTargetFormat::k_32_32_FLOAT: return "k_32_32_FLOAT";
  }
  return "?";
}

std::string_view formatName(DepthRenderTargetFormat format) {
  return format == DepthRenderTargetFormat::kD24S8 ? "D24S8" : "D24FS8";
}

bool isColorRenderTargetFormat64bpp(ColorRenderTargetFormat format) {
  return format == ColorRenderTargetFormat::k_16_16_16_16 || format == ColorRenderTargetFormat::k_16_16_16_16_FLOAT ||
         format == ColorRenderTargetFormat::k_32_32_FLOAT;
}

uint32_t surfacePitchTiles(uint32_t pitchPx, MsaaSamples msaa, bool is64bpp) {
  uint32_t widthSamples = pitchPx << (msaa >= MsaaSamples::k4X ? 1 : 0);
  return ceilDiv(widthSamples, kEdramTileWidthSamples) << (is64bpp ? 1 : 0);
}

uint32_t surfaceSizeTiles(uint32_t widthPx, uint32_t heightPx, MsaaSamples msaa, bool is64bpp) {
  // XGSurfaceSize: 2x and 4x double the height, 4x doubles the width; align to 80x16 samples;
  // 4 or 8 bytes per sample; divide by 5120.
  uint32_t heightSamples = heightPx << (msaa >= MsaaSamples::k2X ? 1 : 0);
  uint32_t widthSamples = widthPx << (msaa >= MsaaSamples::k4X ? 1 : 0);
  return ceilDiv(heightSamples, kEdramTileHeightSamples) * ceilDiv(widthSamples, kEdramTileWidthSamples) *
         (is64bpp ? 2u : 1u);
}

std::string EdramSurface::formatLabel() const {
  return std::string(isDepth ? formatName(depthFormat) : formatName(colorFormat));
}

TileRange tileRange(const EdramSurface& surface) {
  return TileRange{surface.baseTile % kEdramTileCount, surface.sizeTiles()};
}

bool tileRangesIntersect(TileRange a, TileRange b) {
  if (a.count == 0 || b.count == 0) return false;
  if (a.count >= kEdramTileCount || b.count >= kEdramTileCount) return true;
  // Distance from each base to the other, going forward around the ring.
  uint32_t ab = (b.base + kEdramTileCount - a.base) % kEdramTileCount;
  uint32_t ba = (a.base + kEdramTileCount - b.base) % kEdramTileCount;
  return ab < a.count || ba < b.count;
}

std::string formatTileRange(TileRange r) {
  uint32_t end = r.base + r.count;
  std::string out = "[" + std::to_string(r.base) + ", " + std::to_string(end) + ")";
  if (end > kEdramTileCount && r.count < kEdramTileCount) {
    out += " = [" + std::to_string(r.base) + ", " + std::to_string(kEdramTileCount) + ") + [0, " +
           std::to_string(end - kEdramTileCount) + ")";
  }
  return out;
}

SampleCoord edramSampleCoord(MsaaSamples msaa, uint32_t x, uint32_t y, uint32_t sample, const PlatformParams& params) {
  const bool msaa2 = msaa >= MsaaSamples::k2X;
  const bool msaa4 = msaa >= MsaaSamples::k4X;
  if (msaa4 && params.msaa4xSampleOrder == Msaa4xSampleOrder::CanaryCanonical) {
    // xenia-canary #1163: u = ((x&~1)<<1)|(x&1)|((s&1)<<1); v = ((y&~1)<<1)|(y&1)|(s&2).
    return {((x & ~1u) << 1) | (x & 1u) | ((sample & 1u) << 1), ((y & ~1u) << 1) | (y & 1u) | (sample & 2u)};
  }
  // Mainline: sx = px << (msaa>=4x) + ((sample>>1)&1); sy = py << (msaa>=2x) + (sample&1).
  // 2x samples are vertical with sample 0 on top (both layouts).
  return {(x << (msaa4 ? 1 : 0)) + (msaa4 ? ((sample >> 1) & 1u) : 0u),
          (y << (msaa2 ? 1 : 0)) + (msaa2 ? (sample & 1u) : 0u)};
}

uint32_t hostSampleIndex(MsaaSamples msaa, uint32_t guestSample) {
  return msaa == MsaaSamples::k2X ? (guestSample ^ 1u) : guestSample;
}

SampleOffset16 hostSamplePosition16(MsaaSamples msaa, uint32_t hostSample) {
  static constexpr SampleOffset16 k2x[] = {{4, 4}, {-4, -4}};
  static constexpr SampleOffset16 k4x[] = {{-2, -6}, {6, -2}, {-6, 2}, {2, 6}};
  switch (msaa) {
    case MsaaSamples::k1X: return {0, 0};
    case MsaaSamples::k2X: return k2x[hostSample & 1u];
    case MsaaSamples::k4X: return k4x[hostSample & 3u];
  }
  return {0, 0};
}

uint32_t edramByteOffset(const EdramSurface& s, uint32_t x, uint32_t y, uint32_t sample, const PlatformParams& params) {
  const bool is64 = s.is64bpp();
  SampleCoord c = edramSampleCoord(s.msaa, x, y, sample, params);
  uint32_t sx = c.sx, sy = c.sy;
  // 64 bpp: the tile layout is open question 3; Xenia40x16 (the only layout a source proposes)
  // keeps 16 rows and halves the width: 40x16 samples of 8 bytes per 5120-byte tile.
  uint32_t tileW = kEdramTileWidthSamples;
  if (is64) {
    switch (params.edram64bppTileLayout) {
      case Edram64bppTileLayout::Xenia40x16: tileW = kEdramTileWidthSamples / 2; break;
    }
  }
  const uint32_t tileH = kEdramTileHeightSamples;
  uint32_t tile = s.baseTile + (sy / tileH) * s.pitchTiles() + sx / tileW;
  sx %= tileW;
  sy %= tileH;
  if (s.isDepth) {
    // X1: depth tiles have their 40x16-sample halves swapped.
    sx = sx >= tileW / 2 ? sx - tileW / 2 : sx + tileW / 2;
  }
  uint64_t dword = uint64_t(tile) * kEdramTileSizeDwords + (uint64_t(sy * tileW + sx) << (is64 ? 1 : 0));
  dword %= uint64_t(kEdramTileSizeDwords) * kEdramTileCount;  // wrap: tile 2048 is tile 0
  return static_cast<uint32_t>(dword * 4);
}

uint32_t placeContiguous(std::span<EdramSurface> surfaces, uint32_t firstTile) {
  uint32_t next = firstTile;
  for (EdramSurface& s : surfaces) {
    s.baseTile = next % kEdramTileCount;
    next += s.sizeTiles();
  }
  return next;
}

void placeReusingDeadTiles(std::span<EdramSurface> surfaces, const std::function<bool(size_t)>& reuse,
                           const std::function<bool(size_t, size_t)>& liveTogether) {
  uint32_t next = 0;  // the end of the surfaces placed so far, unwrapped
  for (size_t i = 0; i < surfaces.size(); ++i) {
    EdramSurface& s = surfaces[i];
    const uint32_t size = s.sizeTiles();
    bool placed = false;
    if (reuse(i)) {
      // Candidates: tile 0 and the end of every earlier surface, lowest first.
      std::vector<uint32_t> candidates = {0};
      for (size_t j = 0; j < i; ++j) candidates.push_back(surfaces[j].baseTile + surfaces[j].sizeTiles());
      std::sort(candidates.begin(), candidates.end());
      for (uint32_t base : candidates) {
        if (base + size > kEdramTileCount) break;
        bool free = true;
        for (size_t j = 0; j < i && free; ++j)
          free = !liveTogether(i, j) || !tileRangesIntersect({base, size}, tileRange(surfaces[j]));
        if (free) {
          s.baseTile = base;
          next = std::max(next, base + size);
          placed = true;
          break;
        }
      }
    }
    if (!placed) {
      s.baseTile = next % kEdramTileCount;
      next += size;
    }
  }
}

void checkSurface(const EdramSurface& s, DiagnosticList& out) {
  uint32_t tiles = s.sizeTiles();
  if (tiles > kEdramTileCount) {
    out.report("E_EDRAM_SURFACE_TOO_LARGE", {s.name},
               s.name + " (" + std::to_string(s.pitchPx) + "x" + std::to_string(s.heightPx) + " " +
                   std::to_string(sampleCount(s.msaa)) + "x " + s.formatLabel() + ") needs " + std::to_string(tiles) +
                   " tiles > " + std::to_string(kEdramTileCount) + ": it overlaps itself (X1)");
    return;
  }
  if (s.baseTile % kEdramTileCount + tiles > kEdramTileCount) {
    out.report("W_EDRAM_WRAP", {s.name},
               s.name + " occupies tiles " + formatTileRange(tileRange(s)) +
                   ": it wraps past tile 2047 to tile 0 (legal, X1)");
  }
}

void checkLiveSurfaces(std::string_view when, std::span<const EdramSurface> live, DiagnosticList& out) {
  for (const EdramSurface& s : live) checkSurface(s, out);
  reportBudget(when, live, out);
  reportPairs(when, live, out);
}

void checkBoundTargets(std::string_view pass, std::span<const EdramSurface> bound, DiagnosticList& out) {
  checkSurfaceInfo(pass, bound, out);
  checkLiveSurfaces(pass, bound, out);
}

void checkInferredLightingLayout(const InferredLightingLayout& layout, DiagnosticList& out) {
  std::vector<EdramSurface> geometry;
  for (EdramSurface s : layout.gbufferColor) {
    s.role = SurfaceRole::GBuffer;
    geometry.push_back(std::move(s));
  }
  EdramSurface depth = layout.depth;
  depth.role = SurfaceRole::GBuffer;
  depth.isDepth = true;
  geometry.push_back(depth);
  EdramSurface lbuffer = layout.lbuffer;
  lbuffer.role = SurfaceRole::LBuffer;

  // Each surface once.
  for (const EdramSurface& s : geometry) checkSurface(s, out);
  checkSurface(lbuffer, out);

  // Geometry pass: G-buffer colour targets and depth bound together.
  checkSurfaceInfo("the geometry pass", geometry, out);
  reportBudget("the geometry pass", geometry, out);
  reportPairs("the geometry pass", geometry, out);

  // Light pass: the G-buffer colour targets are resolved (dead); depth stays live.
  const EdramSurface light[] = {depth, lbuffer};
  checkSurfaceInfo("the light pass", light, out);
  reportBudget("the light pass", light, out);
  reportPairs("the light pass", light, out);
}

EdramMemory::EdramMemory() : bytes_(kEdramSizeBytes, 0) {}

uint32_t EdramMemory::readDword(uint32_t byteOffset) const {
  if (byteOffset % 4 != 0 || byteOffset >= kEdramSizeBytes) throw std::out_of_range("EDRAM dword offset");
  return uint32_t(bytes_[byteOffset]) | uint32_t(bytes_[byteOffset + 1]) << 8 | uint32_t(bytes_[byteOffset + 2]) << 16 |
         uint32_t(bytes_[byteOffset + 3]) << 24;
}

void EdramMemory::writeDword(uint32_t byteOffset, uint32_t value) {
  if (byteOffset % 4 != 0 || byteOffset >= kEdramSizeBytes) throw std::out_of_range("EDRAM dword offset");
  for (int i = 0; i < 4; ++i) bytes_[byteOffset + i] = static_cast<uint8_t>(value >> (8 * i));
}

uint64_t EdramMemory::readSample(const EdramSurface& s, uint32_t x, uint32_t y, uint32_t sample,
                                 const PlatformParams& params) const {
  uint32_t offset = edramByteOffset(s, x, y, sample, params);
  uint64_t value = readDword(offset);
  if (s.is64bpp()) value |= uint64_t(readDword(offset + 4)) << 32;
  return value;
}

void EdramMemory::writeSample(const EdramSurface& s, uint32_t x, uint32_t y, uint32_t sample, uint64_t value,
                              const PlatformParams& params) {
  uint32_t offset = edramByteOffset(s, x, y, sample, params);
  writeDword(offset, static_cast<uint32_t>(value));
  if (s.is64bpp()) writeDword(offset + 4, static_cast<uint32_t>(value >> 32));
}

}  // namespace parity::platforms::x360
