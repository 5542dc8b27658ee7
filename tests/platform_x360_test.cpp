// Xbox 360 CPU model against the reference pack's vectors (console-quirks.md, X1-X5).
// Every expected value below is quoted from the pack; the comment names the section.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <set>

#include "platforms/x360/edram.h"
#include "platforms/x360/edram_frame.h"
#include "platforms/x360/fixed16.h"
#include "platforms/x360/pixel_center.h"
#include "platforms/x360/resolve.h"
#include "platforms/x360/x360_platform.h"

using namespace parity::platforms;
using namespace parity::platforms::x360;

namespace {

EdramSurface color(std::string name, uint32_t w, uint32_t h, MsaaSamples msaa = MsaaSamples::k1X,
                   ColorRenderTargetFormat f = ColorRenderTargetFormat::k_8_8_8_8, uint32_t base = 0) {
  EdramSurface s;
  s.name = std::move(name);
  s.colorFormat = f;
  s.pitchPx = w;
  s.heightPx = h;
  s.msaa = msaa;
  s.baseTile = base;
  return s;
}

EdramSurface depth(std::string name, uint32_t w, uint32_t h, MsaaSamples msaa = MsaaSamples::k1X, uint32_t base = 0) {
  EdramSurface s = color(std::move(name), w, h, msaa, ColorRenderTargetFormat::k_8_8_8_8, base);
  s.isDepth = true;
  s.depthFormat = DepthRenderTargetFormat::kD24S8;
  return s;
}

constexpr auto k64 = ColorRenderTargetFormat::k_16_16_16_16;
constexpr auto k1616 = ColorRenderTargetFormat::k_16_16;

}  // namespace

// ---------------------------------------------------------------------------------------------
// X1: EDRAM geometry
// ---------------------------------------------------------------------------------------------

TEST(X360Edram, GeometryConstants) {
  // X1 (1): kEdramTileCount = 2048, 80x16 samples, 10,485,760 B; one tile is 5120 B.
  EXPECT_EQ(kEdramTileCount, 2048u);
  EXPECT_EQ(kEdramTileWidthSamples, 80u);
  EXPECT_EQ(kEdramTileHeightSamples, 16u);
  EXPECT_EQ(kEdramTileSizeBytes, 5120u);
  EXPECT_EQ(kEdramSizeBytes, 10485760u);
}

struct TileRow {
  uint32_t w, h;
  uint32_t x1_32, x1_64, x2_32, x2_64, x4_32;
};

class X360EdramTiles : public ::testing::TestWithParam<TileRow> {};

TEST_P(X360EdramTiles, SurfaceSizeInTilesMatchesPackTable) {
  // X1 (3): surface sizes in tiles.
  const TileRow r = GetParam();
  SCOPED_TRACE(std::to_string(r.w) + "x" + std::to_string(r.h));
  EXPECT_EQ(surfaceSizeTiles(r.w, r.h, MsaaSamples::k1X, false), r.x1_32);
  EXPECT_EQ(surfaceSizeTiles(r.w, r.h, MsaaSamples::k1X, true), r.x1_64);
  EXPECT_EQ(surfaceSizeTiles(r.w, r.h, MsaaSamples::k2X, false), r.x2_32);
  EXPECT_EQ(surfaceSizeTiles(r.w, r.h, MsaaSamples::k2X, true), r.x2_64);
  EXPECT_EQ(surfaceSizeTiles(r.w, r.h, MsaaSamples::k4X, false), r.x4_32);
}

INSTANTIATE_TEST_SUITE_P(X360PackTable, X360EdramTiles,
                         ::testing::Values(TileRow{1280, 720, 720, 1440, 1440, 2880, 2880},
                                           TileRow{1120, 720, 630, 1260, 1260, 2520, 2520},
                                           TileRow{1024, 576, 468, 936, 936, 1872, 1872},
                                           TileRow{640, 360, 184, 368, 360, 720, 720},
                                           TileRow{256, 256, 64, 128, 128, 256, 224}),
                         [](const ::testing::TestParamInfo<TileRow>& info) {
                           return std::to_string(info.param.w) + "x" + std::to_string(info.param.h);
                         });

TEST(X360Edram, SurfaceBytesAndPitch) {
  // X1 (3): 1280x720 1x 32bpp = 720 tiles = 3,686,400 B; 256x256 is stored with a 320-px pitch.
  EXPECT_EQ(surfaceSizeTiles(1280, 720, MsaaSamples::k1X, false) * kEdramTileSizeBytes, 3686400u);
  EXPECT_EQ(surfacePitchTiles(256, MsaaSamples::k1X, false) * kEdramTileWidthSamples, 320u);
  // X1 (3) byte-offset table: pitch tiles 16 (1x colour), 32 (4x colour), 32 (64bpp 1x) at 1280 px.
  EXPECT_EQ(surfacePitchTiles(1280, MsaaSamples::k1X, false), 16u);
  EXPECT_EQ(surfacePitchTiles(1280, MsaaSamples::k4X, false), 32u);
  EXPECT_EQ(surfacePitchTiles(1280, MsaaSamples::k1X, true), 32u);
}

TEST(X360Edram, OverBudgetSurfacesAreTooLarge) {
  // X1 (4): E_EDRAM_SURFACE_TOO_LARGE, "Example: 1280x720 4x" (2880 tiles, marked OVER in X1 (3)).
  DiagnosticList d;
  checkSurface(color("hdr", 1280, 720, MsaaSamples::k4X), d);
  EXPECT_TRUE(d.has("E_EDRAM_SURFACE_TOO_LARGE")) << d.format();
  DiagnosticList d64;
  checkSurface(color("hdr64", 1280, 720, MsaaSamples::k2X, k64), d64);  // 2x 64bpp: 2880 OVER
  EXPECT_TRUE(d64.has("E_EDRAM_SURFACE_TOO_LARGE"));
  // Near miss: 1024x576 4x is 1872 tiles.
  DiagnosticList ok;
  checkSurface(color("fits", 1024, 576, MsaaSamples::k4X), ok);
  EXPECT_TRUE(ok.empty()) << ok.format();
}

struct OffsetCase {
  const char* what;
  EdramSurface surface;
  uint32_t x, y, sample;
  uint32_t expected;
};

TEST(X360Edram, ByteOffsetsMatchPackTable) {
  // X1 (3) byte offsets, mainline layout, base 0, 1280-px pitch.
  const EdramSurface c1 = color("c1", 1280, 720);
  const EdramSurface d1 = depth("d1", 1280, 720);
  const EdramSurface c4 = color("c4", 1280, 720, MsaaSamples::k4X);
  const EdramSurface c2 = color("c2", 1280, 720, MsaaSamples::k2X);
  const EdramSurface c64 = color("c64", 1280, 720, MsaaSamples::k1X, k64);
  ASSERT_EQ(c1.pitchTiles(), 16u);
  ASSERT_EQ(c4.pitchTiles(), 32u);
  ASSERT_EQ(c64.pitchTiles(), 32u);
  const OffsetCase cases[] = {
      {"1x colour (0,0)", c1, 0, 0, 0, 0},
      {"1x colour (79,0)", c1, 79, 0, 0, 316},
      {"1x colour (80,0)", c1, 80, 0, 0, 5120},
      {"1x colour (0,16)", c1, 0, 16, 0, 81920},
      {"1x depth (0,0) half-swap", d1, 0, 0, 0, 160},
      {"1x depth (40,0)", d1, 40, 0, 0, 0},
      {"4x colour (0,0) s0", c4, 0, 0, 0, 0},
      {"4x colour (0,0) s1", c4, 0, 0, 1, 320},
      {"4x colour (0,0) s2", c4, 0, 0, 2, 4},
      {"4x colour (0,0) s3", c4, 0, 0, 3, 324},
      {"2x colour (0,0) s0", c2, 0, 0, 0, 0},
      {"2x colour (0,0) s1", c2, 0, 0, 1, 320},
      {"64bpp 1x (1,0)", c64, 1, 0, 0, 8},
      {"64bpp 1x (40,0)", c64, 40, 0, 0, 5120},
  };
  for (const OffsetCase& c : cases) EXPECT_EQ(edramByteOffset(c.surface, c.x, c.y, c.sample), c.expected) << c.what;
}

TEST(X360Edram, ByteOffsetWrapsAroundTile2048) {
  // X1 (3): base 2047, pitch 16, pixel (0,16) -> tile (2047+16) mod 2048 = 15 -> byte 76800.
  EdramSurface s = color("wrapping", 1280, 720, MsaaSamples::k1X, ColorRenderTargetFormat::k_8_8_8_8, 2047);
  ASSERT_EQ(s.pitchTiles(), 16u);
  EXPECT_EQ(edramByteOffset(s, 0, 16, 0), 76800u);
}

TEST(X360Edram, CanaryFourSampleOrderIsAPermutationOfTheBlock) {
  // X1 (1), open question 2: the canary layout must still give each sample of a 2x2-pixel block
  // its own dword inside the 4x4-sample block (no pack offsets are given for it).
  PlatformParams p;
  p.msaa4xSampleOrder = Msaa4xSampleOrder::CanaryCanonical;
  EdramSurface s = color("c4", 1280, 720, MsaaSamples::k4X);
  std::set<uint32_t> seen;
  for (uint32_t y = 0; y < 2; ++y)
    for (uint32_t x = 0; x < 2; ++x)
      for (uint32_t smp = 0; smp < 4; ++smp) {
        uint32_t off = edramByteOffset(s, x, y, smp, p);
        uint32_t sx = (off / 4) % 80, sy = (off / 4) / 80;
        EXPECT_LT(sx, 4u);
        EXPECT_LT(sy, 4u);
        seen.insert(off);
      }
  EXPECT_EQ(seen.size(), 16u);
}

TEST(X360Edram, GuestToHostSamplesAndPositions) {
  // X1 (1): guest 2x sample 0 (top) maps to host D3D10 2x sample 1; Xenia's assumed positions in
  // 1/16 px are 2x {(4,4),(-4,-4)} and 4x {(-2,-6),(6,-2),(-6,2),(2,6)}.
  EXPECT_EQ(hostSampleIndex(MsaaSamples::k2X, 0), 1u);
  EXPECT_EQ(hostSampleIndex(MsaaSamples::k2X, 1), 0u);
  const SampleOffset16 two[] = {{4, 4}, {-4, -4}};
  const SampleOffset16 four[] = {{-2, -6}, {6, -2}, {-6, 2}, {2, 6}};
  for (uint32_t i = 0; i < 2; ++i) {
    EXPECT_EQ(hostSamplePosition16(MsaaSamples::k2X, i).x, two[i].x);
    EXPECT_EQ(hostSamplePosition16(MsaaSamples::k2X, i).y, two[i].y);
  }
  for (uint32_t i = 0; i < 4; ++i) {
    EXPECT_EQ(hostSamplePosition16(MsaaSamples::k4X, i).x, four[i].x);
    EXPECT_EQ(hostSamplePosition16(MsaaSamples::k4X, i).y, four[i].y);
  }
  // Guest sample 0 is the top one: its host position is above (negative y) the other's.
  EXPECT_LT(hostSamplePosition16(MsaaSamples::k2X, hostSampleIndex(MsaaSamples::k2X, 0)).y,
            hostSamplePosition16(MsaaSamples::k2X, hostSampleIndex(MsaaSamples::k2X, 1)).y);
  // Mainline 4x: (s0,s1,s2,s3) = (0,0),(0,1),(1,0),(1,1) in (x,y) sample units.
  const uint32_t expect[4][2] = {{0, 0}, {0, 1}, {1, 0}, {1, 1}};
  for (uint32_t smp = 0; smp < 4; ++smp) {
    SampleCoord c = edramSampleCoord(MsaaSamples::k4X, 0, 0, smp);
    EXPECT_EQ(c.sx, expect[smp][0]);
    EXPECT_EQ(c.sy, expect[smp][1]);
  }
}

TEST(X360Edram, Fable2DepthBufferWraps) {
  // X1 (1): Fable 2's 1120x720 2x depth buffer sits in tiles [1008, 2268) (1260 tiles): legal,
  // so W_EDRAM_WRAP is a warning only.
  EdramSurface d = depth("fable2_depth", 1120, 720, MsaaSamples::k2X, 1008);
  EXPECT_EQ(d.sizeTiles(), 1260u);
  EXPECT_EQ(d.baseTile + d.sizeTiles(), 2268u);
  DiagnosticList out;
  checkSurface(d, out);
  ASSERT_TRUE(out.has("W_EDRAM_WRAP")) << out.format();
  EXPECT_EQ(out.first("W_EDRAM_WRAP")->severity, Severity::Warning);
  EXPECT_FALSE(out.hasErrors());
  // Near miss: the same buffer at base 0 ends at 1260.
  DiagnosticList none;
  checkSurface(depth("fable2_depth", 1120, 720, MsaaSamples::k2X, 0), none);
  EXPECT_TRUE(none.empty());
}

TEST(X360Edram, AcceptanceTwoGBuffersPlusDepthAt720pDoNotFit) {
  // X1 (3): a 1280x720 1x setup with two 32-bpp colour targets plus D24S8 needs
  // 3 x 720 = 2160 tiles > 2048, so the harness must flag it.
  EdramSurface live[] = {color("gbuffer0", 1280, 720), color("gbuffer1", 1280, 720, MsaaSamples::k1X, k1616),
                         depth("depth", 1280, 720)};
  uint32_t end = placeContiguous(live);
  EXPECT_EQ(end, 2160u);
  DiagnosticList out;
  checkBoundTargets("geometry pass", live, out);
  ASSERT_TRUE(out.has("E_EDRAM_OVERLAP")) << out.format();
  bool budget = false;
  for (const Diagnostic& d : out.all())
    if (d.code == "E_EDRAM_OVERLAP" && d.message.find("2160") != std::string::npos) budget = true;
  EXPECT_TRUE(budget) << out.format();
  EXPECT_TRUE(out.has("W_EDRAM_WRAP"));  // depth [1440, 2160) wraps onto gbuffer0's tiles
}

TEST(X360Edram, SameGBuffersAt576pFit) {
  // X1 (3): "The same setup at 1024x576 needs 1404 tiles."
  EdramSurface live[] = {color("gbuffer0", 1024, 576), color("gbuffer1", 1024, 576, MsaaSamples::k1X, k1616),
                         depth("depth", 1024, 576)};
  EXPECT_EQ(placeContiguous(live), 1404u);
  DiagnosticList out;
  checkBoundTargets("geometry pass", live, out);
  EXPECT_TRUE(out.empty()) << out.format();
}

TEST(X360Edram, OverlapIsIntersectionModulo2048) {
  // X1 (4): E_EDRAM_OVERLAP when [base, base+tiles) mod 2048 intersect.
  EdramSurface a = color("a", 1280, 720, MsaaSamples::k1X, ColorRenderTargetFormat::k_8_8_8_8, 0);    // [0, 720)
  EdramSurface b = color("b", 1280, 720, MsaaSamples::k1X, ColorRenderTargetFormat::k_8_8_8_8, 719);  // [719, 1439)
  EdramSurface live[] = {a, b};
  DiagnosticList out;
  checkLiveSurfaces("pass", live, out);
  ASSERT_TRUE(out.has("E_EDRAM_OVERLAP"));
  EXPECT_NE(out.first("E_EDRAM_OVERLAP")->message.find("a "), std::string::npos);
  // Near miss: touching ranges [0, 720) and [720, 1440) do not intersect.
  live[1].baseTile = 720;
  DiagnosticList none;
  checkLiveSurfaces("pass", live, none);
  EXPECT_TRUE(none.empty()) << none.format();
  // Modulo: a wrapping surface [1500, 2220) reaches tiles [0, 172) and overlaps a at 0.
  EdramSurface w = color("w", 1280, 720, MsaaSamples::k1X, ColorRenderTargetFormat::k_8_8_8_8, 1500);
  EdramSurface wrapped[] = {a, w};
  DiagnosticList modulo;
  checkLiveSurfaces("pass", wrapped, modulo);
  EXPECT_TRUE(modulo.has("E_EDRAM_OVERLAP"));
  EXPECT_TRUE(modulo.has("W_EDRAM_WRAP"));
}

TEST(X360Edram, BoundTargetsShareSurfaceInfo) {
  // X1 (1): RB_SURFACE_INFO (pitch, MSAA) is shared by every bound target; formats and bpp may
  // differ (X1 "Consequence").
  EdramSurface pitch[] = {color("g0", 1280, 720), color("g1", 1024, 720, MsaaSamples::k1X, ColorRenderTargetFormat::k_8_8_8_8, 720)};
  DiagnosticList a;
  checkBoundTargets("pass", pitch, a);
  EXPECT_TRUE(a.has("E_MRT_SURFACE_INFO_MISMATCH")) << a.format();
  EdramSurface msaa[] = {color("g0", 640, 360), color("g1", 640, 360, MsaaSamples::k2X, ColorRenderTargetFormat::k_8_8_8_8, 184)};
  DiagnosticList b;
  checkBoundTargets("pass", msaa, b);
  EXPECT_TRUE(b.has("E_MRT_SURFACE_INFO_MISMATCH"));
  // Near miss: same pitch and MSAA, different format and bpp.
  EdramSurface mixed[] = {color("g0", 640, 360), color("g1", 640, 360, MsaaSamples::k1X, k64, 184)};
  DiagnosticList c;
  checkBoundTargets("pass", mixed, c);
  EXPECT_TRUE(c.empty()) << c.format();
}

TEST(X360Edram, SameBaseIsReported) {
  // X1 (4): W_RT_SAME_BASE when two bound targets have the same base.
  EdramSurface same[] = {color("g0", 640, 360, MsaaSamples::k1X, ColorRenderTargetFormat::k_8_8_8_8, 100),
                         color("g1", 640, 360, MsaaSamples::k1X, ColorRenderTargetFormat::k_8_8_8_8, 100)};
  DiagnosticList out;
  checkBoundTargets("pass", same, out);
  EXPECT_TRUE(out.has("W_RT_SAME_BASE"));
  // Near miss: different (overlapping) bases are an overlap, not a same-base warning.
  same[1].baseTile = 101;
  DiagnosticList other;
  checkBoundTargets("pass", same, other);
  EXPECT_FALSE(other.has("W_RT_SAME_BASE"));
  EXPECT_TRUE(other.has("E_EDRAM_OVERLAP"));
}

TEST(X360Edram, RenderTargetsAreNotSampleable) {
  // X1 (4): E_EDRAM_NOT_READABLE when a shader samples a render target without a resolve.
  EdramFrame frame;
  frame.declare(color("scene", 640, 360));
  DiagnosticList out;
  frame.draw("opaque", {"scene"}, out);
  frame.sample("post", "scene", out);
  EXPECT_TRUE(out.has("E_EDRAM_NOT_READABLE")) << out.format();
  // Near miss: resolve first, then sample the texture.
  EdramFrame ok;
  ok.declare(color("scene", 640, 360));
  DiagnosticList none;
  ok.draw("opaque", {"scene"}, none);
  ResolveRequest r;
  r.rect = {0, 0, 640, 360};
  ok.resolve("scene", r, "scene_tex", none);
  ok.sample("post", "scene_tex", none);
  EXPECT_TRUE(none.empty()) << none.format();
}

// X2 (3) aliasing: the model's EDRAM keeps a raw 0x8000 word where X1 puts it (the GPU path's
// aliased views: X360GpuTest.RawFixed16WordsSurviveTheAliasedViews).
TEST(X360Edram, MemoryKeepsRawFixed16WordsAcrossAliasedViews) {
  EdramMemory edram;
  EdramSurface a = color("dsf", 640, 360, MsaaSamples::k1X, k1616, 10);
  edram.writeSample(a, 3, 2, 0, packFixed16x2(int16_t(0x8000), int16_t(0x8000)));
  uint32_t word = static_cast<uint32_t>(edram.readSample(a, 3, 2, 0));
  EXPECT_EQ(word, 0x80008000u);
  // "A SNORM-float round trip would give 0x8001."
  EXPECT_EQ(transferThroughSnorm16(uint16_t(word & 0xFFFF)), 0x8001);
  // The bytes sit where the X1 address formula says.
  EXPECT_EQ(edram.readDword(edramByteOffset(a, 3, 2, 0)), word);
}

// ---------------------------------------------------------------------------------------------
// X2: k_16_16 fixed point
// ---------------------------------------------------------------------------------------------

TEST(X360Fixed16, EncodeVectors) {
  // X2 (3).
  EXPECT_EQ(uint16_t(encodeFixed16(0.0f).value), 0x0000);
  EXPECT_EQ(uint16_t(encodeFixed16(1.0f).value), 0x0400);
  EXPECT_EQ(encodeFixed16(1.0f).value, 1024);
  EXPECT_NEAR(decodeFixed16(0x0400), 1.0000305f, 5e-8);
  EXPECT_EQ(uint16_t(encodeFixed16(-1.0f).value), 0xFC00);
  EXPECT_EQ(uint16_t(encodeFixed16(32.0f).value), 0x7FFF);
  EXPECT_EQ(uint16_t(encodeFixed16(-32.0f).value), 0x8001);
  EXPECT_FALSE(encodeFixed16(32.0f).clamped);
  EXPECT_EQ(uint16_t(encodeFixed16(40.0f).value), 0x7FFF);
  EXPECT_EQ(uint16_t(encodeFixed16(-40.0f).value), 0x8001);
  EXPECT_TRUE(encodeFixed16(40.0f).clamped);
  Fixed16Encoded nan = encodeFixed16(std::numeric_limits<float>::quiet_NaN());
  EXPECT_EQ(uint16_t(nan.value), 0x0000);
  EXPECT_TRUE(nan.wasNaN);
}

TEST(X360Fixed16, DecodeRangeEnds) {
  // X2 (1): 0x7FFF = +32, 0x8001 = -32 ("The texture expects 0x8001 = -32, 0x7FFF = 32").
  EXPECT_EQ(decodeFixed16(0x7FFF), 32.0f);
  EXPECT_EQ(decodeFixed16(int16_t(0x8001)), -32.0f);
}

TEST(X360Fixed16, SmallestStepRoundsHalfAwayFromZero) {
  // X2 (3): smallest positive step 32/32767 = 9.7659e-4; v = 0.5 * 32/32767 rounds up to s = 1.
  EXPECT_NEAR(decodeFixed16(1), 9.7659e-4f, 5e-9);
  EXPECT_EQ(encodeFixed16(0.5f * 32.0f / 32767.0f).value, 1);
  EXPECT_EQ(encodeFixed16(-0.5f * 32.0f / 32767.0f).value, -1);
}

TEST(X360Fixed16, DsfValueWithAndWithoutExponentBias) {
  // X2 (3): v = 0.123456 with color_exp_bias 0 -> s = 126 (0x007E), decodes to 0.1230506,
  // error -4.054e-4; with color_exp_bias +5 -> s = 4045 (0x0FCD).
  Fixed16Encoded e0 = encodeFixed16(0.123456f, 0);
  EXPECT_EQ(e0.value, 126);
  EXPECT_EQ(uint16_t(e0.value), 0x007E);
  EXPECT_NEAR(decodeFixed16(e0.value), 0.1230506f, 5e-8);
  EXPECT_NEAR(decodeFixed16(e0.value) - 0.123456f, -4.054e-4f, 5e-8);
  Fixed16Encoded e5 = encodeFixed16(0.123456f, 5);
  EXPECT_EQ(e5.value, 4045);
  EXPECT_EQ(uint16_t(e5.value), 0x0FCD);
}

TEST(X360Fixed16, Decode0x8000DivergesBetweenEmulators) {
  // X2 (3): decoding 0x8000: -32.000977 raw; -32 under canary; -1 under mainline.
  EXPECT_NEAR(decodeFixed16(int16_t(0x8000)), -32.000977f, 5e-7);
  EXPECT_EQ(unpackFixed16ForResolve(int16_t(0x8000)), -32.0f);
  PlatformParams mainline;
  mainline.k16UnpackClamp = K16UnpackClamp::Minus1;
  EXPECT_EQ(unpackFixed16ForResolve(int16_t(0x8000), mainline), -1.0f);
}

TEST(X360Fixed16, ComponentsPackLowHalfFirst) {
  // X2 (1): R in bits 0-15, G in bits 16-31; 64 bpp B and A in the second dword.
  EXPECT_EQ(packFixed16x2(0x0400, int16_t(0xFC00)), 0xFC000400u);
  auto rg = unpackFixed16x2(0xFC000400u);
  EXPECT_EQ(rg[0], 1024);
  EXPECT_EQ(rg[1], -1024);
  EXPECT_EQ(packFixed16x4(1, 2, 3, 4), 0x0004000300020001ull);
}

TEST(X360Fixed16, HostSnormTrickScale) {
  // X2 (2): with snorm16_render_target_full_range the output is multiplied by 2^(bias-5).
  EXPECT_EQ(hostOutputScale(0, K16HostStorage::Snorm16Div32), 1.0f / 32.0f);
  EXPECT_EQ(hostOutputScale(5, K16HostStorage::Snorm16Div32), 1.0f);
  EXPECT_EQ(hostOutputScale(0, K16HostStorage::Snorm16Clamp1), 1.0f);
  EXPECT_EQ(hostResolveExpBiasFold(K16HostStorage::Snorm16Div32), 5);
}

TEST(X360Fixed16, RangeClampAndNanAreCounted) {
  // X2 (4): W_FIXED16_RANGE_CLAMP (count of pixels), W_FIXED16_NAN.
  const float rg[] = {40.0f, 0.0f, 1.0f, -33.0f, 0.5f, 0.5f};
  DiagnosticList out;
  std::vector<uint32_t> words = encodeFixed16x2Image("dsf", rg, 0, out);
  ASSERT_EQ(words.size(), 3u);
  ASSERT_TRUE(out.has("W_FIXED16_RANGE_CLAMP"));
  EXPECT_NE(out.first("W_FIXED16_RANGE_CLAMP")->message.find("2 pixel"), std::string::npos);
  EXPECT_FALSE(out.has("W_FIXED16_NAN"));
  const float withNan[] = {std::numeric_limits<float>::quiet_NaN(), 0.0f};
  DiagnosticList nan;
  EXPECT_EQ(encodeFixed16x2Image("dsf", withNan, 0, nan)[0], 0u);
  EXPECT_TRUE(nan.has("W_FIXED16_NAN"));
  // Near miss: exactly +-32 is in range.
  const float edge[] = {32.0f, -32.0f};
  DiagnosticList none;
  encodeFixed16x2Image("dsf", edge, 0, none);
  EXPECT_TRUE(none.empty()) << none.format();
}

TEST(X360Fixed16, UnitRangeWithoutBiasWastesPrecision) {
  // X2 (4): W_FIXED16_PRECISION when the shader only uses [0,1] with bias 0.
  const float unit[] = {0.0f, 0.25f, 1.0f, 0.75f};
  DiagnosticList out;
  encodeFixed16x2Image("dsf", unit, 0, out);
  EXPECT_TRUE(out.has("W_FIXED16_PRECISION"));
  // Near misses: bias +5 (path B), or outputs spread over -32..32 (path C).
  DiagnosticList biased;
  encodeFixed16x2Image("dsf", unit, 5, biased);
  EXPECT_FALSE(biased.has("W_FIXED16_PRECISION"));
  DiagnosticList wide;
  checkFixed16OutputRange("dsf", -32.0f, 32.0f, 0, wide);
  EXPECT_TRUE(wide.empty());
}

TEST(X360Fixed16, MultiplicativeBlendUnderTheSnormTrick) {
  // X2 (4): W_FIXED16_MULT_BLEND with DEST_COLOR / SRC_COLOR while the host uses SNORM / 32.
  BlendState modulate{true, BlendFactor::DestColor, BlendFactor::Zero, BlendFactor::One, BlendFactor::Zero};
  DiagnosticList out;
  checkFixed16Blend("lbuffer", modulate, K16HostStorage::Snorm16Div32, out);
  EXPECT_TRUE(out.has("W_FIXED16_MULT_BLEND"));
  // Near misses: additive blending, or an interlock host.
  BlendState add{true, BlendFactor::One, BlendFactor::One, BlendFactor::One, BlendFactor::One};
  DiagnosticList none;
  checkFixed16Blend("lbuffer", add, K16HostStorage::Snorm16Div32, none);
  checkFixed16Blend("lbuffer", modulate, K16HostStorage::Interlock, none);
  EXPECT_TRUE(none.empty());
}

// ---------------------------------------------------------------------------------------------
// X3: resolves
// ---------------------------------------------------------------------------------------------

TEST(X360Resolve, D3DFormatWords) {
  // X3 (1): D3DFMT_V16U16 = 0x2D20AB99 (k_16_16 with all four sign fields = 1); D3DFMT_G16R16 =
  // 0x2D200199 (unsigned); D3DFMT_G16R16_EDRAM = 0x2D20AB8D (texture format 13). X2: k_16_16 is
  // ColorFormat 25, k_16_16_EDRAM 13.
  D3DFormatFields v = decodeD3DFormatWord(kD3DFMT_V16U16);
  EXPECT_EQ(v.textureFormat, uint32_t(ColorFormat::k_16_16));
  EXPECT_EQ(v.textureFormat, 25u);
  for (uint32_t sign : v.signs) EXPECT_EQ(sign, 1u);
  D3DFormatFields g = decodeD3DFormatWord(kD3DFMT_G16R16);
  EXPECT_EQ(g.textureFormat, 25u);
  for (uint32_t sign : g.signs) EXPECT_EQ(sign, 0u);
  D3DFormatFields e = decodeD3DFormatWord(kD3DFMT_G16R16_EDRAM);
  EXPECT_EQ(e.textureFormat, kTextureFormat_16_16_EDRAM);
  EXPECT_EQ(e.textureFormat, 13u);
  EXPECT_TRUE(v.tiled && g.tiled && e.tiled);
}

TEST(X360Resolve, PathANaive) {
  // X3 (3) path A: EDRAM 126 (0x007E); f = 0.1230506, unorm16 = 8064 (0x1F80); sampled
  // 0.12304875; error -4.07e-4; about 10 bits.
  DsfPathResult r = runDsfPath(dsfPath(DsfResolvePath::NaiveA), 0.123456f);
  EXPECT_EQ(r.edram, 126);
  EXPECT_NEAR(r.resolved.value, 0.1230506f, 5e-8);
  EXPECT_EQ(r.resolved.word, 0x1F80);
  EXPECT_EQ(r.resolved.word, 8064);
  EXPECT_NEAR(r.sampled, 0.12304875f, 5e-9);
  EXPECT_NEAR(r.reconstructed - 0.123456f, -4.07e-4f, 5e-7);
  EXPECT_EQ(dsfPathPrecision(dsfPath(DsfResolvePath::NaiveA)).roundedBits, 10);
}

TEST(X360Resolve, PathBXdkIdiom) {
  // X3 (3) path B: EDRAM 4045 (0x0FCD); f = 4045/32767 = 0.12344737, unorm16 = 8090 (0x1F9A);
  // sampled 8090/65535 = 0.12344549; error -1.05e-5; 15 bits.
  DsfPathResult r = runDsfPath(dsfPath(DsfResolvePath::XdkBiasB), 0.123456f);
  EXPECT_EQ(r.edram, 4045);
  EXPECT_NEAR(r.resolved.value, 0.12344737f, 5e-9);
  EXPECT_EQ(r.resolved.word, 0x1F9A);
  EXPECT_NEAR(r.sampled, 0.12344549f, 5e-9);
  EXPECT_NEAR(r.reconstructed - 0.123456f, -1.05e-5f, 5e-8);
  EXPECT_EQ(dsfPathPrecision(dsfPath(DsfResolvePath::XdkBiasB)).roundedBits, 15);
}

TEST(X360Resolve, PathCPaperSignedFormat) {
  // X3 (3) path C: c = 64v - 32 = -24.098816; EDRAM -24676 (0x9F9C), raw int16 kept;
  // t = -0.75307474 -> v' = (t+1)/2 = 0.12346263; error +6.63e-6; 16 bits, step 1/65534 =
  // 1.526e-5, max error 7.63e-6.
  DsfPathSpec c = dsfPath(DsfResolvePath::PaperSignedC);
  EXPECT_NEAR(0.123456f * c.shaderScale + c.shaderOffset, -24.098816f, 5e-6);
  DsfPathResult r = runDsfPath(c, 0.123456f);
  EXPECT_EQ(r.edram, -24676);
  EXPECT_EQ(uint16_t(r.edram), 0x9F9C);
  EXPECT_EQ(r.resolved.word, 0x9F9C);
  EXPECT_NEAR(r.sampled, -0.75307474f, 5e-9);
  // The pack's v' and error are exact arithmetic. The sampling shader runs in fp32: t is already
  // rounded to 2^-25 (half an ULP at 0.75) and t + 1 cancels, so v' = (t + 1) / 2 carries up to
  // 2^-26 + half an ULP of v' (about 2e-8, two ULPs at 0.12) of fetch rounding.
  EXPECT_NEAR(r.reconstructed, 0.12346263f, 2e-8);
  EXPECT_NEAR(r.reconstructed - 0.123456f, 6.63e-6f, 2e-8);
  PathPrecision p = dsfPathPrecision(c);
  EXPECT_EQ(p.roundedBits, 16);
  EXPECT_EQ(p.levels, 65535u);  // int16 -32767..32767
  EXPECT_NEAR(1.0 / (p.levels - 1), 1.526e-5, 5e-9);
  EXPECT_NEAR(0.5 / (p.levels - 1), 7.63e-6, 5e-9);
}

TEST(X360Resolve, PathCThroughMainlineLosesTheLowerHalf) {
  // X3 (3): C through mainline Xenia (unsigned saturate): -24676 -> 0x0000, sampled 0.0;
  // "mainline loses every v < 0.5".
  PlatformParams mainline;
  mainline.signedK16Resolve = SignedK16Resolve::UnsignedSaturate;
  DsfPathSpec c = dsfPath(DsfResolvePath::PaperSignedC);
  DsfPathResult r = runDsfPath(c, 0.123456f, mainline);
  EXPECT_EQ(r.edram, -24676);
  EXPECT_EQ(r.resolved.word, 0x0000);
  EXPECT_EQ(r.sampled, 0.0f);
  EXPECT_TRUE(r.resolved.signLost);
  for (float v : {0.0f, 0.25f, 0.49f}) EXPECT_EQ(runDsfPath(c, v, mainline).resolved.word, 0x0000) << v;
}

TEST(X360Resolve, SignedReencodeClampsOnlyTheDoubleMinusOne) {
  // Open question 1 alternatives: canary's EDRAM-style re-encode keeps every int16 but 0x8000
  // (clamped to -32 = 0x8001); the default keeps the raw word.
  const int16_t raw[] = {int16_t(0x8000)};
  PlatformParams canary;
  canary.signedK16Resolve = SignedK16Resolve::ReencodeEdramStyle;
  EXPECT_EQ(resolveFixed16Component(raw, 0, SurfaceNumberFormat::kSignedRepeatingFraction).word, 0x8000);
  EXPECT_EQ(resolveFixed16Component(raw, 0, SurfaceNumberFormat::kSignedRepeatingFraction, canary).word, 0x8001);
  const int16_t c[] = {-24676};
  EXPECT_EQ(resolveFixed16Component(c, 0, SurfaceNumberFormat::kSignedRepeatingFraction, canary).word, 0x9F9C);
}

TEST(X360Resolve, MsaaAveragingVector) {
  // X3 (3): 2x, s0 = 0x0800 (+2.000061), s1 = 0xF800 (-2.000061), k01, bias 0: the model (and
  // canary's -32 clamp) averages in float and gives 0.0; mainline clamps at -1 and gives
  // (2.000061 - 1)/2 = 0.50003.
  EXPECT_NEAR(decodeFixed16(0x0800), 2.000061f, 5e-7);
  EXPECT_NEAR(decodeFixed16(int16_t(0xF800)), -2.000061f, 5e-7);
  const int16_t samples[] = {0x0800, int16_t(0xF800)};
  ResolvedComponent model = resolveFixed16Component(samples, 0, SurfaceNumberFormat::kUnsignedRepeatingFraction);
  EXPECT_EQ(model.value, 0.0f);
  EXPECT_EQ(model.word, 0);
  PlatformParams mainline;
  mainline.k16UnpackClamp = K16UnpackClamp::Minus1;
  ResolvedComponent xenia =
      resolveFixed16Component(samples, 0, SurfaceNumberFormat::kUnsignedRepeatingFraction, mainline);
  EXPECT_NEAR(xenia.value, 0.50003f, 5e-6);
}

TEST(X360Resolve, MsaaAveragingThroughEdramMemory) {
  // The same X3 (3) vector end to end: the two samples are written where X1 places 2x samples,
  // the k01 resolve averages them to 0.0.
  EdramMemory edram;
  EdramSurface s = color("dsf", 64, 32, MsaaSamples::k2X, k1616, 0);
  edram.writeSample(s, 0, 0, 0, packFixed16x2(0x0800, 0x0800));
  edram.writeSample(s, 0, 0, 1, packFixed16x2(int16_t(0xF800), int16_t(0xF800)));
  ResolveRequest r;
  r.rect = {0, 0, 8, 8};
  r.destFormat = ColorFormat::k_16_16;
  r.sampleSelect = CopySampleSelect::k01;
  DiagnosticList out;
  ResolvedTexture t = resolveSurface(edram, s, r, out);
  ASSERT_EQ(t.texels.size(), 64u);
  EXPECT_EQ(t.texels[0], 0u);
  EXPECT_TRUE(out.empty()) << out.format();
}

TEST(X360Resolve, AlignmentAndPackedMips) {
  // X3 (4): E_RESOLVE_ALIGNMENT (not a multiple of 8 px), E_RESOLVE_PACKED_MIP (< 32x32).
  EdramSurface s = color("scene", 640, 360);
  ResolveRequest bad;
  bad.rect = {4, 0, 64, 64};
  DiagnosticList a;
  checkResolveRequest(s, bad, a);
  EXPECT_TRUE(a.has("E_RESOLVE_ALIGNMENT"));
  ResolveRequest size;
  size.rect = {0, 0, 60, 64};
  DiagnosticList b;
  checkResolveRequest(s, size, b);
  EXPECT_TRUE(b.has("E_RESOLVE_ALIGNMENT"));
  ResolveRequest mip;
  mip.rect = {0, 0, 16, 16};
  mip.destMipWidth = 16;
  mip.destMipHeight = 16;
  DiagnosticList c;
  checkResolveRequest(s, mip, c);
  EXPECT_TRUE(c.has("E_RESOLVE_PACKED_MIP"));
  // Near misses: aligned rectangle into a 32x32 mip.
  ResolveRequest ok;
  ok.rect = {8, 16, 32, 32};
  ok.destMipWidth = 32;
  ok.destMipHeight = 32;
  DiagnosticList none;
  checkResolveRequest(s, ok, none);
  EXPECT_TRUE(none.empty()) << none.format();
}

TEST(X360Resolve, SignLossAndRangeClampAreCounted) {
  // X3 (4): W_RESOLVE_SIGN_LOSS (negative k_16_16 into copy_dest_number = 0, count reported) and
  // W_RESOLVE_RANGE_CLAMP (|f * 2^bias| > 1 into UNORM).
  EdramMemory edram;
  EdramSurface s = color("dsf", 64, 32, MsaaSamples::k1X, k1616, 0);
  edram.writeSample(s, 0, 0, 0, packFixed16x2(-24676, 100));  // negative
  edram.writeSample(s, 1, 0, 0, packFixed16x2(2048, 100));    // +2.000061
  ResolveRequest r;
  r.rect = {0, 0, 8, 8};
  r.destFormat = ColorFormat::k_16_16;
  DiagnosticList out;
  resolveSurface(edram, s, r, out);
  ASSERT_TRUE(out.has("W_RESOLVE_SIGN_LOSS")) << out.format();
  EXPECT_NE(out.first("W_RESOLVE_SIGN_LOSS")->message.find("1 texel"), std::string::npos);
  EXPECT_TRUE(out.has("W_RESOLVE_RANGE_CLAMP"));
  // Near miss: the same data into a signed destination keeps the sign; small positive values fit.
  r.destNumber = SurfaceNumberFormat::kSignedRepeatingFraction;
  DiagnosticList signedDest;
  ResolvedTexture t = resolveSurface(edram, s, r, signedDest);
  EXPECT_FALSE(signedDest.has("W_RESOLVE_SIGN_LOSS"));
  EXPECT_EQ(t.texels[0] & 0xFFFF, 0x9F9Cu);
  EdramMemory small;
  small.writeSample(s, 0, 0, 0, packFixed16x2(1000, 100));
  r.destNumber = SurfaceNumberFormat::kUnsignedRepeatingFraction;
  DiagnosticList none;
  resolveSurface(small, s, r, none);
  EXPECT_TRUE(none.empty()) << none.format();
}

TEST(X360Resolve, PrecisionBelowSixteenBitsIsReported) {
  // X3 (4): W_RESOLVE_PRECISION(bits), e.g. A = 10, B = 15, C = 16.
  DiagnosticList a, b, c;
  checkDsfPathPrecision("dsf", dsfPath(DsfResolvePath::NaiveA), a);
  checkDsfPathPrecision("dsf", dsfPath(DsfResolvePath::XdkBiasB), b);
  checkDsfPathPrecision("dsf", dsfPath(DsfResolvePath::PaperSignedC), c);
  ASSERT_TRUE(a.has("W_RESOLVE_PRECISION"));
  EXPECT_NE(a.first("W_RESOLVE_PRECISION")->message.find("10 effective bits"), std::string::npos);
  ASSERT_TRUE(b.has("W_RESOLVE_PRECISION"));
  EXPECT_NE(b.first("W_RESOLVE_PRECISION")->message.find("15 effective bits"), std::string::npos);
  EXPECT_TRUE(c.empty()) << c.format();  // near miss: 16 bits
}

TEST(X360Resolve, DepthResolvesDoNotConvert) {
  // X3 (4): E_DEPTH_RESOLVE_CONVERT for format conversion, averaging or exponent bias.
  EdramSurface d = depth("depth", 640, 360, MsaaSamples::k2X);
  ResolveRequest bias;
  bias.rect = {0, 0, 640, 360};
  bias.destExpBias = -5;
  DiagnosticList a;
  checkResolveRequest(d, bias, a);
  EXPECT_TRUE(a.has("E_DEPTH_RESOLVE_CONVERT"));
  ResolveRequest average;
  average.rect = {0, 0, 640, 360};
  average.sampleSelect = CopySampleSelect::k01;
  DiagnosticList b;
  checkResolveRequest(d, average, b);
  EXPECT_TRUE(b.has("E_DEPTH_RESOLVE_CONVERT"));
  // Near miss: a plain copy of one sample.
  ResolveRequest copy;
  copy.rect = {0, 0, 640, 360};
  DiagnosticList none;
  checkResolveRequest(d, copy, none);
  EXPECT_TRUE(none.empty()) << none.format();
}

// ---------------------------------------------------------------------------------------------
// X4: inferred-lighting placement
// ---------------------------------------------------------------------------------------------

namespace {

InferredLightingLayout packLayout() {
  // X4 (3): 1024x576 1x: G0 (RGBA8) at 0, G1 (DSF k_16_16) at 468, D24S8 at 936;
  // L-buffer (k_16_16_16_16) at 0.
  InferredLightingLayout l;
  l.gbufferColor = {color("G0", 1024, 576, MsaaSamples::k1X, ColorRenderTargetFormat::k_8_8_8_8, 0),
                    color("G1", 1024, 576, MsaaSamples::k1X, k1616, 468)};
  l.depth = depth("depth", 1024, 576, MsaaSamples::k1X, 936);
  l.lbuffer = color("L", 1024, 576, MsaaSamples::k1X, k64, 0);
  return l;
}

}  // namespace

TEST(X360InferredLighting, PackLayoutIsValid) {
  // X4 (3): valid, total 1404 tiles; L-buffer 936 tiles [0, 936) aliases only G0 and G1.
  InferredLightingLayout l = packLayout();
  EXPECT_EQ(l.gbufferColor[0].sizeTiles(), 468u);
  EXPECT_EQ(l.gbufferColor[1].sizeTiles(), 468u);
  EXPECT_EQ(l.depth.sizeTiles(), 468u);
  EXPECT_EQ(l.lbuffer.sizeTiles(), 936u);
  DiagnosticList out;
  checkInferredLightingLayout(l, out);
  EXPECT_TRUE(out.empty()) << out.format();
}

TEST(X360InferredLighting, LBufferOverDepthIsRejected) {
  // X4 (3): L-buffer at base 500 -> [500, 1436) intersects depth [936, 1404): E_LBUF_DEPTH_ALIAS.
  InferredLightingLayout l = packLayout();
  l.lbuffer.baseTile = 500;
  DiagnosticList out;
  checkInferredLightingLayout(l, out);
  ASSERT_TRUE(out.has("E_LBUF_DEPTH_ALIAS")) << out.format();
  const Diagnostic* d = out.first("E_LBUF_DEPTH_ALIAS");
  EXPECT_NE(d->message.find("[500, 1436)"), std::string::npos) << d->message;
  EXPECT_NE(d->message.find("[936, 1404)"), std::string::npos) << d->message;
  EXPECT_FALSE(out.has("E_GBUF_OVERLAP"));
}

TEST(X360InferredLighting, OverlappingGBuffersAreRejected) {
  // X4 (3): G1 at base 400 -> [400, 868) intersects G0 [0, 468): E_GBUF_OVERLAP.
  InferredLightingLayout l = packLayout();
  l.gbufferColor[1].baseTile = 400;
  DiagnosticList out;
  checkInferredLightingLayout(l, out);
  ASSERT_TRUE(out.has("E_GBUF_OVERLAP")) << out.format();
  EXPECT_NE(out.first("E_GBUF_OVERLAP")->message.find("[400, 868)"), std::string::npos);
  EXPECT_FALSE(out.has("E_LBUF_DEPTH_ALIAS"));
}

TEST(X360InferredLighting, LBufferMayOnlyReuseResolvedGBufferTiles) {
  // X4 (1)/(4): the L-buffer may alias G-buffer colour tiles once they are resolved;
  // E_USE_BEFORE_RESOLVE when the aliasing write comes first.
  auto run = [](bool resolveFirst) {
    InferredLightingLayout l = packLayout();
    EdramFrame frame;
    for (EdramSurface s : l.gbufferColor) {
      s.role = SurfaceRole::GBuffer;
      frame.declare(s);
    }
    EdramSurface d = l.depth;
    d.role = SurfaceRole::GBuffer;
    frame.declare(d);
    EdramSurface lb = l.lbuffer;
    lb.role = SurfaceRole::LBuffer;
    frame.declare(lb);
    DiagnosticList out;
    frame.draw("geometry", {"G0", "G1", "depth"}, out);
    if (resolveFirst) {
      ResolveRequest r;
      r.rect = {0, 0, 1024, 576};
      frame.resolve("G0", r, "G0_tex", out);
      frame.resolve("G1", r, "G1_tex", out);
    }
    frame.draw("light", {"L", "depth"}, out);
    frame.sample("light", resolveFirst ? "G1_tex" : "G1", out);
    return out;
  };
  DiagnosticList early = run(false);
  EXPECT_TRUE(early.has("E_USE_BEFORE_RESOLVE")) << early.format();
  DiagnosticList ok = run(true);
  EXPECT_TRUE(ok.empty()) << ok.format();
}

// ---------------------------------------------------------------------------------------------
// X5: pixel centres
// ---------------------------------------------------------------------------------------------

TEST(X360PixelCenter, QuadUvAtPixel) {
  // X5 (3): quad (0,0)-(4,4), UV 0..1 over a 4x4 texture, pixel (3,1): PIX_CENTER=0 gives
  // (0.75, 0.25); PIX_CENTER=1 gives (0.875, 0.375).
  ScreenQuad q{0, 0, 4, 4, 0, 0, 1, 1};
  ScreenPoint d3d9 = quadUvAtPixel(q, 3, 1, PixelCenter::kD3DZero);
  EXPECT_EQ(d3d9.x, 0.75f);
  EXPECT_EQ(d3d9.y, 0.25f);
  ScreenPoint d3d10 = quadUvAtPixel(q, 3, 1, PixelCenter::kOGLHalf);
  EXPECT_EQ(d3d10.x, 0.875f);
  EXPECT_EQ(d3d10.y, 0.375f);
}

TEST(X360PixelCenter, BilinearFootprints) {
  // X5 (3): at (0.75, 0.25) bilinear clamp sampling averages 4 texels; (0.875, 0.375) is exactly
  // texel (3,1). Texel selection per X5 (1): linear floor(U*W - 0.5), point floor(U*W).
  LinearFootprint corner = linearFootprint(0.75f, 0.25f, 4, 4);
  EXPECT_EQ(corner.x0, 2);
  EXPECT_EQ(corner.y0, 0);
  EXPECT_EQ(corner.fx, 0.5f);
  EXPECT_EQ(corner.fy, 0.5f);
  LinearFootprint centre = linearFootprint(0.875f, 0.375f, 4, 4);
  EXPECT_EQ(centre.x0, 3);
  EXPECT_EQ(centre.y0, 1);
  EXPECT_EQ(centre.fx, 0.0f);
  EXPECT_EQ(centre.fy, 0.0f);
  EXPECT_EQ(pointTexel(0.875f, 4), 3);
  EXPECT_EQ(pointTexel(0.375f, 4), 1);
}

TEST(X360PixelCenter, ThinQuadCoverage) {
  // X5 (3): thin quad x in [0.5, 1.5), y in [0, 4): D3D9 covers column 1; D3D10 covers column 0.
  ScreenQuad q{0.5f, 0.0f, 1.5f, 4.0f};
  EXPECT_FALSE(quadCoversPixel(q, 0, 1, PixelCenter::kD3DZero));
  EXPECT_TRUE(quadCoversPixel(q, 1, 1, PixelCenter::kD3DZero));
  EXPECT_TRUE(quadCoversPixel(q, 0, 1, PixelCenter::kOGLHalf));
  EXPECT_FALSE(quadCoversPixel(q, 1, 1, PixelCenter::kOGLHalf));
}

TEST(X360PixelCenter, ResolveRectangle) {
  // X5 (3): RECTLIST (-0.5,-0.5)-(1279.5,719.5) with PIX_CENTER=0 resolves [0,1280) x [0,720).
  PixelRect r = resolveRectFromVertices({-0.5f, -0.5f}, {1279.5f, 719.5f}, PixelCenter::kD3DZero);
  EXPECT_EQ(r.x0, 0);
  EXPECT_EQ(r.y0, 0);
  EXPECT_EQ(r.x1, 1280);
  EXPECT_EQ(r.y1, 720);
}

TEST(X360PixelCenter, HalfPixelOffsetMapping) {
  // X5 (1): HALFPIXELOFFSET TRUE sets PIX_CENTER = 1, FALSE (the default) PIX_CENTER = 0
  // (open question 5); the host adds +0.5 px for D3D9 centres (Xenia, DXVK: p_vk = p_d3d9 + 0.5).
  EXPECT_EQ(pixelCenterFor(true), PixelCenter::kOGLHalf);
  EXPECT_EQ(pixelCenterFor(false), PixelCenter::kD3DZero);
  EXPECT_EQ(pixelCenterFor(PlatformParams{}.halfPixelOffset), PixelCenter::kD3DZero);
  PlatformParams inverted;
  inverted.halfPixelOffsetMapping = HalfPixelOffsetMapping::TrueMeansPixCenterZero;
  EXPECT_EQ(pixelCenterFor(true, inverted), PixelCenter::kD3DZero);
  EXPECT_EQ(hostWindowOffset(PixelCenter::kD3DZero), 0.5f);
  EXPECT_EQ(hostWindowOffset(PixelCenter::kOGLHalf), 0.0f);
}

TEST(X360PixelCenter, D3D9CentresOnScreenSpaceDraws) {
  // X5 (4): W_D3D9_PIXEL_CENTER: vertices on integer screen positions and UV = pos/size.
  const ScreenVertex naive[] = {{0, 0, 0, 0}, {1280, 0, 1, 0}, {0, 720, 0, 1}, {1280, 720, 1, 1}};
  DiagnosticList out;
  checkScreenSpaceDraw("tonemap", naive, 1280, 720, PixelCenter::kD3DZero, out);
  EXPECT_TRUE(out.has("W_D3D9_PIXEL_CENTER"));
  // Near misses: the -0.5 compensation, or HALFPIXELOFFSET set.
  const ScreenVertex shifted[] = {{-0.5f, -0.5f, 0, 0}, {1279.5f, -0.5f, 1, 0}, {-0.5f, 719.5f, 0, 1},
                                  {1279.5f, 719.5f, 1, 1}};
  DiagnosticList none;
  checkScreenSpaceDraw("tonemap", shifted, 1280, 720, PixelCenter::kD3DZero, none);
  checkScreenSpaceDraw("tonemap", naive, 1280, 720, PixelCenter::kOGLHalf, none);
  EXPECT_TRUE(none.empty()) << none.format();
}

TEST(X360PixelCenter, ModeChangeWithinAPass) {
  // X5 (4): I_HALFPIXEL_MODE_CHANGE when the state flips within a pass.
  const PixelCenter flips[] = {PixelCenter::kD3DZero, PixelCenter::kOGLHalf};
  DiagnosticList out;
  checkPassPixelCenters("post", flips, out);
  ASSERT_TRUE(out.has("I_HALFPIXEL_MODE_CHANGE"));
  EXPECT_EQ(out.first("I_HALFPIXEL_MODE_CHANGE")->severity, Severity::Info);
  const PixelCenter steady[] = {PixelCenter::kD3DZero, PixelCenter::kD3DZero};
  DiagnosticList none;
  checkPassPixelCenters("post", steady, none);
  EXPECT_TRUE(none.empty());
}

TEST(X360Platform, LogicalTargets) {
  // X2/X3: a two-channel 16-bit target is k_16_16 in EDRAM; X4: the L-buffer is 64 bpp.
  TargetMapping dsf = mapTarget(parity::platforms::LogicalFormat::Rg16Unorm);
  EXPECT_NE(dsf.consoleFormat.find("k_16_16"), std::string::npos);
  EXPECT_EQ(dsf.consoleBytesPerPixel, 4u);
  EXPECT_NE(dsf.write.find("path C"), std::string::npos);
  EXPECT_EQ(mapTarget(parity::platforms::LogicalFormat::Rgba16Hdr).consoleBytesPerPixel, 8u);
}
