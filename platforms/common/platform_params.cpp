#include "platforms/common/platform_params.h"

#include <algorithm>
#include <array>
#include <type_traits>
#include <vector>

namespace parity::platforms {

namespace {

// The catalogue row of the PlatformParams field `Field`, whose value is the index of its name in
// `values` (the enumerator, or false/true).
template <auto Field>
constexpr ParamInfo param(std::string_view name, std::string_view section, int openQuestion,
                          std::string_view defaultValue, std::string_view values, std::string_view explanation) {
  using Value = std::remove_reference_t<decltype(PlatformParams{}.*Field)>;
  return {name, section, openQuestion, defaultValue, values, explanation,
          [](const PlatformParams& p) { return int(p.*Field); },
          [](PlatformParams& p, int index) { p.*Field = Value(index); }};
}

constexpr std::array kParams = {
    param<&PlatformParams::signedK16Resolve>(
        "x360.signed_k16_resolve", "X3", 1, "preserve-raw-int16",
        "preserve-raw-int16|reencode-edram-style|unsigned-saturate",
        "k_16_16 resolve into a signed (copy_dest_number=1) k_16_16 destination: keep the raw int16 (pack "
        "recommendation; path C needs it), re-encode x32767/32 clamped to +-32 (xenia-canary #898), or ignore the "
        "sign and pack UNORM (mainline Xenia)"),
    param<&PlatformParams::msaa4xSampleOrder>(
        "x360.msaa4x_sample_order", "X1", 2, "xenia-mainline", "xenia-mainline|canary-canonical",
        "4x MSAA sample placement in EDRAM: mainline Xenia (s0..s3 = (0,0),(0,1),(1,0),(1,1)) or xenia-canary "
        "#1163's canonical (0,2,1,3) layout; hardware placement is unsettled"),
    param<&PlatformParams::msaaSamplePositions>(
        "x360.msaa_sample_positions", "X1", 2, "d3d10.1-standard", "d3d10.1-standard",
        "sub-sample positions are unknown on hardware; Xenia assumes the D3D10.1 standard positions"),
    param<&PlatformParams::edram64bppTileLayout>(
        "x360.edram_64bpp_tile_layout", "X1", 3, "xenia-40x16", "xenia-40x16",
        "64-bpp surfaces hold 40x16 samples of 8 bytes per tile: Xenia's own assumption, storage of 64bpp relative "
        "to 32bpp is not known"),
    param<&PlatformParams::halfPixelOffsetMapping>(
        "x360.halfpixeloffset_mapping", "X5", 5, "true-is-pix-center-half",
        "true-is-pix-center-half|true-is-pix-center-zero",
        "D3DRS_HALFPIXELOFFSET=TRUE sets PA_SU_VTX_CNTL.PIX_CENTER=1 (D3D10/GL centres); inferred from sample "
        "comments and emulator naming, no official document"),
    param<&PlatformParams::halfPixelOffset>(
        "x360.halfpixeloffset", "X5", 0, "false", "false|true",
        "D3DRS_HALFPIXELOFFSET for screen-space passes; FALSE (the D3D default) keeps D3D9 pixel centres at integer "
        "positions"),
    param<&PlatformParams::k16UnpackClamp>(
        "x360.k16_unpack_clamp", "X2", 0, "-32", "-32|-1",
        "lower clamp when a resolve unpacks a k_16_16 sample: -32 (xenia-canary #898, the model) or -1 (mainline "
        "Xenia, a known divergence)"),
    param<&PlatformParams::dsfResolvePath>(
        "x360.dsf_resolve_path", "X3", 0, "paper-signed-c", "paper-signed-c|xdk-bias-b|naive-a",
        "write/resolve/sample path for two-channel 16-bit unorm targets: C (paper, signed custom format, 16 bits), B "
        "(XDK +5/-5 idiom, 15 bits), A (naive, about 10 bits)"),
    param<&PlatformParams::hdrFormat>(
        "x360.hdr_format", "X2", 0, "k_16_16_16_16", "k_16_16_16_16|k_2_10_10_10_float",
        "the render-target format of HDR light buffers (Rgba16Hdr): k_16_16_16_16 (fixed point -32...32, 64 bpp) or "
        "k_2_10_10_10_FLOAT (7e3: [0, 31.875], 8 significant bits, 2-bit alpha, 32 bpp: half the EDRAM)"),
    param<&PlatformParams::texDepth2DPrecise>(
        "ps3.texdepth2d_precise", "P4", 4, "exact-d24-over-16777215",
        "exact-d24-over-16777215|fp32-precise-factors-dp3",
        "texDepth2D_precise: round each byte and return D24/16777215 (pack decode), or the fp32 DP3 with "
        "_depth_factor_precise; SDK definition not public, compare with 1 ULP tolerance"),
    param<&PlatformParams::ps3MrtRule>(
        "ps3.mrt_rule", "P1", 0, "same-format", "same-format|same-bpp",
        "MRT targets must share one format (SET_SURFACE_FORMAT has one colour field) or only the same bits per pixel "
        "(the paper's and D3D9's rule)"),
};

// The value names of `p`, "|"-separated in its catalogue row, in index order.
std::vector<std::string_view> valueNames(const ParamInfo& p) {
  std::vector<std::string_view> names;
  for (std::string_view rest = p.values;;) {
    const std::size_t bar = rest.find('|');
    names.push_back(rest.substr(0, bar));
    if (bar == std::string_view::npos) return names;
    rest.remove_prefix(bar + 1);
  }
}

}  // namespace

std::span<const ParamInfo> parameterCatalogue() { return kParams; }

const ParamInfo* findParameter(std::string_view name) {
  for (const ParamInfo& p : kParams)
    if (p.name == name) return &p;
  return nullptr;
}

std::string parameterValue(const PlatformParams& params, std::string_view name) {
  const ParamInfo* p = findParameter(name);
  return p ? std::string(valueNames(*p).at(std::size_t(p->valueOf(params)))) : std::string();
}

bool setParameter(PlatformParams& params, std::string_view name, std::string_view value, std::string* error) {
  const ParamInfo* p = findParameter(name);
  if (!p) {
    if (error) *error = "unknown platform parameter '" + std::string(name) + "'";
    return false;
  }
  const std::vector<std::string_view> names = valueNames(*p);
  const auto it = std::find(names.begin(), names.end(), value);
  if (it == names.end()) {
    if (error)
      *error = "unknown value '" + std::string(value) + "' for " + std::string(name) + " (one of " +
               std::string(p->values) + ")";
    return false;
  }
  p->setValue(params, int(it - names.begin()));
  return true;
}

std::string describeParameters(const PlatformParams& params) {
  std::string out;
  for (const ParamInfo& info : kParams) {
    std::string value = parameterValue(params, info.name);
    out += std::string(info.name) + " = " + value;
    if (value == info.defaultValue) out += " (default)";
    if (info.openQuestion) out += " [open question " + std::to_string(info.openQuestion) + "]";
    out += " - " + std::string(info.explanation) + "\n";
  }
  return out;
}

}  // namespace parity::platforms
