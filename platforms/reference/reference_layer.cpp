// Reference platform layer: logical formats become float formats; nothing to resolve.
#include "platforms/platform_layer.h"
#include "platforms/reference/reference_platform.h"

namespace parity::platforms::reference {

void planTarget(PhysicalTarget& t, const PlatformParams& params) {
  t.mapping = mapTarget(t.logical.format, params);
  if (t.logical.format == LogicalFormat::Depth24Stencil8 && t.logical.stencil) {
    // The reference's depth is D32F, which has no stencil (the RHI has no D32F + S8): a
    // technique that uses stencil gets D24S8, as every console has.
    t.mapping.consoleFormat = "D24S8 (the technique uses stencil)";
    t.mapping.hostFormat = rhi::Format::D24S8;
  }
  t.attachmentFormat = t.mapping.hostFormat;
  t.readFormat = t.attachmentFormat;
  t.resolve.needed = false;
  t.resolve.description = "none: the rendered texture is sampled directly";
  if (t.logical.format == LogicalFormat::Depth24Stencil8 && t.logical.readLater) {
    // A copy, as every console reads depth through one (x360 resolve, dx10 R24X8, ps3 ARGB8
    // view): a later pass may then test against the depth while it samples it, which no host
    // allows of one texture.
    t.resolve.needed = true;
    t.resolve.description = "a copy of the depth texture, sampled while the depth itself stays bound for testing";
  }
  t.resolve.effectiveBits = t.logical.format == LogicalFormat::Depth24Stencil8 ? depthEffectiveBits(PlatformId::Reference)
                                                                              : rg16EffectiveBits(PlatformId::Reference);
  if (t.logical.format == LogicalFormat::Rgba8Unorm) t.resolve.effectiveBits = 24;
  if (t.logical.format == LogicalFormat::Output || t.logical.format == LogicalFormat::Rgba8Bits ||
      t.logical.format == LogicalFormat::R8Unorm)
    t.resolve.effectiveBits = 8;
  if (t.logical.format == LogicalFormat::R32Float) t.resolve.effectiveBits = 24;
}

void shaderDefines(const PlatformParams&, std::vector<std::pair<std::string, std::string>>& out) {
  out.push_back({"PARITY_PLATFORM_REFERENCE", "1"});
}

}  // namespace parity::platforms::reference
