// DX10 CPU model against the reference pack's vectors (console-quirks.md, D1).
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cstdlib>
#include <limits>

#include "platforms/dx10/depth_read.h"
#include "platforms/dx10/dx10_platform.h"

using namespace parity::platforms;
using namespace parity::platforms::dx10;

namespace {

int64_t ulpDistance(float a, float b) {
  auto key = [](float f) {
    int32_t i = std::bit_cast<int32_t>(f);
    return i < 0 ? int64_t(std::numeric_limits<int32_t>::min()) - i : int64_t(i);
  };
  return std::llabs(key(a) - key(b));
}

}  // namespace

TEST(Dx10Depth, R24X8Values) {
  // D1 (3): D24 = 0xABCDEF -> 0.67111108727; 0x000001 -> 5.96e-8; 0xFFFFFF -> 1.0.
  // D1 (1): R24_UNORM decodes to D24/16777215.
  EXPECT_LE(ulpDistance(decodeR24X8(0xABCDEF), static_cast<float>(11259375.0 / 16777215.0)), 0);
  EXPECT_NEAR(decodeR24X8(0xABCDEF), 0.67111108727f, 6e-8);
  EXPECT_NEAR(decodeR24X8(0x000001), 5.96e-8f, 5e-11);
  EXPECT_EQ(decodeR24X8(0xFFFFFF), 1.0f);
  EXPECT_EQ(decodeR24X8(0), 0.0f);
}

TEST(Dx10Depth, QuantisationToD24) {
  // D24 = round(d * 16777215): the copy to R24X8 quantises, and decoding gives D24/16777215 back.
  EXPECT_EQ(quantizeD24(1.0f), 0xFFFFFFu);
  EXPECT_EQ(quantizeD24(0.0f), 0u);
  EXPECT_EQ(quantizeD24(decodeR24X8(0xABCDEF)), 0xABCDEFu);
  EXPECT_EQ(quantizeD24(decodeR24X8(0x000001)), 1u);
}

TEST(Dx10Depth, FormatCodes) {
  // D1 (1): FL10.0 table rows 44-46.
  EXPECT_EQ(int(DxgiFormat::R24G8_TYPELESS), 44);
  EXPECT_EQ(int(DxgiFormat::D24_UNORM_S8_UINT), 45);
  EXPECT_EQ(int(DxgiFormat::R24_UNORM_X8_TYPELESS), 46);
}

TEST(Dx10Depth, SingleSampleR24X8ReadIsAllowed) {
  DiagnosticList out;
  DepthRead ok{"depth"};
  DepthReadOutcome o = checkDepthRead(ok, out);
  EXPECT_EQ(o, DepthReadOutcome::Allowed);
  EXPECT_TRUE(out.empty()) << out.format();
  EXPECT_EQ(sampleDepth(0xFFFFFF, o), 1.0f);
}

TEST(Dx10Depth, MsaaDepthSrvIsRefused) {
  // D1 (3): in DX10 mode an MSAA depth SRV must be refused (E_DX10_MSAA_DEPTH_READ).
  DiagnosticList out;
  DepthRead msaa{"depth", DxgiFormat::R24G8_TYPELESS, DxgiFormat::R24_UNORM_X8_TYPELESS, 4};
  EXPECT_EQ(checkDepthRead(msaa, out), DepthReadOutcome::Refused);
  ASSERT_TRUE(out.has("E_DX10_MSAA_DEPTH_READ"));
  EXPECT_NE(out.first("E_DX10_MSAA_DEPTH_READ")->message.find("depth"), std::string::npos);
}

TEST(Dx10Depth, SrvAndDsvTogetherNullTheSrv) {
  // D1 (3): binding the same depth texture as DSV and SRV must null the SRV (sampling returns 0).
  DiagnosticList out;
  DepthRead both{"depth"};
  both.boundAsDsv = true;
  DepthReadOutcome o = checkDepthRead(both, out);
  EXPECT_EQ(o, DepthReadOutcome::NulledSrv);
  EXPECT_TRUE(out.has("W_DX10_SRV_DSV_HAZARD"));
  EXPECT_EQ(sampleDepth(0xABCDEF, o), 0.0f);
}

TEST(Dx10Depth, SrvFormatRules) {
  // D1 (4): E_DX10_DEPTH_SRV_FORMAT: resource not R24G8_TYPELESS or SRV not R24_UNORM_X8_TYPELESS.
  DiagnosticList typed;
  EXPECT_EQ(checkDepthRead({"depth", DxgiFormat::D24_UNORM_S8_UINT, DxgiFormat::R24_UNORM_X8_TYPELESS}, typed),
            DepthReadOutcome::Refused);
  EXPECT_TRUE(typed.has("E_DX10_DEPTH_SRV_FORMAT"));
  DiagnosticList view;
  checkDepthRead({"depth", DxgiFormat::R24G8_TYPELESS, DxgiFormat::X24_TYPELESS_G8_UINT}, view);
  EXPECT_TRUE(view.has("E_DX10_DEPTH_SRV_FORMAT"));
}

TEST(Dx10Depth, StaleDepthCopy) {
  // D1 (4): W_DX10_DEPTH_NOT_RESOLVED: the read was not copied after the last depth write.
  DiagnosticList out;
  DepthRead stale{"depth"};
  stale.resolvedSinceLastDepthWrite = false;
  checkDepthRead(stale, out);
  EXPECT_TRUE(out.has("W_DX10_DEPTH_NOT_RESOLVED"));
}

TEST(Dx10Platform, LogicalTargets) {
  // D1: "All other surfaces can be read from directly"; depth goes through R24X8.
  EXPECT_EQ(mapTarget(LogicalFormat::Rg16Unorm).hostFormat, parity::rhi::Format::RG16_UNORM);
  EXPECT_NE(mapTarget(LogicalFormat::Depth24Stencil8).read.find("R24X8"), std::string::npos);
}
