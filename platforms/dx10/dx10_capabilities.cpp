// What a Direct3D feature level 10.0 device runs at all (capabilities.h): shader model 4 with
// geometry shaders, compute only as the optional cs_4_x of D3D11 on 10.x hardware, and the DXGI
// format-support table of feature level 10.0 (MicrosoftDocs/win32, "Format support for
// Direct3D Feature Level 10.0 hardware": every multisample count there is optional).
#include "platforms/common/capabilities.h"

namespace parity::platforms::dx10 {

namespace {

constexpr Support G = Support::Guaranteed, O = Support::Optional, N = Support::None;

constexpr std::string_view kCs4x = "cs_4_x on feature level 10.x hardware (Microsoft, \"Compute Shaders on Downlevel Hardware\")";
constexpr std::string_view kTable = "DXGI format support, feature level 10.0";

constexpr CapabilityTable kRows = {{
    {Capability::Compute, O, 0,
     "optional on feature level 10.0 (D3D10_X_HARDWARE_OPTIONS: ComputeShaders_Plus_RawAndStructuredBuffers_Via_Shader_4_x)"},
    {Capability::ComputeInvocations, O, 768, kCs4x},
    {Capability::ComputeWorkgroupDepth, O, 1, kCs4x},
    {Capability::ComputeSharedMemory, O, 16384, kCs4x},
    {Capability::ComputeAtomics, N, 0, kCs4x},
    {Capability::ComputeStorageBuffers, O, 1, kCs4x},
    {Capability::ComputeStorageImages, N, 0, kCs4x},
    {Capability::ColorTargets, G, 8, "D3D10_SIMULTANEOUS_RENDER_TARGET_COUNT"},
    {Capability::FragmentTextures, G, 128, "D3D10_COMMONSHADER_INPUT_RESOURCE_SLOT_COUNT"},
    {Capability::VertexTextures, G, 128, "D3D10_COMMONSHADER_INPUT_RESOURCE_SLOT_COUNT"},
    {Capability::Interpolators, G, 15, "D3D10_VS_OUTPUT_REGISTER_COUNT: 16 registers, one of them SV_Position"},
    {Capability::Multisampling, O, 4, "every multisample count is optional at feature level 10.0 (DXGI format support)"},
    {Capability::GeometryShaders, G, 0, "shader model 4"},
    {Capability::TessellationShaders, N, 0, "hull and domain shaders arrive with feature level 11.0"},
    {Capability::GraphicsStorageWrites, N, 0, "UAVs in graphics stages arrive with feature level 11.0"},
    {Capability::EdramBytes, G, 0, "no EDRAM"},
}};
static_assert(hasOneRowPerCapability(kRows), "one row per Capability, in the enum's order");

// Shader model 4 samples any format in any stage: vertex fetch is the filter column's "Shader ld".
constexpr FormatRow kFormats[] = {
    {rhi::Format::RGBA8, "R8G8B8A8_UNORM", G, G, G, G, O, kTable},
    {rhi::Format::RG16_UNORM, "R16G16_UNORM", G, O, G, G, O, kTable},
    {rhi::Format::RG16_SNORM, "R16G16_SNORM", G, N, G, G, O, kTable},
    {rhi::Format::RG16_FLOAT, "R16G16_FLOAT", G, G, G, G, O, kTable},
    {rhi::Format::RGBA16F, "R16G16B16A16_FLOAT", G, G, G, G, O, kTable},
    {rhi::Format::R32F, "R32_FLOAT", G, G, O, G, O, kTable},
    {rhi::Format::RG32F, "R32G32_FLOAT", G, G, O, G, O, kTable},
    {rhi::Format::RGBA32F, "R32G32B32A32_FLOAT", G, G, O, G, O, kTable},
    {rhi::Format::R8, "R8_UNORM", G, G, G, G, O, kTable},
    {rhi::Format::R32_UINT, "R32_UINT", G, N, N, G, O, kTable},
    {rhi::Format::RGBA32_UINT, "R32G32B32A32_UINT", G, N, N, G, O, kTable},
    {rhi::Format::B10G11R11_UFLOAT, "R11G11B10_FLOAT", G, G, G, G, O, kTable},
    // Depth is filtered only by comparison (the RHI refuses a Linear sampler on depth otherwise):
    // sample_c of its R24_UNORM_X8_TYPELESS or R32_FLOAT view is required.
    {rhi::Format::D24S8, "D24_UNORM_S8_UINT", G, N, G, N, O, kTable},
    {rhi::Format::D32F, "D32_FLOAT", G, N, G, N, O, kTable},
    {rhi::Format::Undefined, "R24G8_TYPELESS", G, N, G, G, O, "read through R24_UNORM_X8_TYPELESS (console-quirks D1)"},
};

const PlatformCapabilities kCapabilities{PlatformId::Dx10, kRows, kFormats};

}  // namespace

const PlatformCapabilities& capabilities() { return kCapabilities; }

}  // namespace parity::platforms::dx10
