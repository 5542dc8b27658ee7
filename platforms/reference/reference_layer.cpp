// Reference platform layer: logical formats become float formats; nothing to resolve.
#include "platforms/platform_layer.h"
#include "platforms/platforms.h"
#include "platforms/reference/reference_platform.h"

namespace parity::platforms::reference {

namespace {

constexpr std::string_view kSampledDirectly = "none: the rendered texture is sampled directly";

// Every value passes unchanged; rows differ in their storage and its precision.
constexpr TargetRow unchanged(LogicalFormat format, std::string_view storage, uint32_t bytesPerPixel,
                              rhi::Format host, double effectiveBits) {
  return {.format = format, .consoleFormat = storage, .consoleBytesPerPixel = bytesPerPixel, .hostFormat = host,
          .write = "float, unchanged", .read = "float, unchanged", .source = "none (reference)",
          .resolve = kSampledDirectly, .effectiveBits = effectiveBits};
}

// fp32 keeps every value of [0, 1] a technique writes: 24 bits; the 8-bit formats keep 8 bits.
constexpr TargetTable kTargets = {
    unchanged(LogicalFormat::Rgba8Unorm, "RGBA32F", 16, rhi::Format::RGBA32F, 24),
    unchanged(LogicalFormat::Rg16Unorm, "RG32F", 8, rhi::Format::RG32F, 24),
    unchanged(LogicalFormat::Rgba16Hdr, "RGBA32F", 16, rhi::Format::RGBA32F, 24),
    // A copy, as every console reads depth through one (x360 resolve, dx10 R24X8, ps3 ARGB8
    // view): a later pass may then test against the depth while it samples it, which no host
    // allows of one texture.
    [] {
      TargetRow row = unchanged(LogicalFormat::Depth24Stencil8, "D32F", 4, rhi::Format::D32F, 24);
      row.resolvedWhenRead = true;
      row.resolve = "a copy of the depth texture, sampled while the depth itself stays bound for testing";
      return row;
    }(),
    unchanged(LogicalFormat::Rgba8Bits, "RGBA8 (the bits are the data)", 4, rhi::Format::RGBA8, 8),
    // Planned in the format the harness asks for (applyTargetRow).
    unchanged(LogicalFormat::Output, "the requested output format", 4, rhi::Format::RGBA8, 8),
    unchanged(LogicalFormat::R8Unorm, "R8 (8 bits on every platform)", 1, rhi::Format::R8, 8),
    unchanged(LogicalFormat::R32Float, "R32F", 4, rhi::Format::R32F, 24),
};
static_assert(hasOneRowPerFormat(kTargets), "one row per LogicalFormat, in the enum's order");

// The reference's depth is D32F, which has no stencil (the RHI has no D32F + S8): a technique
// that uses stencil gets D24S8, as every console has.
constexpr TargetRow kDepthWithStencil = [] {
  TargetRow row = rowOf(kTargets, LogicalFormat::Depth24Stencil8);
  row.consoleFormat = "D24S8 (the technique uses stencil)";
  row.hostFormat = rhi::Format::D24S8;
  return row;
}();

}  // namespace

void planTarget(PhysicalTarget& t, const PlatformParams&) {
  const bool depth = t.logical.format == LogicalFormat::Depth24Stencil8;
  applyTargetRow(depth && t.logical.stencil ? kDepthWithStencil : rowOf(kTargets, t.logical.format), t);
  if (!t.resolve.needed) t.resolve.description = kSampledDirectly;  // no pass reads the depth: nothing to copy
}

TargetMapping mapTarget(LogicalFormat logical, const PlatformParams& params) {
  return platforms::mapTarget(PlatformId::Reference, logical, params);
}

void shaderDefines(const PlatformParams&, std::vector<std::pair<std::string, std::string>>& out) {
  out.push_back({"PARITY_PLATFORM_REFERENCE", "1"});
}

}  // namespace parity::platforms::reference
