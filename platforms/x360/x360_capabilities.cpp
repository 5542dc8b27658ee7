// What Xenos runs at all (capabilities.h), as the XNA Framework's HiDef profile states the Xbox
// 360's limits (FNA's ProfileCapabilities.cs copies them from XNA 4.0) and Xenia's xenos.h its
// render-target formats.
#include "platforms/common/capabilities.h"

namespace parity::platforms::x360 {

namespace {

constexpr Support G = Support::Guaranteed, N = Support::None;

constexpr std::string_view kNoCompute =
    "Xenos runs vertex and pixel shaders of shader model 3 (XNA HiDef); a port moves compute work to the CPU "
    "or to pixel passes";
constexpr std::string_view kTargets = "xenos.h ColorRenderTargetFormat and DepthRenderTargetFormat";
constexpr std::string_view kHiDefFloat =
    "XNA HiDef: float formats are vertex-texture formats, never filtered, and (but for HdrBlendable) never blended";

constexpr CapabilityTable kRows = {{
    {Capability::Compute, N, 0, kNoCompute},
    {Capability::ComputeInvocations, N, 0, kNoCompute},
    {Capability::ComputeWorkgroupDepth, N, 0, kNoCompute},
    {Capability::ComputeSharedMemory, N, 0, kNoCompute},
    {Capability::ComputeAtomics, N, 0, kNoCompute},
    {Capability::ComputeStorageBuffers, N, 0, kNoCompute},
    {Capability::ComputeStorageImages, N, 0, kNoCompute},
    {Capability::ColorTargets, G, 4, "xenos.h kMaxColorRenderTargets; XNA HiDef MaxRenderTargets"},
    {Capability::FragmentTextures, G, 16, "XNA HiDef MaxSamplers"},
    {Capability::VertexTextures, G, 4, "XNA HiDef MaxVertexSamplers"},
    {Capability::Interpolators, G, 16, "xenos.h kMaxInterpolators"},
    {Capability::Multisampling, G, 4, "EDRAM holds 2x and 4x surfaces (console-quirks X1)"},
    {Capability::GeometryShaders, N, 0, "shader model 3: no geometry stage"},
    {Capability::TessellationShaders, N, 0, "the Xenos tessellator is fixed-function: no hull or domain shaders"},
    {Capability::GraphicsStorageWrites, N, 0, "shader model 3 has no UAVs (memexport is not modelled)"},
    {Capability::EdramBytes, G, 10485760, "10 MiB of EDRAM, 2048 tiles of 80x16 32-bit samples (console-quirks X1)"},
}};
static_assert(hasOneRowPerCapability(kRows), "one row per Capability, in the enum's order");

constexpr FormatRow kFormats[] = {
    {rhi::Format::RGBA8, "k_8_8_8_8", G, G, G, N, G, kTargets},
    {rhi::Format::RG16_UNORM, "k_16_16", G, G, G, N, G, kTargets},
    {rhi::Format::RG16_SNORM, "k_16_16", G, G, G, N, G, kTargets},
    {rhi::Format::RGBA16_SNORM, "k_16_16_16_16", G, G, G, N, G, kTargets},
    {rhi::Format::RG16_FLOAT, "k_16_16_FLOAT", G, N, N, G, G, kHiDefFloat},
    {rhi::Format::RGBA16F, "k_16_16_16_16_FLOAT", G, N, N, G, G, kHiDefFloat},
    {rhi::Format::R32F, "k_32_FLOAT", G, N, N, G, G, kHiDefFloat},
    {rhi::Format::RG32F, "k_32_32_FLOAT", G, N, N, G, G, kHiDefFloat},
    {rhi::Format::Undefined, "k_2_10_10_10_FLOAT", G, G, G, N, G, "XNA HiDef HdrBlendable: blended and filtered"},
    {rhi::Format::D24S8, "D24S8", G, N, G, N, G, kTargets},
    {rhi::Format::RGBA32F, "k_32_32_32_32_FLOAT", N, N, N, G, N,
     "a texture format only: no 128-bit colour render target (xenos.h); XNA HiDef float rules"},
    {rhi::Format::R8, "k_8", N, N, G, N, N, "a texture format only: no 8-bit colour render target (xenos.h)"},
    {rhi::Format::D32F, "D32F", N, N, N, N, N, "depth targets are D24S8 and D24FS8 only (xenos.h)"},
    {rhi::Format::D16, "D16", N, N, N, N, N, "depth targets are D24S8 and D24FS8 only (xenos.h)"},
    {rhi::Format::RGBA8_UINT, "RGBA8_UINT", N, N, N, N, N, "no integer colour render target (xenos.h)"},
    {rhi::Format::R32_UINT, "R32_UINT", N, N, N, N, N, "no integer colour render target (xenos.h)"},
    {rhi::Format::R32_SINT, "R32_SINT", N, N, N, N, N, "no integer colour render target (xenos.h)"},
    {rhi::Format::RGBA32_UINT, "RGBA32_UINT", N, N, N, N, N, "no integer colour render target (xenos.h)"},
    {rhi::Format::B10G11R11_UFLOAT, "R11G11B10_FLOAT", N, N, N, N, N, "no 11/11/10 float render target (xenos.h)"},
};

const PlatformCapabilities kCapabilities{PlatformId::X360, kRows, kFormats};

}  // namespace

const PlatformCapabilities& capabilities() { return kCapabilities; }

}  // namespace parity::platforms::x360
