// PS3 CPU model against the reference pack's vectors (console-quirks.md, P1-P4).
// Every expected value below is quoted from the pack; the comment names the section.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>

#include "platforms/ps3/depth_read.h"
#include "platforms/ps3/msaa_layout.h"
#include "platforms/ps3/packed16.h"
#include "platforms/ps3/ps3_platform.h"
#include "platforms/ps3/remap.h"
#include "platforms/ps3/surface.h"
#include "platforms/x360/edram.h"

using namespace parity::platforms;
using namespace parity::platforms::ps3;

namespace {

int64_t ulpDistance(float a, float b) {
  auto key = [](float f) {
    int32_t i = std::bit_cast<int32_t>(f);
    return i < 0 ? int64_t(std::numeric_limits<int32_t>::min()) - i : int64_t(i);
  };
  return std::llabs(key(a) - key(b));
}

// Within `ulps` of the fp32 value nearest to `exact`.
::testing::AssertionResult withinUlps(float actual, double exact, int64_t ulps) {
  float nearest = static_cast<float>(exact);
  int64_t d = ulpDistance(actual, nearest);
  if (d <= ulps) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << actual << " is " << d << " ULP from " << exact;
}

ColorSurface surface(std::string name, SurfaceColorFormat f, bool packed = false) {
  ColorSurface s;
  s.name = std::move(name);
  s.format = f;
  s.packed16x2 = packed;
  return s;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// P1: colour surfaces and MRT
// ---------------------------------------------------------------------------------------------

TEST(Ps3Surface, BytesPerPixel) {
  // P1 (1): B8 = 1; G8B8, R5G6B5, X1R5G5B5 = 2; all 8888 formats and X32 = 4; W16Z16Y16X16 = 8;
  // W32Z32Y32X32 = 16.
  EXPECT_EQ(bytesPerPixel(SurfaceColorFormat::B8), 1u);
  EXPECT_EQ(bytesPerPixel(SurfaceColorFormat::G8B8), 2u);
  EXPECT_EQ(bytesPerPixel(SurfaceColorFormat::R5G6B5), 2u);
  EXPECT_EQ(bytesPerPixel(SurfaceColorFormat::X1R5G5B5_Z1R5G5B5), 2u);
  EXPECT_EQ(bytesPerPixel(SurfaceColorFormat::X1R5G5B5_O1R5G5B5), 2u);
  EXPECT_EQ(bytesPerPixel(SurfaceColorFormat::A8R8G8B8), 4u);
  EXPECT_EQ(bytesPerPixel(SurfaceColorFormat::X8R8G8B8_Z8R8G8B8), 4u);
  EXPECT_EQ(bytesPerPixel(SurfaceColorFormat::A8B8G8R8), 4u);
  EXPECT_EQ(bytesPerPixel(SurfaceColorFormat::F_X32), 4u);
  EXPECT_EQ(bytesPerPixel(SurfaceColorFormat::F_W16Z16Y16X16), 8u);
  EXPECT_EQ(bytesPerPixel(SurfaceColorFormat::F_W32Z32Y32X32), 16u);
  // P1 (1) codes.
  EXPECT_EQ(int(SurfaceColorFormat::A8R8G8B8), 8);
  EXPECT_EQ(int(SurfaceColorFormat::F_W16Z16Y16X16), 11);
}

TEST(Ps3Surface, NoTwoChannel16BitSurface) {
  // P1 (1)/(4): E_RSX_NO_RG16_SURFACE; P2: the workaround is a packed A8R8G8B8 surface.
  DiagnosticList out;
  EXPECT_FALSE(requestColorSurface({"dsf", 2, 16, false, false}, out).has_value());
  EXPECT_TRUE(out.has("E_RSX_NO_RG16_SURFACE"));
  DiagnosticList fp;
  EXPECT_FALSE(requestColorSurface({"velocity", 2, 16, true, true}, fp).has_value());
  EXPECT_TRUE(fp.has("E_RSX_NO_RG16_SURFACE"));
  // Near miss: the same request with packing allowed.
  DiagnosticList none;
  auto packed = requestColorSurface({"dsf", 2, 16, false, true}, none);
  ASSERT_TRUE(packed.has_value());
  EXPECT_EQ(packed->format, SurfaceColorFormat::A8R8G8B8);
  EXPECT_TRUE(packed->packed16x2);
  EXPECT_TRUE(none.empty());
}

TEST(Ps3Mrt, NormalPlusPackedDsfIsValid) {
  // P1 (3): A8R8G8B8 plus DSF-packed A8R8G8B8: same bpp and same format. Valid.
  const ColorSurface t[] = {surface("normals", SurfaceColorFormat::A8R8G8B8),
                            surface("dsf", SurfaceColorFormat::A8R8G8B8, true)};
  for (Ps3MrtRule rule : {Ps3MrtRule::SameFormat, Ps3MrtRule::SameBpp}) {
    DiagnosticList out;
    checkMrt("geometry", t, rule, out);
    EXPECT_TRUE(out.empty()) << out.format();
  }
}

TEST(Ps3Mrt, DifferentBppIsRejected) {
  // P1 (3): A8R8G8B8 with F_W16Z16Y16X16 (4 B vs 8 B) and R5G6B5 with A8R8G8B8 (2 B vs 4 B): reject.
  const ColorSurface wide[] = {surface("a", SurfaceColorFormat::A8R8G8B8),
                               surface("b", SurfaceColorFormat::F_W16Z16Y16X16)};
  const ColorSurface narrow[] = {surface("a", SurfaceColorFormat::R5G6B5), surface("b", SurfaceColorFormat::A8R8G8B8)};
  for (auto targets : {std::span<const ColorSurface>(wide), std::span<const ColorSurface>(narrow)}) {
    DiagnosticList strict, bpp;
    checkMrt("pass", targets, Ps3MrtRule::SameFormat, strict);
    checkMrt("pass", targets, Ps3MrtRule::SameBpp, bpp);
    EXPECT_TRUE(strict.has("E_MRT_FORMAT_MISMATCH"));
    EXPECT_TRUE(bpp.has("E_MRT_BPP_MISMATCH"));
  }
}

TEST(Ps3Mrt, StrictModeRejectsDifferentFormatsOfEqualBpp) {
  // P1 (1): strict PS3 mode requires one format; D3D9/paper mode only the same bpp.
  const ColorSurface t[] = {surface("a", SurfaceColorFormat::A8R8G8B8),
                            surface("b", SurfaceColorFormat::X8R8G8B8_Z8R8G8B8)};
  DiagnosticList strict, bpp;
  checkMrt("pass", t, Ps3MrtRule::SameFormat, strict);
  checkMrt("pass", t, Ps3MrtRule::SameBpp, bpp);
  EXPECT_TRUE(strict.has("E_MRT_FORMAT_MISMATCH"));
  EXPECT_TRUE(bpp.empty()) << bpp.format();  // near miss for E_MRT_BPP_MISMATCH
}

TEST(Ps3Mrt, OneBlendFunctionForAllTargets) {
  // P1 (3): two A8R8G8B8 targets with different blend functions requested: warn.
  ColorSurface a = surface("a", SurfaceColorFormat::A8R8G8B8), b = surface("b", SurfaceColorFormat::A8R8G8B8);
  a.blend = {true, BlendFactor::SrcAlpha, BlendFactor::OneMinusSrcAlpha, BlendFactor::One, BlendFactor::Zero};
  b.blend = {true, BlendFactor::One, BlendFactor::One, BlendFactor::One, BlendFactor::One};
  const ColorSurface differ[] = {a, b};
  DiagnosticList out;
  checkMrt("pass", differ, Ps3MrtRule::SameFormat, out);
  EXPECT_TRUE(out.has("W_MRT_SHARED_BLEND"));
  // Near miss: the same function (enables are per target).
  b.blend = a.blend;
  const ColorSurface same[] = {a, b};
  DiagnosticList none;
  checkMrt("pass", same, Ps3MrtRule::SameFormat, none);
  b.blend.enabled = false;
  b.blend.srcColor = BlendFactor::DestColor;
  const ColorSurface oneBlended[] = {a, b};
  checkMrt("pass", oneBlended, Ps3MrtRule::SameFormat, none);
  EXPECT_TRUE(none.empty()) << none.format();
}

// ---------------------------------------------------------------------------------------------
// P2: packing two 16-bit values, Y16_X16 read-back
// ---------------------------------------------------------------------------------------------

TEST(Ps3Packed16, FormatCodes) {
  // P2 (1): CELL_GCM_TEXTURE_Y16_X16 = 0x95, A8R8G8B8 = 0x85, LN = 0x20, UN = 0x40.
  EXPECT_EQ(kTextureY16X16, 0x95);
  EXPECT_EQ(kTextureA8R8G8B8, 0x85);
  EXPECT_EQ(kTextureFlagLN, 0x20);
  EXPECT_EQ(kTextureFlagUN, 0x40);
  EXPECT_EQ(kRemapIdentity, 0xAAE4u);
}

TEST(Ps3Packed16, DsfValueVector) {
  // P2 (3): (0.123456, 0.987654): X16 = 8091 (0x1F9B), Y16 = 64726 (0xFCD6); bytes 1F 9B FC D6
  // (word 0x1F9BFCD6); .r = 0.12346075 (error 4.75e-6), .g = 0.98765545; host RG16 after the
  // swap (0x1F9B, 0xFCD6).
  EXPECT_EQ(quantizeUnorm16(0.123456f), 8091);
  EXPECT_EQ(quantizeUnorm16(0.987654f), 64726);
  Argb8Bytes b = packTwo16InArgb8(0.123456f, 0.987654f);
  EXPECT_EQ(b, (Argb8Bytes{0x1F, 0x9B, 0xFC, 0xD6}));
  EXPECT_EQ(argb8Word(b), 0x1F9BFCD6u);
  auto words = y16x16Words(b);
  EXPECT_EQ(words[0], 0x1F9B);
  EXPECT_EQ(words[1], 0xFCD6);
  std::optional<Rgba> t = sampleY16X16(b);
  ASSERT_TRUE(t.has_value());
  EXPECT_NEAR(t->r, 0.12346075f, 5e-9);
  EXPECT_NEAR(t->r - 0.123456f, 4.75e-6f, 5e-9);
  EXPECT_NEAR(t->g, 0.98765545f, 5e-9);
  // Host BGRA8 u32 0xAARRGGBB -> 0xGGBBAARR -> RG16: R16 = 0xAARR, G16 = 0xGGBB (P2 (2)).
  auto host = hostRg16FromBgra8(argb8Word(b));
  EXPECT_EQ(host[0], 0x1F9B);
  EXPECT_EQ(host[1], 0xFCD6);
}

TEST(Ps3Packed16, HalfAndQuarter) {
  // P2 (3): (0.5, 0.25): bytes 80 00 40 00; .r = 0.50000763, .g = 0.25000381.
  Argb8Bytes b = packTwo16InArgb8(0.5f, 0.25f);
  EXPECT_EQ(b, (Argb8Bytes{0x80, 0x00, 0x40, 0x00}));
  std::optional<Rgba> t = sampleY16X16(b);
  ASSERT_TRUE(t.has_value());
  EXPECT_NEAR(t->r, 0.50000763f, 5e-9);
  EXPECT_NEAR(t->g, 0.25000381f, 5e-9);
}

TEST(Ps3Packed16, OneAndZero) {
  // P2 (3): (1, 0): bytes FF FF 00 00; .r = 1.0, .g = 0.0.
  Argb8Bytes b = packTwo16InArgb8(1.0f, 0.0f);
  EXPECT_EQ(b, (Argb8Bytes{0xFF, 0xFF, 0x00, 0x00}));
  std::optional<Rgba> t = sampleY16X16(b);
  ASSERT_TRUE(t.has_value());
  EXPECT_EQ(t->r, 1.0f);
  EXPECT_EQ(t->g, 0.0f);
}

TEST(Ps3Packed16, ShaderOutputsHighAndLowBytes) {
  // P2 (1): output A = hi/255, R = lo/255 (same for y into G and B); ROP round(c * 255).
  Argb out = packTwo16ShaderOutput(0.123456f, 0.987654f);
  EXPECT_EQ(out[kA], 0x1F / 255.0f);
  EXPECT_EQ(out[kR], 0x9B / 255.0f);
  EXPECT_EQ(out[kG], 0xFC / 255.0f);
  EXPECT_EQ(out[kB], 0xD6 / 255.0f);
  for (int c = 0; c < 4; ++c) EXPECT_EQ(ropUnorm8(out[c]), packTwo16InArgb8(0.123456f, 0.987654f)[c]);
}

TEST(Ps3Packed16, RemapRoundTrips) {
  // P2 (3): identity remap 0xAAE4 on Y16_X16 yields (r,g,b,a) = (X, Y, X, Y); remap low byte 0x4E
  // yields (Y, X, Y, X).
  Argb8Bytes b = packTwo16InArgb8(0.123456f, 0.987654f);
  const float X = 8091 / 65535.0f, Y = 64726 / 65535.0f;
  std::optional<Rgba> id = sampleY16X16(b, 0xAAE4);
  ASSERT_TRUE(id.has_value());
  EXPECT_EQ(id->r, X);
  EXPECT_EQ(id->g, Y);
  EXPECT_EQ(id->b, X);
  EXPECT_EQ(id->a, Y);
  std::optional<Rgba> swapped = sampleY16X16(b, 0xAA4E);
  ASSERT_TRUE(swapped.has_value());
  EXPECT_EQ(swapped->r, Y);
  EXPECT_EQ(swapped->g, X);
  EXPECT_EQ(swapped->b, Y);
  EXPECT_EQ(swapped->a, X);
}

TEST(Ps3Packed16, RemapRewriteTable) {
  // P2 (1): 0xE4 -> 0x66 (0x56 with the override), 0x4E -> 0x99 (0xA9), 0xEE -> 0xAA, 0x44 -> 0x55.
  EXPECT_EQ(rewriteY16X16Remap(0xAAE4).value() & 0xFF, 0x66u);
  EXPECT_EQ(rewriteY16X16Remap(0xAA4E).value() & 0xFF, 0x99u);
  EXPECT_EQ(rewriteY16X16Remap(0xAAEE).value() & 0xFF, 0xAAu);
  EXPECT_EQ(rewriteY16X16Remap(0xAA44).value() & 0xFF, 0x55u);
  EXPECT_EQ(rewriteY16X16Remap(0x1AAE4).value() & 0xFF, 0x56u);
  EXPECT_EQ(rewriteY16X16Remap(0x1AA4E).value() & 0xFF, 0xA9u);
}

TEST(Ps3Packed16, InvalidY16X16Remap) {
  // P2 (4): E_Y16X16_REMAP_INVALID for a low byte outside {E4, 4E, EE, 44}.
  DiagnosticList out;
  EXPECT_FALSE(sampleY16X16(packTwo16InArgb8(0.5f, 0.5f), 0xAA93, "dsf", &out).has_value());
  EXPECT_TRUE(out.has("E_Y16X16_REMAP_INVALID"));
  // Near misses: the four valid low bytes.
  DiagnosticList none;
  for (uint32_t low : {0xE4u, 0x4Eu, 0xEEu, 0x44u}) EXPECT_TRUE(rewriteY16X16Remap(0xAA00 | low, "dsf", &none));
  EXPECT_TRUE(none.empty());
}

TEST(Ps3Packed16, FilterTrap) {
  // P2 (3): bilinear sampling of the ARGB8 view halfway between 0x00FF and 0x0100 gives
  // a = 0.5/255 and r = 127.5/255. Rounding each byte reconstructs 128 or 384; a linear decode
  // (65280 a + 255 r) gives 255.5; the Y16_X16 view filters real 16-bit values, about 255.5.
  const Argb8Bytes lo{0x00, 0xFF, 0, 0}, hi{0x01, 0x00, 0, 0};
  Argb f = filterArgb8(lo, hi, 0.5f);
  EXPECT_EQ(f[kA], 0.5f / 255.0f);
  EXPECT_EQ(f[kR], 127.5f / 255.0f);
  float perByte = decodePacked16RoundPerByte(f[kA], f[kR]);
  EXPECT_TRUE(perByte == 128.0f || perByte == 384.0f) << perByte;
  EXPECT_NEAR(decodePacked16Linear(f[kA], f[kR]), 255.5f, 1e-3);
  EXPECT_EQ(filterY16(0x00FF, 0x0100, 0.5f), 255.5f);
}

TEST(Ps3Packed16, ViewAndFilterDiagnostics) {
  // P2 (4): W_PACKED_VIEW_MISMATCH (packed data sampled as A8R8G8B8), W_PACKED_FILTER (linear on
  // the ARGB8 view with a per-byte decode), I_TYPELESS_COPY (host copy for the Y16_X16 view).
  PackedTextureRead bytes{"dsf", true, kTextureA8R8G8B8, Filter::Linear, true, kRemapIdentity, true};
  DiagnosticList out;
  checkPackedTextureRead(bytes, out);
  EXPECT_TRUE(out.has("W_PACKED_VIEW_MISMATCH"));
  EXPECT_TRUE(out.has("W_PACKED_FILTER"));
  // Near miss for the filter: point sampling of the byte view.
  bytes.filter = Filter::Nearest;
  DiagnosticList point;
  checkPackedTextureRead(bytes, point);
  EXPECT_TRUE(point.has("W_PACKED_VIEW_MISMATCH"));
  EXPECT_FALSE(point.has("W_PACKED_FILTER"));
  // Near miss for both: the Y16_X16 view (linear is a real 16-bit filter); it needs a typeless
  // copy on the host when the data was rendered.
  PackedTextureRead view{"dsf", true, uint8_t(kTextureY16X16 | kTextureFlagLN), Filter::Linear, true,
                         kRemapIdentity, true};
  DiagnosticList y16;
  checkPackedTextureRead(view, y16);
  EXPECT_FALSE(y16.has("W_PACKED_VIEW_MISMATCH"));
  EXPECT_FALSE(y16.has("W_PACKED_FILTER"));
  ASSERT_TRUE(y16.has("I_TYPELESS_COPY"));
  EXPECT_EQ(y16.first("I_TYPELESS_COPY")->severity, Severity::Info);
  view.sourceIsRenderTarget = false;
  DiagnosticList uploaded;
  checkPackedTextureRead(view, uploaded);
  EXPECT_TRUE(uploaded.empty()) << uploaded.format();
}

// ---------------------------------------------------------------------------------------------
// P3: packed targets have no alpha
// ---------------------------------------------------------------------------------------------

TEST(Ps3PackedTarget, BlendCorruptsPackedValues) {
  // P3 (3): dst X = 0x00FF, src X = 0x0100, 0.5 src + 0.5 dst per unorm8 channel: hi in {0,1},
  // lo in {127,128}; decoded 127/128/383/384 against an ideal 255 or 256 (about 128 LSB).
  const Argb8Bytes dst{0x00, 0xFF, 0, 0}, src{0x01, 0x00, 0, 0};
  BlendState half{true, BlendFactor::ConstantAlpha, BlendFactor::ConstantAlpha, BlendFactor::ConstantAlpha,
                  BlendFactor::ConstantAlpha, 0.5f};
  Argb8Bytes r = blendArgb8(src, dst, half);
  EXPECT_TRUE(r[kA] == 0 || r[kA] == 1) << int(r[kA]);
  EXPECT_TRUE(r[kR] == 127 || r[kR] == 128) << int(r[kR]);
  int decoded = r[kA] * 256 + r[kR];
  EXPECT_TRUE(decoded == 127 || decoded == 128 || decoded == 383 || decoded == 384) << decoded;
  EXPECT_GE(std::abs(decoded - 255.5), 127.0);
}

TEST(Ps3PackedTarget, BlendingAValueWithItselfIsExact) {
  // P3 (3): dst X = 0x1234, src X = 0x1234 with any blend factors: bit-identical.
  const Argb8Bytes v{0x12, 0x34, 0x12, 0x34};
  const BlendState states[] = {
      {true, BlendFactor::ConstantAlpha, BlendFactor::ConstantAlpha, BlendFactor::ConstantAlpha,
       BlendFactor::ConstantAlpha, 0.5f},
      {true, BlendFactor::SrcAlpha, BlendFactor::OneMinusSrcAlpha, BlendFactor::SrcAlpha, BlendFactor::OneMinusSrcAlpha},
      {true, BlendFactor::One, BlendFactor::Zero, BlendFactor::One, BlendFactor::Zero},
      {true, BlendFactor::Zero, BlendFactor::One, BlendFactor::Zero, BlendFactor::One},
      {true, BlendFactor::DestAlpha, BlendFactor::OneMinusDestAlpha, BlendFactor::DestAlpha,
       BlendFactor::OneMinusDestAlpha},
  };
  for (const BlendState& b : states) EXPECT_EQ(blendArgb8(v, v, b), v);
}

TEST(Ps3PackedTarget, DrawDiagnostics) {
  // P3 (4): E_PACKED_BLEND, W_PACKED_PARTIAL_WRITEMASK (A/R or G/B split), E_PACKED_ALPHA_TEST.
  PackedTargetDraw decal{"normals", true, {true, BlendFactor::SrcAlpha, BlendFactor::OneMinusSrcAlpha}, kWriteAll, false};
  DiagnosticList out;
  checkPackedTargetDraw(decal, out);
  EXPECT_TRUE(out.has("E_PACKED_BLEND"));
  PackedTargetDraw partial{"normals", true, {}, kWriteA | kWriteG | kWriteB, false};
  DiagnosticList p;
  checkPackedTargetDraw(partial, p);
  EXPECT_TRUE(p.has("W_PACKED_PARTIAL_WRITEMASK"));
  PackedTargetDraw alphaTest{"normals", true, {}, kWriteAll, true};
  DiagnosticList a;
  checkPackedTargetDraw(alphaTest, a);
  EXPECT_TRUE(a.has("E_PACKED_ALPHA_TEST"));
  // Near misses: a mask that writes whole values (Y only), and the same states on a target that
  // is not packed.
  DiagnosticList none;
  checkPackedTargetDraw({"normals", true, {}, kWriteG | kWriteB, false}, none);
  checkPackedTargetDraw({"albedo", false, decal.blend, kWriteA, true}, none);
  EXPECT_TRUE(none.empty()) << none.format();
}

TEST(Ps3PackedTarget, MsaaAveragingOfPackedTargets) {
  // P3 (4): E_PACKED_MSAA_RESOLVE: averaging a packed target averages bytes.
  DiagnosticList out;
  checkPackedResolve("normals", true, 4, true, out);
  EXPECT_TRUE(out.has("E_PACKED_MSAA_RESOLVE"));
  DiagnosticList none;
  checkPackedResolve("normals", true, 1, true, none);   // single-sampled
  checkPackedResolve("normals", true, 4, false, none);  // one sample copied
  checkPackedResolve("albedo", false, 4, true, none);   // not packed
  EXPECT_TRUE(none.empty());
}

// ---------------------------------------------------------------------------------------------
// P4: depth through an ARGB8 view
// ---------------------------------------------------------------------------------------------

TEST(Ps3Depth, MemoryLayoutAndRemaps) {
  // P4 (3): D24 = 0xABCDEF, S = 0x5A: memory AB CD EF 5A; identity remap (a,r,g,b) =
  // (AB, CD, EF, 5A)/255; BARG 0xAA93 (r,g,b,a) = (AB, CD, EF, 5A)/255.
  EXPECT_EQ(depthStencilMemoryBytes(0xABCDEF, 0x5A), (std::array<uint8_t, 4>{0xAB, 0xCD, 0xEF, 0x5A}));
  Rgba id = sampleDepthAsArgb8(0xABCDEF, 0x5A, kRemapIdentity);
  EXPECT_EQ(id.a, 0xAB / 255.0f);
  EXPECT_EQ(id.r, 0xCD / 255.0f);
  EXPECT_EQ(id.g, 0xEF / 255.0f);
  EXPECT_EQ(id.b, 0x5A / 255.0f);
  Rgba barg = sampleDepthAsArgb8(0xABCDEF, 0x5A, kRemapBarg);
  EXPECT_EQ(barg.r, 0xAB / 255.0f);
  EXPECT_EQ(barg.g, 0xCD / 255.0f);
  EXPECT_EQ(barg.b, 0xEF / 255.0f);
  EXPECT_EQ(barg.a, 0x5A / 255.0f);
}

TEST(Ps3Depth, BargRemapWord) {
  // P4 (1): A <- FROM_B, R <- FROM_A, G <- FROM_R, B <- FROM_G, outputs all REMAP: 0xAA93.
  EXPECT_EQ(makeRemap(RemapOrder::XYXY, RemapFrom::B, RemapFrom::A, RemapFrom::R, RemapFrom::G), 0xAA93u);
  EXPECT_EQ(makeRemap(RemapOrder::XYXY, RemapFrom::A, RemapFrom::R, RemapFrom::G, RemapFrom::B), 0xAAE4u);
}

TEST(Ps3Depth, PreciseDecodeVectors) {
  // P4 (3): precise decode 11259375/16777215 = 0.67111108727 (1 ULP, open question 4);
  // non-precise D/2^24 = 0.67111104727; their difference is below fp32 resolution (1 ULP).
  // D24 = 0xFFFFFF: 1.0 precise, 0.99999994 non-precise. D24 = 0: 0.0.
  for (TexDepth2DPrecise variant : {TexDepth2DPrecise::ExactD24Over16777215, TexDepth2DPrecise::Fp32PreciseFactorsDp3}) {
    PlatformParams p;
    p.texDepth2DPrecise = variant;
    SCOPED_TRACE(int(variant));
    float precise = texDepth2DPrecise(sampleDepthAsArgb8(0xABCDEF, 0x5A), p);
    EXPECT_TRUE(withinUlps(precise, 11259375.0 / 16777215.0, 1));
    EXPECT_TRUE(withinUlps(precise, 0.67111108727, 1));
    EXPECT_TRUE(withinUlps(texDepth2DPrecise(sampleDepthAsArgb8(0xFFFFFF, 0x5A), p), 1.0, 1));
    EXPECT_EQ(texDepth2DPrecise(sampleDepthAsArgb8(0, 0x5A), p), 0.0f);
    float coarse = texDepth2D(sampleDepthAsArgb8(0xABCDEF, 0x5A));
    EXPECT_LE(ulpDistance(precise, coarse), 1);
  }
  EXPECT_TRUE(withinUlps(texDepth2D(sampleDepthAsArgb8(0xABCDEF, 0)), 0.67111104727, 1));
  EXPECT_TRUE(withinUlps(texDepth2D(sampleDepthAsArgb8(0xFFFFFF, 0)), 0.99999994, 1));
  // The exact variant is the correctly rounded value itself.
  EXPECT_EQ(texDepth2DPrecise(sampleDepthAsArgb8(0xFFFFFF, 0)), 1.0f);
}

TEST(Ps3Depth, HandWrittenDecodeOnTheUnremappedLayout) {
  // P4 (1): the earlier hand decode reads .arg with the identity remap and gives D24/16777215.
  EXPECT_TRUE(withinUlps(decodeDepthArgByHand(sampleDepthAsArgb8(0xABCDEF, 0x5A, kRemapIdentity)),
                         11259375.0 / 16777215.0, 1));
}

TEST(Ps3Depth, WrongRemapTrap) {
  // P4 (3): decoding .rgb with the identity remap uses bytes (CD, EF, 5A):
  // (205*65536 + 239*256 + 90)/16777215 = 0.80443 instead of 0.67111.
  float wrong = texDepth2DPrecise(sampleDepthAsArgb8(0xABCDEF, 0x5A, kRemapIdentity));
  EXPECT_TRUE(withinUlps(wrong, (205.0 * 65536 + 239 * 256 + 90) / 16777215.0, 1));
  EXPECT_NEAR(wrong, 0.80443f, 5e-6);
  DiagnosticList out;
  checkDepthAsColorRead({"depth", kRemapIdentity, DepthDecodeChannels::Rgb}, out);
  EXPECT_TRUE(out.has("E_DEPTH_AS_COLOR_REMAP"));
  EXPECT_TRUE(out.has("W_DEPTH_STENCIL_IN_DECODE"));  // .b is the stencil byte under identity
  DiagnosticList arg;
  checkDepthAsColorRead({"depth", kRemapBarg, DepthDecodeChannels::Arg}, arg);
  EXPECT_TRUE(arg.has("E_DEPTH_AS_COLOR_REMAP"));
  // Near misses: .rgb with BARG, .arg with identity.
  DiagnosticList none;
  checkDepthAsColorRead({"depth", kRemapBarg, DepthDecodeChannels::Rgb}, none);
  checkDepthAsColorRead({"depth", kRemapIdentity, DepthDecodeChannels::Arg}, none);
  EXPECT_TRUE(none.empty()) << none.format();
}

TEST(Ps3Depth, FilterTrapAndEnforcedPointFiltering) {
  // P4 (3): bilinear halfway between D24 = 0x00FFFF and 0x010000 gives per-byte (0.5, 127.5,
  // 127.5); texDepth2D_precise decodes 0x018080 = 98432 instead of 65535.5; a non-rounding
  // linear decode gives 65535.5.
  std::array<float, 3> f = filterDepthBytes(0x00FFFF, 0x010000, 0.5f);
  EXPECT_EQ(f[0] * 255.0f, 0.5f);
  EXPECT_EQ(f[1] * 255.0f, 127.5f);
  EXPECT_EQ(f[2] * 255.0f, 127.5f);
  Rgba filtered{f[0], f[1], f[2], 0.0f};
  EXPECT_TRUE(withinUlps(texDepth2DPrecise(filtered), 98432.0 / 16777215.0, 1));
  EXPECT_EQ(0x018080, 98432);
  EXPECT_EQ(f[0] * 255.0f * 65536.0f + f[1] * 255.0f * 256.0f + f[2] * 255.0f, 65535.5f);
  // The PS3 layer samples with NEAREST whatever filter is asked for.
  DepthSurfaceImage img{2, 1, {0x00FFFF, 0x010000}, {0, 0}};
  DepthAsColorRead linear{"depth", kRemapBarg, DepthDecodeChannels::Rgb, Filter::Linear, Filter::Linear};
  float v = readDepthAsColor(img, 0.5f, 0.5f, linear);
  EXPECT_TRUE(v == texDepth2DPrecise(sampleDepthAsArgb8(0x00FFFF, 0)) ||
              v == texDepth2DPrecise(sampleDepthAsArgb8(0x010000, 0)));
}

TEST(Ps3Depth, FilterAndFeedbackDiagnostics) {
  // P4 (4): W_DEPTH_AS_COLOR_FILTER (min/mag != NEAREST), W_DEPTH_FEEDBACK (sampled while bound
  // for depth writes).
  DiagnosticList out;
  checkDepthAsColorRead({"depth", kRemapBarg, DepthDecodeChannels::Rgb, Filter::Nearest, Filter::Linear, true}, out);
  EXPECT_TRUE(out.has("W_DEPTH_AS_COLOR_FILTER"));
  EXPECT_TRUE(out.has("W_DEPTH_FEEDBACK"));
  EXPECT_FALSE(out.has("E_DEPTH_AS_COLOR_REMAP"));
  DiagnosticList none;
  checkDepthAsColorRead({"depth", kRemapBarg, DepthDecodeChannels::Rgb, Filter::Nearest, Filter::Nearest, false}, none);
  EXPECT_TRUE(none.empty());
}

// ---------------------------------------------------------------------------------------------
// P5 (contrast): RSX MSAA surface layout
// ---------------------------------------------------------------------------------------------

TEST(Ps3MsaaLayout, RsxStoresSamplesSideBySide) {
  // P5: an RSX 4x surface of WxH px occupies 2W x 2H texels in memory. Sample 1 of pixel (0,0)
  // sits at memory texel (1,0); on Xenos (mainline layout) it sits at sample offset (0,1).
  EXPECT_EQ(int(AntiAliasMode::SquareCentered4), 4);
  EXPECT_EQ(aaFactorU(AntiAliasMode::SquareCentered4) * 640, 1280u);
  EXPECT_EQ(aaFactorV(AntiAliasMode::SquareCentered4) * 360, 720u);
  MemoryTexel t = rsxSampleTexel(AntiAliasMode::SquareCentered4, 0, 0, 1);
  EXPECT_EQ(t.x, 1u);
  EXPECT_EQ(t.y, 0u);
  parity::platforms::x360::SampleCoord xenos =
      parity::platforms::x360::edramSampleCoord(parity::platforms::x360::MsaaSamples::k4X, 0, 0, 1);
  EXPECT_EQ(xenos.sx, 0u);
  EXPECT_EQ(xenos.sy, 1u);
  // P5: RSX 2x is horizontal (2x1): aa_factor_u = 2, aa_factor_v = 1.
  EXPECT_EQ(aaFactorU(AntiAliasMode::DiagonalCentered2), 2u);
  EXPECT_EQ(aaFactorV(AntiAliasMode::DiagonalCentered2), 1u);
  MemoryTexel s1 = rsxSampleTexel(AntiAliasMode::DiagonalCentered2, 0, 0, 1);
  EXPECT_EQ(s1.x, 1u);
  EXPECT_EQ(s1.y, 0u);
}

TEST(Ps3Platform, LogicalTargets) {
  // P1/P2: a two-channel 16-bit target becomes a packed A8R8G8B8 surface; P4: depth is read through
  // the BARG remap.
  TargetMapping dsf = mapTarget(LogicalFormat::Rg16Unorm);
  EXPECT_NE(dsf.consoleFormat.find("A8R8G8B8"), std::string::npos);
  EXPECT_EQ(dsf.consoleBytesPerPixel, 4u);
  EXPECT_NE(mapTarget(LogicalFormat::Depth24Stencil8).consoleFormat.find("0xAA93"), std::string::npos);
}
