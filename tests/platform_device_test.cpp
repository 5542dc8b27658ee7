// The PlatformDevice a technique draws through (platforms/platform_device.h): it collects the
// diagnostics of the plans allocated on it and checks every draw into a platform target with the
// real pipeline's state. A blended draw into a PS3 packed two-16-bit target is E_PACKED_BLEND, a
// partial write mask splitting its bytes W_PACKED_PARTIAL_WRITEMASK; the same draws into a plain
// RGBA8 target raise nothing; a multiplicative blend into an x360 fixed-point surface is
// W_FIXED16_MULT_BLEND.
#include <gtest/gtest.h>

#include "platforms/platform_device.h"
#include "platforms/platform_layer.h"
#include "rhi/shader_compiler.h"
#include "test_support.h"

using namespace parity;
using namespace parity::platforms;

namespace {

const char* kVs = R"(#version 450
void main() {
  vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
})";
const char* kFs = R"(#version 450
layout(location = 0) out vec4 o;
void main() { o = vec4(0.25); })";

class PlatformDeviceTest : public ::testing::TestWithParam<std::string> {
 protected:
  // One full-screen draw into `target` of a plan with a packed (Rg16Unorm) and a plain target.
  DiagnosticList drawInto(PlatformId platform, const char* target, const rhi::BlendState& blend, uint8_t writeMask) {
    auto host = test::makeDevice(GetParam());
    if (!host) return {};
    PlatformDevice device(*host, platform, {});
    const LogicalTarget logical[] = {{"dsf", LogicalFormat::Rg16Unorm, true, TargetRole::Plain, "p"},
                                     {"albedo", LogicalFormat::Rgba8Unorm, true, TargetRole::Plain, "q"},
                                     {"light", LogicalFormat::Rgba16Hdr, true, TargetRole::Plain, "r"}};
    DiagnosticList found;
    {
      GpuTargets targets(device, planTargets(platform, logical, 8, 8));
      rhi::PipelineDesc p;
      p.vertexShader = test::makeShader(device, rhi::ShaderStage::Vertex, kVs);
      p.fragmentShader = test::makeShader(device, rhi::ShaderStage::Fragment, kFs);
      p.colorTargets[0].format = targets.plan().find(target)->attachmentFormat;
      p.colorTargets[0].blend = blend;
      p.colorTargets[0].writeMask = writeMask;
      p.colorTargetCount = 1;
      p.label = "packed draw";
      rhi::PipelineHandle pipeline = device.createPipeline(p);
      rhi::PassDesc pass;
      pass.colors[0].texture = targets.attachment(target);
      pass.label = "p";
      device.beginPass(pass);
      device.setPipeline(pipeline);
      device.draw(3);
      device.endPass();
      device.submit();
      device.destroy(pipeline);
      device.destroy(p.vertexShader);
      device.destroy(p.fragmentShader);
      found = device.diagnostics();
    }
    return found;
  }
};

rhi::BlendState additive() {
  rhi::BlendState b;
  b.enabled = true;
  b.srcColor = b.dstColor = b.srcAlpha = b.dstAlpha = rhi::BlendFactor::One;
  return b;
}

TEST_P(PlatformDeviceTest, DrawsIntoPackedTargetsAreCheckedWithTheRealPipeline) {
  DiagnosticList blended = drawInto(PlatformId::Ps3, "dsf", additive(), rhi::ColorMask_All);
  if (HasFatalFailure() || IsSkipped()) return;
  EXPECT_TRUE(blended.has("E_PACKED_BLEND")) << blended.format();
  const Diagnostic* where = blended.first("E_PACKED_BLEND");
  ASSERT_NE(where, nullptr);
  EXPECT_EQ(where->pass, "p") << "a draw's diagnostic names the pass it fired in";
  EXPECT_EQ(where->pipeline, "packed draw") << "and the pipeline";
  // The host mask is translated to console channels (host r, g = console R, A: both bytes of X).
  DiagnosticList masked = drawInto(PlatformId::Ps3, "dsf", {}, rhi::ColorMask_G);
  EXPECT_TRUE(masked.has("W_PACKED_PARTIAL_WRITEMASK")) << masked.format();
  EXPECT_FALSE(masked.has("E_PACKED_BLEND")) << masked.format();
  DiagnosticList wholeX = drawInto(PlatformId::Ps3, "dsf", {}, rhi::ColorMask_R | rhi::ColorMask_G);
  EXPECT_FALSE(wholeX.has("W_PACKED_PARTIAL_WRITEMASK")) << wholeX.format();
  DiagnosticList plain = drawInto(PlatformId::Ps3, "albedo", additive(), rhi::ColorMask_R);
  EXPECT_FALSE(plain.has("E_PACKED_BLEND") || plain.has("W_PACKED_PARTIAL_WRITEMASK")) << plain.format();

  rhi::BlendState modulate = additive();
  modulate.srcColor = rhi::BlendFactor::DstColor;
  modulate.dstColor = rhi::BlendFactor::Zero;
  // (A k_16_16_16_16 surface: the host's RG16_SNORM k_16_16 storage cannot blend on lavapipe.)
  DiagnosticList fixed16 = drawInto(PlatformId::X360, "light", modulate, rhi::ColorMask_All);
  EXPECT_TRUE(fixed16.has("W_FIXED16_MULT_BLEND")) << fixed16.format();
  DiagnosticList added = drawInto(PlatformId::X360, "light", additive(), rhi::ColorMask_All);
  EXPECT_FALSE(added.has("W_FIXED16_MULT_BLEND")) << added.format();
}

INSTANTIATE_TEST_SUITE_P(Backends, PlatformDeviceTest, ::testing::ValuesIn(test::allBackends()), test::BackendName());

}  // namespace
