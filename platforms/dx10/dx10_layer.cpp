// DX10 platform layer: native formats; depth is read through a single-sample R24X8 copy (D1).
#include "platforms/dx10/depth_read.h"
#include "platforms/dx10/dx10_platform.h"
#include "platforms/platform_layer.h"

namespace parity::platforms::dx10 {

void planTarget(PhysicalTarget& t, const PlatformParams& params) {
  t.mapping = mapTarget(t.logical.format, params);
  t.attachmentFormat = t.mapping.hostFormat;
  t.readFormat = t.attachmentFormat;
  switch (t.logical.format) {
    case LogicalFormat::Rgba8Unorm:
    case LogicalFormat::Output:
    case LogicalFormat::Rgba8Bits:
      t.resolve = {false, "none: sampled directly", 8};
      break;
    case LogicalFormat::Rg16Unorm:
      // Exact writes go through an RG16_UINT view: the shader rounds v * 65535 as the model does
      // (D3D10 itself would convert in the output merger; the bits it stores are the model's).
      t.rawViewFormat = rhi::Format::RG16_UINT;
      t.writeFormat = rhi::Format::RG16_UINT;
      t.resolve = {false, "none: R16G16_UNORM is sampled directly", rg16EffectiveBits(PlatformId::Dx10, params)};
      break;
    case LogicalFormat::Rgba16Hdr:
      t.resolve = {false, "none: sampled directly", 11};
      break;
    case LogicalFormat::R8Unorm:
      t.resolve = {false, "none: sampled directly", 8};
      break;
    case LogicalFormat::R32Float:
      t.resolve = {false, "none: sampled directly", 24};
      break;
    case LogicalFormat::Depth24Stencil8:
      t.readFormat = rhi::Format::R32_UINT;
      t.resolve = {t.logical.readLater,
                   "copy of the single-sample depth into R24X8 (R24_UNORM_X8_TYPELESS view of R24G8_TYPELESS), "
                   "read D24 / 16777215",
                   depthEffectiveBits(PlatformId::Dx10)};
      break;
  }
}

void shaderDefines(const PlatformParams&, std::vector<std::pair<std::string, std::string>>& out) {
  out.push_back({"PARITY_PLATFORM_DX10", "1"});
}

}  // namespace parity::platforms::dx10
