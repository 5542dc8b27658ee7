// DX10 platform layer: native formats; depth is read through a single-sample R24X8 copy (D1).
#include "platforms/dx10/depth_read.h"
#include "platforms/dx10/dx10_platform.h"
#include "platforms/platform_layer.h"
#include "platforms/platforms.h"

namespace parity::platforms::dx10 {

namespace {

constexpr TargetRow kRgba8 = {.format = LogicalFormat::Rgba8Unorm, .consoleFormat = "R8G8B8A8_UNORM",
                              .consoleBytesPerPixel = 4, .hostFormat = rhi::Format::RGBA8, .write = "unorm8",
                              .read = "sample directly", .source = "D1", .resolve = "none: sampled directly",
                              .effectiveBits = 8};

constexpr TargetTable kTargets = {
    kRgba8,
    // Exact writes go through an RG16_UINT view: the shader rounds v * 65535 as the model does
    // (D3D10 itself would convert in the output merger; the bits it stores are the model's).
    TargetRow{.format = LogicalFormat::Rg16Unorm, .consoleFormat = "R16G16_UNORM", .consoleBytesPerPixel = 4,
              .hostFormat = rhi::Format::RG16_UNORM, .write = "unorm16", .read = "sample directly", .source = "D1",
              .rawViewFormat = rhi::Format::RG16_UINT, .writeFormat = rhi::Format::RG16_UINT,
              .resolve = "none: R16G16_UNORM is sampled directly", .effectiveBits = 16},
    TargetRow{.format = LogicalFormat::Rgba16Hdr, .consoleFormat = "R16G16B16A16_FLOAT", .consoleBytesPerPixel = 8,
              .hostFormat = rhi::Format::RGBA16F, .write = "fp16", .read = "sample directly", .source = "D1",
              .resolve = "none: sampled directly", .effectiveBits = 11},
    TargetRow{.format = LogicalFormat::Depth24Stencil8,
              .consoleFormat = "R24G8_TYPELESS (DSV D24_UNORM_S8_UINT, SRV R24_UNORM_X8_TYPELESS)",
              .consoleBytesPerPixel = 4, .hostFormat = rhi::Format::D24S8, .write = "depth test",
              .read = "copy/resolve to single-sample R24X8, D24 = round(d * 16777215), read D24 / 16777215; never "
                      "MSAA, never while bound as DSV",
              .source = "D1", .readFormat = rhi::Format::R32_UINT, .resolvedWhenRead = true,
              .resolve = "copy of the single-sample depth into R24X8 (R24_UNORM_X8_TYPELESS view of R24G8_TYPELESS), "
                         "read D24 / 16777215",
              .effectiveBits = 24},
    withFormat(kRgba8, LogicalFormat::Rgba8Bits),
    withFormat(kRgba8, LogicalFormat::Output),
    TargetRow{.format = LogicalFormat::R8Unorm, .consoleFormat = "R8_UNORM", .consoleBytesPerPixel = 1,
              .hostFormat = rhi::Format::R8, .write = "unorm8", .read = "sample directly", .source = "D1",
              .resolve = "none: sampled directly", .effectiveBits = 8},
    TargetRow{.format = LogicalFormat::R32Float, .consoleFormat = "R32_FLOAT", .consoleBytesPerPixel = 4,
              .hostFormat = rhi::Format::R32F, .write = "fp32", .read = "sample directly", .source = "D1",
              .resolve = "none: sampled directly", .effectiveBits = 24},
};
static_assert(hasOneRowPerFormat(kTargets), "one row per LogicalFormat, in the enum's order");

}  // namespace

void planTarget(PhysicalTarget& t, const PlatformParams&) { applyTargetRow(rowOf(kTargets, t.logical.format), t); }

TargetMapping mapTarget(LogicalFormat logical, const PlatformParams& params) {
  return platforms::mapTarget(PlatformId::Dx10, logical, params);
}

void shaderDefines(const PlatformParams&, std::vector<std::pair<std::string, std::string>>& out) {
  out.push_back({"PARITY_PLATFORM_DX10", "1"});
}

}  // namespace parity::platforms::dx10
