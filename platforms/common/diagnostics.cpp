#include "platforms/common/diagnostics.h"

#include <algorithm>
#include <array>
#include <stdexcept>

namespace parity::platforms {

namespace {

constexpr Severity E = Severity::Error;
constexpr Severity W = Severity::Warning;
constexpr Severity I = Severity::Info;

// The reference pack's catalogue. Descriptions paraphrase the pack's trigger in one line.
constexpr std::array kCatalogue = {
    // X1: EDRAM geometry.
    CatalogueEntry{"E_EDRAM_OVERLAP", E, "x360",
                   "two concurrently live surfaces have intersecting tile sets [base, base+tiles) mod 2048 "
                   "(live surfaces needing more than 2048 tiles together cannot avoid it)",
                   "X1", true},
    CatalogueEntry{"E_EDRAM_SURFACE_TOO_LARGE", E, "x360",
                   "one surface needs more than 2048 tiles, so it overlaps itself", "X1", true},
    CatalogueEntry{"W_EDRAM_WRAP", W, "x360",
                   "base + tiles > 2048: the surface wraps to tile 0 (legal on hardware, titles rely on it)",
                   "X1", true},
    CatalogueEntry{"E_MRT_SURFACE_INFO_MISMATCH", E, "x360",
                   "targets bound together request different pitch or MSAA; RB_SURFACE_INFO is shared",
                   "X1", true},
    CatalogueEntry{"W_RT_SAME_BASE", W, "x360",
                   "two bound targets have the same base tile (Xenia drops one of them)", "X1", false},
    CatalogueEntry{"E_EDRAM_NOT_READABLE", E, "x360",
                   "a shader samples a render target without a resolve; EDRAM is only reachable by the RB "
                   "stage and resolves",
                   "X1", true},
    // X2: k_16_16 / k_16_16_16_16 fixed point.
    CatalogueEntry{"W_FIXED16_RANGE_CLAMP", W, "x360",
                   "|v * 2^color_exp_bias| > 32 written to a k_16_16 target: clamped to +-32 (count reported)",
                   "X2", true},
    CatalogueEntry{"W_FIXED16_NAN", W, "x360", "NaN written to a k_16_16 target: stored as 0", "X2", true},
    CatalogueEntry{"W_FIXED16_PRECISION", W, "x360",
                   "the shader only uses [0,1] with color_exp_bias 0 on a k_16_16 target: about 10 effective bits",
                   "X2", true},
    CatalogueEntry{"W_FLOAT7E3_RANGE_CLAMP", W, "x360",
                   "a colour outside [0, 31.875] (or NaN) written to a k_2_10_10_10_FLOAT (7e3) target: stored as 0 "
                   "below, 31.875 above (count reported; parity's own, the pack names no 7e3 code)",
                   "X2", false},
    CatalogueEntry{"W_FIXED16_MULT_BLEND", W, "x360",
                   "DEST_COLOR or SRC_COLOR blend factors on a k_16_16 target while the host stores it as "
                   "SNORM divided by 32 (blend wrong by a factor of 32)",
                   "X2", true},
    // X3: resolves.
    CatalogueEntry{"E_RESOLVE_ALIGNMENT", E, "x360",
                   "resolve rectangle origin or size is not a multiple of 8 pixels", "X3", true},
    CatalogueEntry{"E_RESOLVE_PACKED_MIP", E, "x360",
                   "resolve destination mip level smaller than 32x32 (the GPU cannot resolve to packed mips)",
                   "X3", true},
    CatalogueEntry{"W_RESOLVE_SIGN_LOSS", W, "x360",
                   "k_16_16 source with negative values resolved into an unsigned destination "
                   "(copy_dest_number = 0): count of clamped texels reported",
                   "X3", true},
    CatalogueEntry{"W_RESOLVE_RANGE_CLAMP", W, "x360",
                   "|f * 2^copy_dest_exp_bias| > 1 resolved into a UNORM destination", "X3", true},
    CatalogueEntry{"W_RESOLVE_PRECISION", W, "x360",
                   "effective precision of the write/resolve/sample path is below 16 bits "
                   "(log2 of the levels actually reachable)",
                   "X3", true},
    CatalogueEntry{"E_DEPTH_RESOLVE_CONVERT", E, "x360",
                   "a depth resolve requests format conversion, sample averaging or exponent bias", "X3", false},
    // X4: inferred-lighting placement rules.
    CatalogueEntry{"E_GBUF_OVERLAP", E, "x360", "two G-buffer surfaces (depth included) overlap in EDRAM", "X4",
                   true},
    CatalogueEntry{"E_LBUF_DEPTH_ALIAS", E, "x360",
                   "the L-buffer overlaps the depth/stencil surface's EDRAM tiles, which the light pass still "
                   "tests against",
                   "X4", true},
    CatalogueEntry{"E_USE_BEFORE_RESOLVE", E, "x360",
                   "an aliasing write to G-buffer tiles before their resolve has been issued", "X4", false},
    // X5: pixel centres.
    CatalogueEntry{"W_D3D9_PIXEL_CENTER", W, "x360",
                   "full-screen or post-process draw with PIX_CENTER = 0 and no compensating -0.5 vertex offset",
                   "X5", true},
    CatalogueEntry{"I_HALFPIXEL_MODE_CHANGE", I, "x360", "the pixel-centre state flips within a pass", "X5",
                   false},
    // P1: RSX colour surfaces and MRT.
    CatalogueEntry{"E_RSX_NO_RG16_SURFACE", E, "ps3",
                   "a 2x16-bit colour target is requested; RSX has no such surface format", "P1", true},
    CatalogueEntry{"E_MRT_FORMAT_MISMATCH", E, "ps3",
                   "strict PS3 mode: targets bound together have different formats (one SET_SURFACE_FORMAT field)",
                   "P1", true},
    CatalogueEntry{"E_MRT_BPP_MISMATCH", E, "ps3/d3d9",
                   "D3D9 / paper mode: targets bound together have different bits per pixel", "P1", true},
    CatalogueEntry{"W_MRT_SHARED_BLEND", W, "ps3",
                   "per-target blend functions differ; RSX applies one blend function to all targets", "P1",
                   false},
    // P2: two 16-bit values packed into ARGB8, read as Y16_X16.
    CatalogueEntry{"W_PACKED_VIEW_MISMATCH", W, "ps3",
                   "a packed16x2 surface is sampled as A8R8G8B8 instead of Y16_X16", "P2", true},
    CatalogueEntry{"W_PACKED_FILTER", W, "ps3",
                   "linear or anisotropic filtering of the ARGB8 view of packed data decoded per byte", "P2",
                   true},
    CatalogueEntry{"E_Y16X16_REMAP_INVALID", E, "ps3",
                   "Y16_X16 remap low byte not one of 0xE4, 0x4E, 0xEE, 0x44", "P2", true},
    CatalogueEntry{"I_TYPELESS_COPY", I, "ps3",
                   "the host needed a typeless copy (ARGB8 render target read as Y16_X16); performance only",
                   "P2", false},
    // P3: packed targets have no alpha.
    CatalogueEntry{"E_PACKED_BLEND", E, "ps3", "blending enabled on a packed16x2 target", "P3", true},
    CatalogueEntry{"E_PACKED_ALPHA_TEST", E, "ps3",
                   "alpha test on a draw whose packed16x2 target's alpha holds the high byte of a 16-bit value",
                   "P3", false},
    CatalogueEntry{"W_PACKED_PARTIAL_WRITEMASK", W, "ps3",
                   "colour write mask covers only some bytes of a packed 16-bit value (A/R or G/B split)", "P3",
                   false},
    CatalogueEntry{"E_PACKED_MSAA_RESOLVE", E, "ps3",
                   "MSAA averaging of a packed16x2 target averages bytes, not values", "P3", false},
    // P4: depth read through an ARGB8 view.
    CatalogueEntry{"E_DEPTH_AS_COLOR_REMAP", E, "ps3",
                   "depth sampled as ARGB8 and decoded via .rgb with remap != 0xAA93 (or via .arg with remap != "
                   "0xAAE4)",
                   "P4", true},
    CatalogueEntry{"W_DEPTH_AS_COLOR_FILTER", W, "ps3",
                   "depth sampled as ARGB8 with a min/mag filter other than NEAREST", "P4", true},
    CatalogueEntry{"W_DEPTH_STENCIL_IN_DECODE", W, "ps3", "the stencil byte feeds the depth decode", "P4", false},
    CatalogueEntry{"W_DEPTH_FEEDBACK", W, "ps3", "a depth surface is sampled while bound for depth writes", "P4",
                   false},
    // D1: DX10 depth reads.
    CatalogueEntry{"E_DX10_DEPTH_SRV_FORMAT", E, "dx10",
                   "depth resource is not R24G8_TYPELESS or its SRV is not R24_UNORM_X8_TYPELESS", "D1", true},
    CatalogueEntry{"E_DX10_MSAA_DEPTH_READ", E, "dx10",
                   "MSAA depth read on feature level 10.0 (no MSAA load for R24_UNORM_X8_TYPELESS)", "D1", true},
    CatalogueEntry{"W_DX10_SRV_DSV_HAZARD", W, "dx10",
                   "the same subresource is bound as SRV and DSV: the runtime nulls the SRV (reads return 0)",
                   "D1", true},
    CatalogueEntry{"W_DX10_DEPTH_NOT_RESOLVED", W, "dx10",
                   "a read of depth that was not copied (resolved) after the last depth write", "D1", false},
    // CAP: what a platform can run at all (parity's own; capabilities.h, one table per platform).
    CatalogueEntry{"E_CAP_COMPUTE", E, "ps3, x360", "a dispatch where the platform has no compute shaders", "CAP", false},
    CatalogueEntry{"E_CAP_COMPUTE_INVOCATIONS", E, "dx10", "a workgroup of more invocations than the platform's compute allows", "CAP", false},
    CatalogueEntry{"E_CAP_COMPUTE_WORKGROUP_DEPTH", E, "dx10", "a workgroup deeper in z than the platform's compute allows", "CAP", false},
    CatalogueEntry{"E_CAP_COMPUTE_SHARED_MEMORY", E, "dx10", "more workgroup-shared memory than the platform's compute has", "CAP", false},
    CatalogueEntry{"E_CAP_COMPUTE_ATOMICS", E, "dx10", "atomic operations in a compute shader where the platform has none", "CAP", false},
    CatalogueEntry{"E_CAP_COMPUTE_STORAGE_BUFFERS", E, "dx10", "a dispatch writes more storage buffers (UAVs) than the platform binds", "CAP", false},
    CatalogueEntry{"E_CAP_COMPUTE_STORAGE_IMAGES", E, "dx10", "a compute shader writes typed storage images where the platform has none", "CAP", false},
    CatalogueEntry{"E_CAP_COLOR_TARGETS", E, "ps3, x360, dx10", "a pipeline writes more colour targets than the platform binds", "CAP", false},
    CatalogueEntry{"E_CAP_FRAGMENT_TEXTURES", E, "ps3, x360, dx10", "a fragment shader reads more textures than the platform has samplers", "CAP", false},
    CatalogueEntry{"E_CAP_VERTEX_TEXTURES", E, "ps3, x360, dx10", "the vertex stages read more textures than the platform has vertex samplers", "CAP", false},
    CatalogueEntry{"E_CAP_INTERPOLATORS", E, "ps3, x360, dx10", "a fragment shader reads more interpolated vec4 inputs than the platform has", "CAP", false},
    CatalogueEntry{"E_CAP_MULTISAMPLING", E, "ps3, x360, dx10", "more samples per pixel than the platform has", "CAP", false},
    CatalogueEntry{"E_CAP_GEOMETRY_SHADERS", E, "ps3, x360", "a geometry shader where the platform has none", "CAP", false},
    CatalogueEntry{"E_CAP_TESSELLATION_SHADERS", E, "ps3, x360, dx10", "tessellation shaders where the platform has none", "CAP", false},
    CatalogueEntry{"E_CAP_GRAPHICS_STORAGE_WRITES", E, "ps3, x360, dx10", "a vertex or fragment shader writes storage buffers or images (UAVs)", "CAP", false},
    CatalogueEntry{"E_CAP_EDRAM_BYTES", E, "x360", "a pass binds more render-target bytes at once than EDRAM holds", "CAP", false},
    CatalogueEntry{"E_CAP_RENDER_FORMAT", E, "ps3, x360, dx10", "a texture is rendered to in a format the platform cannot render", "CAP", false},
    CatalogueEntry{"E_CAP_BLEND_FORMAT", E, "ps3, x360, dx10", "blending into a format the platform cannot blend", "CAP", false},
    CatalogueEntry{"E_CAP_FILTER_FORMAT", E, "ps3, x360, dx10", "a Linear filter on a format the platform cannot filter", "CAP", false},
    CatalogueEntry{"E_CAP_VERTEX_FETCH_FORMAT", E, "ps3, x360", "a vertex shader reads a texture format the platform cannot fetch there", "CAP", false},
    CatalogueEntry{"E_CAP_MULTISAMPLE_FORMAT", E, "ps3, x360, dx10", "a multisampled attachment in a format the platform cannot multisample", "CAP", false},
    CatalogueEntry{"W_CAP_OPTIONAL", W, "dx10", "a feature the platform only allows (optional at DX10 feature level 10.0): a port needs a fallback", "CAP", false},
};

}  // namespace

std::string_view severityName(Severity severity) {
  switch (severity) {
    case Severity::Error: return "error";
    case Severity::Warning: return "warning";
    case Severity::Info: return "info";
  }
  return "?";
}

std::span<const CatalogueEntry> diagnosticCatalogue() { return kCatalogue; }

const CatalogueEntry* findCatalogueEntry(std::string_view code) {
  for (const CatalogueEntry& e : kCatalogue)
    if (e.code == code) return &e;
  return nullptr;
}

std::string Diagnostic::format() const {
  std::string out(severityName(severity));
  out += ' ';
  out += code;
  if (!section.empty()) out += " [" + section + "]";
  out += ": ";
  out += message;
  return out;
}

void DiagnosticList::report(std::string_view code, std::vector<std::string> targets, std::string message,
                            const DiagnosticSite& site) {
  const CatalogueEntry* entry = findCatalogueEntry(code);
  if (!entry) throw std::logic_error("platform diagnostic code not in the catalogue: " + std::string(code));
  Diagnostic d;
  d.code = std::string(code);
  d.severity = entry->severity;
  d.message = std::move(message);
  d.targets = std::move(targets);
  d.section = std::string(entry->section);
  d.pass = site.pass;
  d.pipeline = site.pipeline;
  d.count = site.count;
  items_.push_back(std::move(d));
}

void DiagnosticList::locate(std::size_t from, const DiagnosticSite& site) {
  for (std::size_t i = from; i < items_.size(); ++i) {
    if (items_[i].pass.empty()) items_[i].pass = site.pass;
    if (items_[i].pipeline.empty()) items_[i].pipeline = site.pipeline;
  }
}

bool DiagnosticList::has(std::string_view code) const { return first(code) != nullptr; }

std::size_t DiagnosticList::count(std::string_view code) const {
  return static_cast<std::size_t>(
      std::count_if(items_.begin(), items_.end(), [&](const Diagnostic& d) { return d.code == code; }));
}

const Diagnostic* DiagnosticList::first(std::string_view code) const {
  for (const Diagnostic& d : items_)
    if (d.code == code) return &d;
  return nullptr;
}

bool DiagnosticList::hasErrors() const {
  return std::any_of(items_.begin(), items_.end(), [](const Diagnostic& d) { return d.severity == Severity::Error; });
}

void DiagnosticList::append(const DiagnosticList& other) {
  items_.insert(items_.end(), other.items_.begin(), other.items_.end());
}

std::string DiagnosticList::format() const {
  std::string out;
  for (const Diagnostic& d : items_) {
    out += d.format();
    out += '\n';
  }
  return out;
}

}  // namespace parity::platforms
