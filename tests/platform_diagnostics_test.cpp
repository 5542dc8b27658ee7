// The platform diagnostic catalogue (console-quirks.md: "Consolidated diagnostic catalogue" and
// each section's diagnostic list), the named parameters for the pack's open questions, and one
// trigger plus one near miss for every catalogue code.
#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <map>
#include <set>
#include <string>

#include "platforms/common/diagnostics.h"
#include "platforms/common/platform_params.h"
#include "platforms/dx10/depth_read.h"
#include "platforms/platforms.h"
#include "platforms/ps3/depth_read.h"
#include "platforms/ps3/packed16.h"
#include "platforms/ps3/surface.h"
#include "platforms/x360/edram.h"
#include "platforms/x360/edram_frame.h"
#include "platforms/x360/fixed16.h"
#include "platforms/x360/float7e3.h"
#include "platforms/x360/pixel_center.h"
#include "platforms/x360/resolve.h"

using namespace parity::platforms;

namespace {

// The pack's consolidated table, row by row, with the severity it proposes.
const std::map<std::string, Severity> kConsolidated = {
    {"E_EDRAM_OVERLAP", Severity::Error},
    {"E_EDRAM_SURFACE_TOO_LARGE", Severity::Error},
    {"W_EDRAM_WRAP", Severity::Warning},
    {"E_MRT_SURFACE_INFO_MISMATCH", Severity::Error},
    {"E_EDRAM_NOT_READABLE", Severity::Error},
    {"E_GBUF_OVERLAP", Severity::Error},
    {"E_LBUF_DEPTH_ALIAS", Severity::Error},
    {"E_RESOLVE_ALIGNMENT", Severity::Error},
    {"E_RESOLVE_PACKED_MIP", Severity::Error},
    {"W_RESOLVE_SIGN_LOSS", Severity::Warning},
    {"W_RESOLVE_RANGE_CLAMP", Severity::Warning},
    {"W_RESOLVE_PRECISION", Severity::Warning},
    {"W_FIXED16_RANGE_CLAMP", Severity::Warning},  // W_FIXED16_* expands to the four X2 codes
    {"W_FIXED16_NAN", Severity::Warning},
    {"W_FIXED16_PRECISION", Severity::Warning},
    {"W_FIXED16_MULT_BLEND", Severity::Warning},
    {"W_D3D9_PIXEL_CENTER", Severity::Warning},
    {"E_RSX_NO_RG16_SURFACE", Severity::Error},
    {"E_MRT_FORMAT_MISMATCH", Severity::Error},
    {"E_MRT_BPP_MISMATCH", Severity::Error},
    {"E_PACKED_BLEND", Severity::Error},
    {"W_PACKED_FILTER", Severity::Warning},
    {"W_PACKED_VIEW_MISMATCH", Severity::Warning},
    {"E_Y16X16_REMAP_INVALID", Severity::Error},
    {"E_DEPTH_AS_COLOR_REMAP", Severity::Error},
    {"W_DEPTH_AS_COLOR_FILTER", Severity::Warning},
    {"E_DX10_DEPTH_SRV_FORMAT", Severity::Error},
    {"E_DX10_MSAA_DEPTH_READ", Severity::Error},
    {"W_DX10_SRV_DSV_HAZARD", Severity::Warning},
};

// Codes the sections name outside the consolidated table.
// parity's own codes, for rules the pack describes without naming a code.
const std::set<std::string> kParityOwn = {"W_FLOAT7E3_RANGE_CLAMP"};
// What a platform can run at all (section CAP, parity's own): each fires from real pipelines in
// tests/platform_capabilities_test.cpp, its near miss the same pipeline on the reference.
const std::set<std::string> kCapability = {
    "E_CAP_COMPUTE", "E_CAP_COMPUTE_INVOCATIONS", "E_CAP_COMPUTE_WORKGROUP_DEPTH", "E_CAP_COMPUTE_SHARED_MEMORY",
    "E_CAP_COMPUTE_ATOMICS", "E_CAP_COMPUTE_STORAGE_BUFFERS", "E_CAP_COMPUTE_STORAGE_IMAGES", "E_CAP_COLOR_TARGETS",
    "E_CAP_FRAGMENT_TEXTURES", "E_CAP_VERTEX_TEXTURES", "E_CAP_INTERPOLATORS", "E_CAP_MULTISAMPLING",
    "E_CAP_GEOMETRY_SHADERS", "E_CAP_TESSELLATION_SHADERS", "E_CAP_GRAPHICS_STORAGE_WRITES", "E_CAP_EDRAM_BYTES",
    "E_CAP_RENDER_FORMAT", "E_CAP_BLEND_FORMAT", "E_CAP_FILTER_FORMAT", "E_CAP_VERTEX_FETCH_FORMAT",
    "E_CAP_MULTISAMPLE_FORMAT", "W_CAP_OPTIONAL"};

const std::set<std::string> kSectionOnly = {
    "W_RT_SAME_BASE",         "E_DEPTH_RESOLVE_CONVERT", "E_USE_BEFORE_RESOLVE",      "I_HALFPIXEL_MODE_CHANGE",
    "W_MRT_SHARED_BLEND",     "I_TYPELESS_COPY",         "E_PACKED_ALPHA_TEST",       "W_PACKED_PARTIAL_WRITEMASK",
    "E_PACKED_MSAA_RESOLVE",  "W_DEPTH_STENCIL_IN_DECODE", "W_DEPTH_FEEDBACK",        "W_DX10_DEPTH_NOT_RESOLVED",
};

// --- x360 scenario helpers ---

x360::EdramSurface surf(std::string name, uint32_t w, uint32_t h, uint32_t base,
                        x360::MsaaSamples msaa = x360::MsaaSamples::k1X,
                        x360::ColorRenderTargetFormat f = x360::ColorRenderTargetFormat::k_8_8_8_8) {
  x360::EdramSurface s;
  s.name = std::move(name);
  s.pitchPx = w;
  s.heightPx = h;
  s.baseTile = base;
  s.msaa = msaa;
  s.colorFormat = f;
  return s;
}

x360::EdramSurface depthSurf(std::string name, uint32_t w, uint32_t h, uint32_t base) {
  x360::EdramSurface s = surf(std::move(name), w, h, base);
  s.isDepth = true;
  return s;
}

// X1 (1): Fable 2's 1120x720 2x depth buffer (1260 tiles).
x360::EdramSurface fable2Depth(uint32_t base) {
  x360::EdramSurface d = depthSurf("fable2_depth", 1120, 720, base);
  d.msaa = x360::MsaaSamples::k2X;
  return d;
}

DiagnosticList live(std::vector<x360::EdramSurface> surfaces) {
  DiagnosticList d;
  x360::checkLiveSurfaces("pass", surfaces, d);
  return d;
}

DiagnosticList bound(std::vector<x360::EdramSurface> surfaces) {
  DiagnosticList d;
  x360::checkBoundTargets("pass", surfaces, d);
  return d;
}

x360::InferredLightingLayout layout(uint32_t g1Base, uint32_t lBase) {
  // X4 (3) vectors at 1024x576.
  x360::InferredLightingLayout l;
  l.gbufferColor = {surf("G0", 1024, 576, 0), surf("G1", 1024, 576, g1Base, x360::MsaaSamples::k1X,
                                                    x360::ColorRenderTargetFormat::k_16_16)};
  l.depth = depthSurf("depth", 1024, 576, 936);
  l.lbuffer = surf("L", 1024, 576, lBase, x360::MsaaSamples::k1X, x360::ColorRenderTargetFormat::k_16_16_16_16);
  return l;
}

DiagnosticList inferred(uint32_t g1Base, uint32_t lBase) {
  DiagnosticList d;
  x360::checkInferredLightingLayout(layout(g1Base, lBase), d);
  return d;
}

DiagnosticList frame(bool resolveBeforeLight, bool sampleSurface) {
  x360::InferredLightingLayout l = layout(468, 0);
  x360::EdramFrame f;
  for (x360::EdramSurface s : l.gbufferColor) {
    s.role = x360::SurfaceRole::GBuffer;
    f.declare(s);
  }
  l.depth.role = x360::SurfaceRole::GBuffer;
  f.declare(l.depth);
  l.lbuffer.role = x360::SurfaceRole::LBuffer;
  f.declare(l.lbuffer);
  DiagnosticList d;
  f.draw("geometry", {"G0", "G1", "depth"}, d);
  if (resolveBeforeLight) {
    x360::ResolveRequest r;
    r.rect = {0, 0, 1024, 576};
    f.resolve("G0", r, "G0_tex", d);
    f.resolve("G1", r, "G1_tex", d);
  }
  f.draw("light", {"L", "depth"}, d);
  f.sample("material", sampleSurface ? "G1" : "G1_tex", d);
  return d;
}

DiagnosticList resolveCheck(x360::EdramSurface s, x360::ResolveRequest r) {
  DiagnosticList d;
  x360::checkResolveRequest(s, r, d);
  return d;
}

x360::ResolveRequest rect(int32_t x, int32_t y, uint32_t w, uint32_t h) {
  x360::ResolveRequest r;
  r.rect = {x, y, w, h};
  return r;
}

DiagnosticList resolveData(int16_t value, x360::SurfaceNumberFormat number) {
  x360::EdramMemory edram;
  x360::EdramSurface s = surf("dsf", 64, 32, 0, x360::MsaaSamples::k1X, x360::ColorRenderTargetFormat::k_16_16);
  edram.writeSample(s, 0, 0, 0, x360::packFixed16x2(value, 0));
  x360::ResolveRequest r = rect(0, 0, 8, 8);
  r.destNumber = number;
  DiagnosticList d;
  x360::resolveSurface(edram, s, r, d);
  return d;
}

DiagnosticList fixed16Image(std::vector<float> rg, int bias) {
  DiagnosticList d;
  x360::encodeFixed16x2Image("dsf", rg, bias, d);
  return d;
}

DiagnosticList float7e3Image(std::vector<float> rgba) {
  DiagnosticList d;
  x360::encodeFloat7e3Image("light", rgba, d);
  return d;
}

DiagnosticList fixed16Blend(BlendFactor src, x360::K16HostStorage storage) {
  DiagnosticList d;
  x360::checkFixed16Blend("lbuffer", {true, src, BlendFactor::Zero, BlendFactor::One, BlendFactor::Zero}, storage, d);
  return d;
}

DiagnosticList precision(DsfResolvePath path) {
  DiagnosticList d;
  x360::checkDsfPathPrecision("dsf", x360::dsfPath(path), d);
  return d;
}

DiagnosticList screenDraw(float offset, x360::PixelCenter center) {
  const x360::ScreenVertex v[] = {{0 + offset, 0 + offset, 0, 0},
                                  {1280 + offset, 0 + offset, 1, 0},
                                  {0 + offset, 720 + offset, 0, 1},
                                  {1280 + offset, 720 + offset, 1, 1}};
  DiagnosticList d;
  x360::checkScreenSpaceDraw("post", v, 1280, 720, center, d);
  return d;
}

DiagnosticList passCenters(x360::PixelCenter second) {
  const x360::PixelCenter c[] = {x360::PixelCenter::kD3DZero, second};
  DiagnosticList d;
  x360::checkPassPixelCenters("post", c, d);
  return d;
}

// --- ps3 scenario helpers ---

DiagnosticList rg16Request(bool allowPacking) {
  DiagnosticList d;
  ps3::requestColorSurface({"dsf", 2, 16, false, allowPacking}, d);
  return d;
}

DiagnosticList mrt(ps3::SurfaceColorFormat a, ps3::SurfaceColorFormat b, Ps3MrtRule rule, bool differentBlend = false) {
  ps3::ColorSurface s0{"a", a}, s1{"b", b};
  s0.blend = {true, BlendFactor::SrcAlpha, BlendFactor::OneMinusSrcAlpha};
  s1.blend = s0.blend;
  if (differentBlend) s1.blend.dstColor = BlendFactor::One;
  const ps3::ColorSurface t[] = {s0, s1};
  DiagnosticList d;
  ps3::checkMrt("pass", t, rule, d);
  return d;
}

DiagnosticList packedRead(uint8_t view, Filter filter, uint32_t remap = ps3::kRemapIdentity, bool rendered = true) {
  DiagnosticList d;
  ps3::checkPackedTextureRead({"dsf", true, view, filter, true, remap, rendered}, d);
  return d;
}

DiagnosticList packedDraw(bool blend, uint8_t mask, bool alphaTest, bool packed = true) {
  DiagnosticList d;
  BlendState b;
  b.enabled = blend;
  ps3::checkPackedTargetDraw({"normals", packed, b, mask, alphaTest}, d);
  return d;
}

DiagnosticList packedResolve(uint32_t samples) {
  DiagnosticList d;
  ps3::checkPackedResolve("normals", true, samples, true, d);
  return d;
}

DiagnosticList depthRead(uint32_t remap, Filter filter, bool feedback) {
  DiagnosticList d;
  ps3::checkDepthAsColorRead({"depth", remap, ps3::DepthDecodeChannels::Rgb, filter, filter, feedback}, d);
  return d;
}

// --- dx10 ---

DiagnosticList dx10Read(dx10::DxgiFormat resource, uint32_t samples, bool dsv, bool resolved) {
  DiagnosticList d;
  dx10::DepthRead r{"depth", resource, dx10::DxgiFormat::R24_UNORM_X8_TYPELESS, samples, dsv, resolved};
  dx10::checkDepthRead(r, d);
  return d;
}

using x360::MsaaSamples;
constexpr auto R24G8 = dx10::DxgiFormat::R24G8_TYPELESS;

struct Scenario {
  std::function<DiagnosticList()> trigger;
  std::function<DiagnosticList()> nearMiss;
};

// One trigger and one near miss per catalogue code; the near miss differs from the trigger in the
// one property the rule looks at.
const std::map<std::string, Scenario>& scenarios() {
  static const std::map<std::string, Scenario> s = {
      // X1
      {"E_EDRAM_OVERLAP",
       {[] { return live({surf("a", 1280, 720, 0), surf("b", 1280, 720, 719)}); },
        [] { return live({surf("a", 1280, 720, 0), surf("b", 1280, 720, 720)}); }}},
      {"E_EDRAM_SURFACE_TOO_LARGE",
       {[] { return live({surf("hdr", 1280, 720, 0, MsaaSamples::k4X)}); },  // 2880 tiles
        [] { return live({surf("hdr", 1024, 576, 0, MsaaSamples::k4X)}); }}},  // 1872 tiles
      {"W_EDRAM_WRAP",
       {[] { return live({fable2Depth(1008)}); },  // [1008, 2268)
        [] { return live({fable2Depth(0)}); }}},     // [0, 1260)
      {"E_MRT_SURFACE_INFO_MISMATCH",
       {[] { return bound({surf("a", 640, 360, 0), surf("b", 640, 360, 400, MsaaSamples::k2X)}); },
        [] { return bound({surf("a", 640, 360, 0), surf("b", 640, 360, 400)}); }}},
      {"W_RT_SAME_BASE",
       {[] { return bound({surf("a", 640, 360, 100), surf("b", 640, 360, 100)}); },
        [] { return bound({surf("a", 640, 360, 100), surf("b", 640, 360, 284)}); }}},
      {"E_EDRAM_NOT_READABLE", {[] { return frame(true, true); }, [] { return frame(true, false); }}},
      // X2
      {"W_FIXED16_RANGE_CLAMP", {[] { return fixed16Image({32.5f, 0.0f}, 0); }, [] { return fixed16Image({32.0f, 0.0f}, 0); }}},
      {"W_FIXED16_NAN", {[] { return fixed16Image({std::numeric_limits<float>::quiet_NaN(), 0.0f}, 0); }, [] { return fixed16Image({0.0f, 0.0f}, 5); }}},
      {"W_FLOAT7E3_RANGE_CLAMP", {[] { return float7e3Image({32.0f, 0.0f, 0.0f, 1.0f}); }, [] { return float7e3Image({31.875f, 0.0f, 0.5f, 1.0f}); }}},
      {"W_FIXED16_PRECISION", {[] { return fixed16Image({0.0f, 1.0f}, 0); }, [] { return fixed16Image({0.0f, 1.0f}, 5); }}},
      {"W_FIXED16_MULT_BLEND",
       {[] { return fixed16Blend(BlendFactor::DestColor, x360::K16HostStorage::Snorm16Div32); },
        [] { return fixed16Blend(BlendFactor::DestColor, x360::K16HostStorage::Interlock); }}},
      // X3
      {"E_RESOLVE_ALIGNMENT",
       {[] { return resolveCheck(surf("s", 640, 360, 0), rect(0, 4, 64, 64)); },
        [] { return resolveCheck(surf("s", 640, 360, 0), rect(0, 8, 64, 64)); }}},
      {"E_RESOLVE_PACKED_MIP",
       {[] {
          auto r = rect(0, 0, 16, 16);
          r.destMipWidth = r.destMipHeight = 16;
          return resolveCheck(surf("s", 640, 360, 0), r);
        },
        [] {
          auto r = rect(0, 0, 32, 32);
          r.destMipWidth = r.destMipHeight = 32;
          return resolveCheck(surf("s", 640, 360, 0), r);
        }}},
      {"W_RESOLVE_SIGN_LOSS",
       {[] { return resolveData(-24676, x360::SurfaceNumberFormat::kUnsignedRepeatingFraction); },
        [] { return resolveData(-24676, x360::SurfaceNumberFormat::kSignedRepeatingFraction); }}},
      {"W_RESOLVE_RANGE_CLAMP",
       {[] { return resolveData(2048, x360::SurfaceNumberFormat::kUnsignedRepeatingFraction); },   // 2.000061
        [] { return resolveData(1000, x360::SurfaceNumberFormat::kUnsignedRepeatingFraction); }}},  // 0.97659
      {"W_RESOLVE_PRECISION",
       {[] { return precision(DsfResolvePath::NaiveA); }, [] { return precision(DsfResolvePath::PaperSignedC); }}},
      {"E_DEPTH_RESOLVE_CONVERT",
       {[] {
          auto r = rect(0, 0, 64, 64);
          r.destExpBias = 1;
          return resolveCheck(depthSurf("d", 640, 360, 0), r);
        },
        [] { return resolveCheck(depthSurf("d", 640, 360, 0), rect(0, 0, 64, 64)); }}},
      // X4
      {"E_GBUF_OVERLAP", {[] { return inferred(400, 0); }, [] { return inferred(468, 0); }}},
      {"E_LBUF_DEPTH_ALIAS", {[] { return inferred(468, 500); }, [] { return inferred(468, 0); }}},
      {"E_USE_BEFORE_RESOLVE", {[] { return frame(false, false); }, [] { return frame(true, false); }}},
      // X5
      {"W_D3D9_PIXEL_CENTER",
       {[] { return screenDraw(0.0f, x360::PixelCenter::kD3DZero); },
        [] { return screenDraw(-0.5f, x360::PixelCenter::kD3DZero); }}},
      {"I_HALFPIXEL_MODE_CHANGE",
       {[] { return passCenters(x360::PixelCenter::kOGLHalf); }, [] { return passCenters(x360::PixelCenter::kD3DZero); }}},
      // P1
      {"E_RSX_NO_RG16_SURFACE", {[] { return rg16Request(false); }, [] { return rg16Request(true); }}},
      {"E_MRT_FORMAT_MISMATCH",
       {[] { return mrt(ps3::SurfaceColorFormat::A8R8G8B8, ps3::SurfaceColorFormat::X8R8G8B8_Z8R8G8B8, Ps3MrtRule::SameFormat); },
        [] { return mrt(ps3::SurfaceColorFormat::A8R8G8B8, ps3::SurfaceColorFormat::X8R8G8B8_Z8R8G8B8, Ps3MrtRule::SameBpp); }}},
      {"E_MRT_BPP_MISMATCH",
       {[] { return mrt(ps3::SurfaceColorFormat::A8R8G8B8, ps3::SurfaceColorFormat::F_W16Z16Y16X16, Ps3MrtRule::SameBpp); },
        [] { return mrt(ps3::SurfaceColorFormat::A8R8G8B8, ps3::SurfaceColorFormat::A8B8G8R8, Ps3MrtRule::SameBpp); }}},
      {"W_MRT_SHARED_BLEND",
       {[] { return mrt(ps3::SurfaceColorFormat::A8R8G8B8, ps3::SurfaceColorFormat::A8R8G8B8, Ps3MrtRule::SameFormat, true); },
        [] { return mrt(ps3::SurfaceColorFormat::A8R8G8B8, ps3::SurfaceColorFormat::A8R8G8B8, Ps3MrtRule::SameFormat, false); }}},
      // P2
      {"W_PACKED_VIEW_MISMATCH",
       {[] { return packedRead(ps3::kTextureA8R8G8B8, Filter::Nearest); },
        [] { return packedRead(ps3::kTextureY16X16, Filter::Nearest); }}},
      {"W_PACKED_FILTER",
       {[] { return packedRead(ps3::kTextureA8R8G8B8, Filter::Linear); },
        [] { return packedRead(ps3::kTextureA8R8G8B8, Filter::Nearest); }}},
      {"E_Y16X16_REMAP_INVALID",
       {[] { return packedRead(ps3::kTextureY16X16, Filter::Nearest, 0xAA93); },
        [] { return packedRead(ps3::kTextureY16X16, Filter::Nearest, 0xAA4E); }}},
      {"I_TYPELESS_COPY",
       {[] { return packedRead(ps3::kTextureY16X16, Filter::Linear, ps3::kRemapIdentity, true); },
        [] { return packedRead(ps3::kTextureY16X16, Filter::Linear, ps3::kRemapIdentity, false); }}},
      // P3
      {"E_PACKED_BLEND",
       {[] { return packedDraw(true, ps3::kWriteAll, false); }, [] { return packedDraw(true, ps3::kWriteAll, false, false); }}},
      {"E_PACKED_ALPHA_TEST",
       {[] { return packedDraw(false, ps3::kWriteAll, true); }, [] { return packedDraw(false, ps3::kWriteAll, false); }}},
      {"W_PACKED_PARTIAL_WRITEMASK",
       {[] { return packedDraw(false, ps3::kWriteA | ps3::kWriteG | ps3::kWriteB, false); },
        [] { return packedDraw(false, ps3::kWriteA | ps3::kWriteR, false); }}},
      {"E_PACKED_MSAA_RESOLVE", {[] { return packedResolve(4); }, [] { return packedResolve(1); }}},
      // P4
      {"E_DEPTH_AS_COLOR_REMAP",
       {[] { return depthRead(ps3::kRemapIdentity, Filter::Nearest, false); },
        [] { return depthRead(ps3::kRemapBarg, Filter::Nearest, false); }}},
      {"W_DEPTH_AS_COLOR_FILTER",
       {[] { return depthRead(ps3::kRemapBarg, Filter::Linear, false); },
        [] { return depthRead(ps3::kRemapBarg, Filter::Nearest, false); }}},
      {"W_DEPTH_STENCIL_IN_DECODE",
       {[] { return depthRead(ps3::kRemapIdentity, Filter::Nearest, false); },
        [] { return depthRead(ps3::kRemapBarg, Filter::Nearest, false); }}},
      {"W_DEPTH_FEEDBACK",
       {[] { return depthRead(ps3::kRemapBarg, Filter::Nearest, true); },
        [] { return depthRead(ps3::kRemapBarg, Filter::Nearest, false); }}},
      // D1
      {"E_DX10_DEPTH_SRV_FORMAT",
       {[] { return dx10Read(dx10::DxgiFormat::D24_UNORM_S8_UINT, 1, false, true); },
        [] { return dx10Read(R24G8, 1, false, true); }}},
      {"E_DX10_MSAA_DEPTH_READ", {[] { return dx10Read(R24G8, 4, false, true); }, [] { return dx10Read(R24G8, 1, false, true); }}},
      {"W_DX10_SRV_DSV_HAZARD", {[] { return dx10Read(R24G8, 1, true, true); }, [] { return dx10Read(R24G8, 1, false, true); }}},
      {"W_DX10_DEPTH_NOT_RESOLVED",
       {[] { return dx10Read(R24G8, 1, false, false); }, [] { return dx10Read(R24G8, 1, false, true); }}},
  };
  return s;
}

}  // namespace

TEST(PlatformDiagnostics, CatalogueHasEveryConsolidatedRowWithItsSeverity) {
  for (const auto& [code, severity] : kConsolidated) {
    const CatalogueEntry* e = findCatalogueEntry(code);
    ASSERT_NE(e, nullptr) << code;
    EXPECT_EQ(e->severity, severity) << code;
    EXPECT_TRUE(e->consolidated) << code;
  }
}

TEST(PlatformDiagnostics, CatalogueHasEverySectionCode) {
  for (const std::string& code : kSectionOnly) {
    const CatalogueEntry* e = findCatalogueEntry(code);
    ASSERT_NE(e, nullptr) << code;
    EXPECT_FALSE(e->consolidated) << code;
  }
  for (const std::set<std::string>& own : {kParityOwn, kCapability})
    for (const std::string& code : own) {
      const CatalogueEntry* e = findCatalogueEntry(code);
      ASSERT_NE(e, nullptr) << code;
      EXPECT_FALSE(e->consolidated) << code;
      EXPECT_EQ(e->section == "CAP", own == kCapability) << code;
    }
  EXPECT_EQ(diagnosticCatalogue().size(),
            kConsolidated.size() + kSectionOnly.size() + kParityOwn.size() + kCapability.size());
}

TEST(PlatformDiagnostics, CatalogueEntriesAreWellFormed) {
  const std::set<std::string> sections = {"X1", "X2", "X3", "X4", "X5", "P1", "P2", "P3", "P4", "D1", "CAP"};
  std::set<std::string> codes;
  for (const CatalogueEntry& e : diagnosticCatalogue()) {
    SCOPED_TRACE(std::string(e.code));
    EXPECT_TRUE(codes.insert(std::string(e.code)).second) << "duplicate";
    // Severity follows the prefix.
    char prefix = e.code[0];
    EXPECT_EQ(e.severity, prefix == 'E' ? Severity::Error : prefix == 'W' ? Severity::Warning : Severity::Info);
    EXPECT_EQ(e.code[1], '_');
    EXPECT_FALSE(e.description.empty());
    EXPECT_TRUE(sections.count(std::string(e.section)));
    EXPECT_FALSE(e.platform.empty());
  }
}

TEST(PlatformDiagnostics, UnknownCodesAreRejected) {
  // The pack has no separate overflow code: a budget overflow is E_EDRAM_OVERLAP (X1).
  DiagnosticList d;
  EXPECT_THROW(d.report("E_EDRAM_OVERFLOW", {"x"}, "not a catalogue code"), std::logic_error);
  EXPECT_NO_THROW(d.report("E_EDRAM_OVERLAP", {"a", "b"}, "a overlaps b"));
}

TEST(PlatformDiagnostics, DiagnosticsNameTheirTargets) {
  DiagnosticList d = live({surf("gbuffer0", 1280, 720, 0), surf("depth", 1280, 720, 700)});
  const Diagnostic* o = d.first("E_EDRAM_OVERLAP");
  ASSERT_NE(o, nullptr);
  EXPECT_EQ(o->targets, (std::vector<std::string>{"gbuffer0", "depth"}));
  EXPECT_NE(o->message.find("gbuffer0"), std::string::npos);
  EXPECT_NE(o->message.find("depth"), std::string::npos);
  std::string line = o->format();
  EXPECT_EQ(line.rfind("error E_EDRAM_OVERLAP [X1]: ", 0), 0u) << line;
}

TEST(PlatformDiagnostics, EveryCodeHasATriggerAndANearMiss) {
  for (const CatalogueEntry& e : diagnosticCatalogue())
    if (e.section != "CAP") EXPECT_TRUE(scenarios().count(std::string(e.code))) << e.code;
  for (const auto& [code, scenario] : scenarios()) {
    SCOPED_TRACE(code);
    ASSERT_NE(findCatalogueEntry(code), nullptr);
    DiagnosticList fired = scenario.trigger();
    EXPECT_TRUE(fired.has(code)) << fired.format();
    DiagnosticList quiet = scenario.nearMiss();
    EXPECT_FALSE(quiet.has(code)) << quiet.format();
  }
}

TEST(PlatformDiagnostics, WrapScenarioReallyWraps) {
  // X1 (1): the Fable 2 depth buffer (1120x720 2x) in [1008, 2268).
  x360::EdramSurface d = fable2Depth(1008);
  EXPECT_EQ(d.sizeTiles(), 1260u);
  DiagnosticList out = live({d});
  EXPECT_TRUE(out.has("W_EDRAM_WRAP"));
  EXPECT_FALSE(out.hasErrors());
}

// ---------------------------------------------------------------------------------------------
// Parameters for the pack's open questions
// ---------------------------------------------------------------------------------------------

TEST(PlatformParams, EveryOpenQuestionIsANamedParameter) {
  // "Open questions and uncertainties" 1-5 (6 is about sources, not behaviour).
  std::set<int> covered;
  for (const ParamInfo& p : parameterCatalogue()) {
    SCOPED_TRACE(std::string(p.name));
    EXPECT_FALSE(p.explanation.empty());
    EXPECT_NE(std::string(p.values).find(std::string(p.defaultValue)), std::string::npos);
    if (p.openQuestion) covered.insert(p.openQuestion);
    EXPECT_EQ(parameterValue(PlatformParams{}, p.name), p.defaultValue);  // the struct's defaults
  }
  EXPECT_EQ(covered, (std::set<int>{1, 2, 3, 4, 5}));
}

TEST(PlatformParams, DefaultsFollowThePackRecommendations) {
  PlatformParams p;
  // Open question 1: "default to raw int16 preserved when copy_dest_number = signed".
  EXPECT_EQ(p.signedK16Resolve, SignedK16Resolve::PreserveRawInt16);
  // X1 (3): byte offsets use the mainline layout.
  EXPECT_EQ(p.msaa4xSampleOrder, Msaa4xSampleOrder::XeniaMainline);
  // Open question 4: the P4 decode with a 1-ULP tolerance.
  EXPECT_EQ(p.texDepth2DPrecise, TexDepth2DPrecise::ExactD24Over16777215);
  // Open question 5 / X5: TRUE sets PIX_CENTER = 1; FALSE is the default.
  EXPECT_EQ(p.halfPixelOffsetMapping, HalfPixelOffsetMapping::TrueMeansPixCenterHalf);
  EXPECT_FALSE(p.halfPixelOffset);
}

// x360.k16_host_storage changed nothing on the GPU path (always RG16_SNORM holding the guest
// int16), so it is no parameter: naming it is the one-line unknown-parameter error.
TEST(PlatformParams, K16HostStorageIsNoParameter) {
  PlatformParams p;
  std::string error;
  EXPECT_FALSE(setParameter(p, "x360.k16_host_storage", "interlock", &error));
  EXPECT_EQ(error, "unknown platform parameter 'x360.k16_host_storage'");
  EXPECT_EQ(findParameter("x360.k16_host_storage"), nullptr);
  EXPECT_EQ(describeParameters(p).find("k16_host_storage"), std::string::npos);
}

TEST(PlatformParams, SetByName) {
  PlatformParams p;
  std::string error;
  EXPECT_TRUE(setParameter(p, "x360.signed_k16_resolve", "unsigned-saturate", &error)) << error;
  EXPECT_EQ(p.signedK16Resolve, SignedK16Resolve::UnsignedSaturate);
  EXPECT_TRUE(setParameter(p, "x360.halfpixeloffset", "true", &error));
  EXPECT_TRUE(p.halfPixelOffset);
  EXPECT_FALSE(setParameter(p, "x360.signed_k16_resolve", "maybe", &error));
  EXPECT_NE(error.find("preserve-raw-int16"), std::string::npos);
  EXPECT_FALSE(setParameter(p, "x360.nonsense", "1", &error));
  std::string text = describeParameters(PlatformParams{});
  EXPECT_NE(text.find("x360.signed_k16_resolve = preserve-raw-int16 (default) [open question 1]"), std::string::npos)
      << text;
}

// ---------------------------------------------------------------------------------------------
// The four platforms
// ---------------------------------------------------------------------------------------------

TEST(PlatformMapping, AllFourPlatformsMapEveryLogicalTarget) {
  for (PlatformId id : {PlatformId::Reference, PlatformId::Dx10, PlatformId::Ps3, PlatformId::X360}) {
    EXPECT_EQ(platformFromName(platformName(id)), id);
    for (LogicalFormat f : {LogicalFormat::Rgba8Unorm, LogicalFormat::Rg16Unorm, LogicalFormat::Rgba16Hdr,
                            LogicalFormat::Depth24Stencil8}) {
      TargetMapping m = mapTarget(id, f);
      SCOPED_TRACE(std::string(platformName(id)) + " " + std::string(logicalFormatName(f)));
      EXPECT_NE(m.hostFormat, parity::rhi::Format::Undefined);
      EXPECT_FALSE(m.consoleFormat.empty());
      EXPECT_GT(m.consoleBytesPerPixel, 0u);
    }
  }
  EXPECT_FALSE(platformFromName("ps4").has_value());
  // The reference platform has no quirks: float formats.
  EXPECT_EQ(mapTarget(PlatformId::Reference, LogicalFormat::Rg16Unorm).hostFormat, parity::rhi::Format::RG32F);
}
