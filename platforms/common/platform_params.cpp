#include "platforms/common/platform_params.h"

#include <array>

namespace parity::platforms {

namespace {

constexpr std::array kParams = {
    ParamInfo{"x360.signed_k16_resolve", "X3", 1, "preserve-raw-int16",
              "preserve-raw-int16|reencode-edram-style|unsigned-saturate",
              "k_16_16 resolve into a signed (copy_dest_number=1) k_16_16 destination: keep the raw int16 "
              "(pack recommendation; path C needs it), re-encode x32767/32 clamped to +-32 (xenia-canary "
              "#898), or ignore the sign and pack UNORM (mainline Xenia)"},
    ParamInfo{"x360.msaa4x_sample_order", "X1", 2, "xenia-mainline", "xenia-mainline|canary-canonical",
              "4x MSAA sample placement in EDRAM: mainline Xenia (s0..s3 = (0,0),(0,1),(1,0),(1,1)) or "
              "xenia-canary #1163's canonical (0,2,1,3) layout; hardware placement is unsettled"},
    ParamInfo{"x360.msaa_sample_positions", "X1", 2, "d3d10.1-standard", "d3d10.1-standard",
              "sub-sample positions are unknown on hardware; Xenia assumes the D3D10.1 standard positions"},
    ParamInfo{"x360.edram_64bpp_tile_layout", "X1", 3, "xenia-40x16", "xenia-40x16",
              "64-bpp surfaces hold 40x16 samples of 8 bytes per tile: Xenia's own assumption, storage of "
              "64bpp relative to 32bpp is not known"},
    ParamInfo{"x360.halfpixeloffset_mapping", "X5", 5, "true-is-pix-center-half",
              "true-is-pix-center-half|true-is-pix-center-zero",
              "D3DRS_HALFPIXELOFFSET=TRUE sets PA_SU_VTX_CNTL.PIX_CENTER=1 (D3D10/GL centres); inferred from "
              "sample comments and emulator naming, no official document"},
    ParamInfo{"x360.halfpixeloffset", "X5", 0, "false", "false|true",
              "D3DRS_HALFPIXELOFFSET for screen-space passes; FALSE (the D3D default) keeps D3D9 pixel "
              "centres at integer positions"},
    ParamInfo{"x360.k16_unpack_clamp", "X2", 0, "-32", "-32|-1",
              "lower clamp when a resolve unpacks a k_16_16 sample: -32 (xenia-canary #898, the model) or -1 "
              "(mainline Xenia, a known divergence)"},
    ParamInfo{"x360.dsf_resolve_path", "X3", 0, "paper-signed-c", "paper-signed-c|xdk-bias-b|naive-a",
              "write/resolve/sample path for two-channel 16-bit unorm targets: C (paper, signed custom "
              "format, 16 bits), B (XDK +5/-5 idiom, 15 bits), A (naive, about 10 bits)"},
    ParamInfo{"x360.hdr_format", "X2", 0, "k_16_16_16_16", "k_16_16_16_16|k_2_10_10_10_float",
              "the render-target format of HDR light buffers (Rgba16Hdr): k_16_16_16_16 (fixed point "
              "-32...32, 64 bpp) or k_2_10_10_10_FLOAT (7e3: [0, 31.875], 8 significant bits, 2-bit alpha, "
              "32 bpp: half the EDRAM)"},
    ParamInfo{"ps3.texdepth2d_precise", "P4", 4, "exact-d24-over-16777215",
              "exact-d24-over-16777215|fp32-precise-factors-dp3",
              "texDepth2D_precise: round each byte and return D24/16777215 (pack decode), or the fp32 DP3 with "
              "_depth_factor_precise; SDK definition not public, compare with 1 ULP tolerance"},
    ParamInfo{"ps3.mrt_rule", "P1", 0, "same-format", "same-format|same-bpp",
              "MRT targets must share one format (SET_SURFACE_FORMAT has one colour field) or only the same "
              "bits per pixel (the paper's and D3D9's rule)"},
};

template <class Enum, std::size_t N>
bool parseEnum(std::string_view value, const std::array<std::string_view, N>& names, Enum* out) {
  for (std::size_t i = 0; i < N; ++i) {
    if (names[i] == value) {
      *out = static_cast<Enum>(i);
      return true;
    }
  }
  return false;
}

constexpr std::array<std::string_view, 3> kSignedK16 = {"preserve-raw-int16", "reencode-edram-style",
                                                        "unsigned-saturate"};
constexpr std::array<std::string_view, 2> kOrder = {"xenia-mainline", "canary-canonical"};
constexpr std::array<std::string_view, 1> kPositions = {"d3d10.1-standard"};
constexpr std::array<std::string_view, 1> kLayout64 = {"xenia-40x16"};
constexpr std::array<std::string_view, 2> kHalfPixel = {"true-is-pix-center-half", "true-is-pix-center-zero"};
constexpr std::array<std::string_view, 2> kBool = {"false", "true"};
constexpr std::array<std::string_view, 2> kClamp = {"-32", "-1"};
constexpr std::array<std::string_view, 3> kDsf = {"paper-signed-c", "xdk-bias-b", "naive-a"};
constexpr std::array<std::string_view, 2> kHdr = {"k_16_16_16_16", "k_2_10_10_10_float"};
constexpr std::array<std::string_view, 2> kDepth = {"exact-d24-over-16777215", "fp32-precise-factors-dp3"};
constexpr std::array<std::string_view, 2> kMrt = {"same-format", "same-bpp"};

}  // namespace

std::span<const ParamInfo> parameterCatalogue() { return kParams; }

const ParamInfo* findParameter(std::string_view name) {
  for (const ParamInfo& p : kParams)
    if (p.name == name) return &p;
  return nullptr;
}

std::string parameterValue(const PlatformParams& p, std::string_view name) {
  auto at = [](const auto& names, auto value) { return std::string(names[static_cast<std::size_t>(value)]); };
  if (name == "x360.signed_k16_resolve") return at(kSignedK16, p.signedK16Resolve);
  if (name == "x360.msaa4x_sample_order") return at(kOrder, p.msaa4xSampleOrder);
  if (name == "x360.msaa_sample_positions") return at(kPositions, p.msaaSamplePositions);
  if (name == "x360.edram_64bpp_tile_layout") return at(kLayout64, p.edram64bppTileLayout);
  if (name == "x360.halfpixeloffset_mapping") return at(kHalfPixel, p.halfPixelOffsetMapping);
  if (name == "x360.halfpixeloffset") return at(kBool, p.halfPixelOffset ? 1 : 0);
  if (name == "x360.k16_unpack_clamp") return at(kClamp, p.k16UnpackClamp);
  if (name == "x360.dsf_resolve_path") return at(kDsf, p.dsfResolvePath);
  if (name == "x360.hdr_format") return at(kHdr, p.hdrFormat);
  if (name == "ps3.texdepth2d_precise") return at(kDepth, p.texDepth2DPrecise);
  if (name == "ps3.mrt_rule") return at(kMrt, p.ps3MrtRule);
  return {};
}

bool setParameter(PlatformParams& p, std::string_view name, std::string_view value, std::string* error) {
  bool ok = false;
  bool known = true;
  if (name == "x360.signed_k16_resolve") ok = parseEnum(value, kSignedK16, &p.signedK16Resolve);
  else if (name == "x360.msaa4x_sample_order") ok = parseEnum(value, kOrder, &p.msaa4xSampleOrder);
  else if (name == "x360.msaa_sample_positions") ok = parseEnum(value, kPositions, &p.msaaSamplePositions);
  else if (name == "x360.edram_64bpp_tile_layout") ok = parseEnum(value, kLayout64, &p.edram64bppTileLayout);
  else if (name == "x360.halfpixeloffset_mapping") ok = parseEnum(value, kHalfPixel, &p.halfPixelOffsetMapping);
  else if (name == "x360.halfpixeloffset") {
    int v = 0;
    ok = parseEnum(value, kBool, &v);
    if (ok) p.halfPixelOffset = v != 0;
  } else if (name == "x360.k16_unpack_clamp") ok = parseEnum(value, kClamp, &p.k16UnpackClamp);
  else if (name == "x360.dsf_resolve_path") ok = parseEnum(value, kDsf, &p.dsfResolvePath);
  else if (name == "x360.hdr_format") ok = parseEnum(value, kHdr, &p.hdrFormat);
  else if (name == "ps3.texdepth2d_precise") ok = parseEnum(value, kDepth, &p.texDepth2DPrecise);
  else if (name == "ps3.mrt_rule") ok = parseEnum(value, kMrt, &p.ps3MrtRule);
  else known = false;
  if (!ok && error) {
    if (!known) {
      *error = "unknown platform parameter '" + std::string(name) + "'";
    } else {
      *error = "unknown value '" + std::string(value) + "' for " + std::string(name) + " (one of " +
               std::string(findParameter(name)->values) + ")";
    }
  }
  return ok;
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
