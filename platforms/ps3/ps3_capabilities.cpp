// What RSX runs at all (capabilities.h): shader model 3 vertex and fragment programs, the
// CELL_GCM surface formats, NV4x blending and filtering.
#include "platforms/common/capabilities.h"

namespace parity::platforms::ps3 {

namespace {

constexpr Support G = Support::Guaranteed, N = Support::None;

constexpr std::string_view kNoCompute = "RSX runs vertex and fragment programs only; a port moves compute work to the SPUs or to pixel passes";
constexpr std::string_view kSurfaces = "CELL_GCM_SURFACE_* colour and depth formats (gcm_enums.h, console-quirks P1)";
constexpr std::string_view kNv4x =
    "GeForce 6 series (RSX's family): fp16 textures filter and fp16 surfaces blend, fp32 ones do neither "
    "(GPU Gems 2, ch. 30)";
constexpr std::string_view kVertexTextures = "vp40 profile: vertex textures are fp32 formats only";

constexpr CapabilityTable kRows = {{
    {Capability::Compute, N, 0, kNoCompute},
    {Capability::ComputeInvocations, N, 0, kNoCompute},
    {Capability::ComputeWorkgroupDepth, N, 0, kNoCompute},
    {Capability::ComputeSharedMemory, N, 0, kNoCompute},
    {Capability::ComputeAtomics, N, 0, kNoCompute},
    {Capability::ComputeStorageBuffers, N, 0, kNoCompute},
    {Capability::ComputeStorageImages, N, 0, kNoCompute},
    {Capability::ColorTargets, G, 4, "CELL_GCM_SURFACE_TARGET_MRT3: surfaces A to D (console-quirks P1)"},
    {Capability::FragmentTextures, G, 16, "fp40 profile: texture units TEXUNIT0 to TEXUNIT15"},
    {Capability::VertexTextures, G, 4, "vp40 profile: four vertex texture units"},
    {Capability::Interpolators, G, 10, "fp40 profile: varyings TEXCOORD0 to TEXCOORD7, COLOR0 and COLOR1"},
    {Capability::Multisampling, G, 4, "CELL_GCM_SURFACE_CENTER_1, DIAGONAL_CENTERED_2, SQUARE_*_4 (console-quirks P5)"},
    {Capability::GeometryShaders, N, 0, "shader model 3 (vp40, fp40): no geometry stage"},
    {Capability::TessellationShaders, N, 0, "shader model 3 (vp40, fp40): no tessellation stages"},
    {Capability::GraphicsStorageWrites, N, 0, "fp40 and vp40 programs write their outputs only"},
    {Capability::EdramBytes, G, 0, "no EDRAM: surfaces live in local or main memory"},
}};
static_assert(hasOneRowPerCapability(kRows), "one row per Capability, in the enum's order");

// The antialias field of SET_SURFACE_FORMAT is one for every colour format (P1, P5).
constexpr FormatRow kFormats[] = {
    {rhi::Format::RGBA8, "A8R8G8B8", G, G, G, N, G, kSurfaces},
    {rhi::Format::R8, "B8", G, G, G, N, G, kSurfaces},
    {rhi::Format::RGBA16F, "F_W16Z16Y16X16", G, G, G, N, G, kNv4x},
    {rhi::Format::RGBA32F, "F_W32Z32Y32X32", G, N, N, G, G, kNv4x},
    {rhi::Format::R32F, "F_X32", G, N, N, G, G, kNv4x},
    {rhi::Format::D24S8, "Z24S8", G, N, G, N, G, kSurfaces},
    {rhi::Format::D16, "Z16", G, N, G, N, G, kSurfaces},
    // No surface of these (they exist as textures: Y16_X16, Y16_X16_FLOAT, W32_Z32_Y32_X32_FLOAT).
    {rhi::Format::RG16_UNORM, "Y16_X16", N, N, G, N, N, "no 2x16-bit colour surface (gcm_enums.h, console-quirks P1)"},
    {rhi::Format::RG16_SNORM, "Y16_X16_SNORM", N, N, G, N, N, "no 2x16-bit colour surface (gcm_enums.h, console-quirks P1)"},
    {rhi::Format::RG16_FLOAT, "Y16_X16_FLOAT", N, N, G, N, N, "no 2x16-bit colour surface (gcm_enums.h, console-quirks P1)"},
    {rhi::Format::RG16_UINT, "Y16_X16_UINT", N, N, N, N, N, "no 2x16-bit colour surface (gcm_enums.h, console-quirks P1)"},
    {rhi::Format::RG32F, "F_Y32X32", N, N, N, N, N, "no 2x32-bit colour surface (gcm_enums.h)"},
    {rhi::Format::D32F, "Z32F", N, N, N, N, N, "depth surfaces are Z16 and Z24S8 only (gcm_enums.h)"},
    {rhi::Format::RGBA8_UINT, "RGBA8_UINT", N, N, N, N, N, "no integer colour surface (gcm_enums.h)"},
    {rhi::Format::R32_UINT, "R32_UINT", N, N, N, N, N, "no integer colour surface (gcm_enums.h)"},
    {rhi::Format::R32_SINT, "R32_SINT", N, N, N, N, N, "no integer colour surface (gcm_enums.h)"},
    {rhi::Format::RGBA32_UINT, "RGBA32_UINT", N, N, N, N, N, "no integer colour surface (gcm_enums.h)"},
    {rhi::Format::B10G11R11_UFLOAT, "R11G11B10_FLOAT", N, N, N, N, N, "no 11/11/10 float surface (gcm_enums.h)"},
};

const PlatformCapabilities kCapabilities{PlatformId::Ps3, kRows, kFormats};

}  // namespace

const PlatformCapabilities& capabilities() { return kCapabilities; }

}  // namespace parity::platforms::ps3
