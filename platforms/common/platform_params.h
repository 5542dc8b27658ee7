// Named parameters of the platform models.
//
// The reference pack (console-quirks.md, "Open questions and uncertainties") lists behaviour that
// no public source settles: the hardware rule for signed k_16_16 resolves, the Xenos 4x sample
// order and positions, the 64-bpp EDRAM tile layout, the exact texDepth2D_precise definition and
// the D3DRS_HALFPIXELOFFSET -> PIX_CENTER mapping. Each of those is a parameter here, defaulting
// to the pack's recommendation, so a test or `parity explain` can name the assumption it runs
// under and flip it. A few further choices the pack documents as emulator divergences or
// inferences (unpack clamp, MRT rule, ...) are parameters as well.
//
// The CPU models in platforms/<platform>/ read these values; the GPU path must read the same
// ones so that both are compared under the same assumption.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace parity::platforms {

// --- Xbox 360 -------------------------------------------------------------------------------

// X3, open question 1: what a resolve writes when the source is k_16_16 / k_16_16_16_16 and the
// destination is k_16_16 with copy_dest_number = signed.
enum class SignedK16Resolve : uint8_t {
  // Pack recommendation: the raw int16 is kept (a bit copy when there is no averaging and no
  // exponent bias; otherwise the EDRAM-style re-encode below). The paper's path C needs this.
  PreserveRawInt16 = 0,
  // xenia-canary PR #898: always re-encode as EDRAM-style fixed point (x 32767/32, clamp +-32).
  ReencodeEdramStyle,
  // Mainline Xenia: copy_dest_number is ignored, the destination is always packed UNORM.
  UnsignedSaturate,
};

// X1, open question 2: where 4x MSAA samples sit inside a pixel's 2x2 sample block.
enum class Msaa4xSampleOrder : uint8_t {
  XeniaMainline = 0,  // (s0,s1,s2,s3) = (0,0),(0,1),(1,0),(1,1) in (x,y) sample units
  CanaryCanonical,    // xenia-canary PR #1163, the 360's (0, 2, 1, 3) permutation
};

// X1, open question 2: sub-sample positions (unknown on hardware).
enum class MsaaSamplePositions : uint8_t {
  D3D10_1Standard = 0,  // Xenia's assumption, in 1/16 px: 2x {(4,4),(-4,-4)}; 4x {(-2,-6),(6,-2),(-6,2),(2,6)}
};

// X1, open question 3: how a 64-bpp surface is laid out in a tile.
enum class Edram64bppTileLayout : uint8_t {
  Xenia40x16 = 0,  // Xenia's assumption: 40x16 samples of 8 bytes per 5120-byte tile
};

// X5, open question 5: what D3DRS_HALFPIXELOFFSET sets in PA_SU_VTX_CNTL.PIX_CENTER.
enum class HalfPixelOffsetMapping : uint8_t {
  TrueMeansPixCenterHalf = 0,  // inferred from three consistent sources: TRUE -> kOGLHalf (1)
  TrueMeansPixCenterZero,      // the opposite, for sensitivity tests
};

// X2/X3 range notes: the lower clamp a resolve applies when it unpacks a k_16_16 sample.
enum class K16UnpackClamp : uint8_t {
  Minus32 = 0,  // xenia-canary PR #898 and the pack's model: max(s*32/32767, -32)
  Minus1,       // mainline Xenia: max(s*32/32767, -1) (a known divergence)
};

// X3: which write/resolve/sample path the x360 layer uses for a logical two-channel 16-bit
// unorm target (the DSF buffer).
enum class DsfResolvePath : uint8_t {
  PaperSignedC = 0,  // path C: c = 64v - 32, signed resolve, signed k_16_16 fetch, (t+1)/2 (16 bits)
  XdkBiasB,          // path B: color_exp_bias +5, resolve exponent bias -5, unsigned k_16_16 (15 bits)
  NaiveA,            // path A: no bias, unsigned k_16_16 (about 10 bits)
};

// X2: the format of an x360 Rgba16Hdr target (light accumulation): Xenos has two HDR colour
// render-target formats.
enum class X360HdrFormat : uint8_t {
  Fixed16x4 = 0,  // k_16_16_16_16: signed fixed point -32...32, 64 bpp
  Float7e3,       // k_2_10_10_10_FLOAT: 7e3 RGB over [0, 31.875] (8 significant bits), 2-bit alpha, 32 bpp
};

// --- PS3 ------------------------------------------------------------------------------------

// P4, open question 4: what texDepth2D_precise computes from the remapped ARGB8 depth texel.
enum class TexDepth2DPrecise : uint8_t {
  // Round each byte (floor(255 c + 0.5)) and return D24 / 16777215, correctly rounded to fp32
  // (the hand-written decode and the RAWZ constants in the pack).
  ExactD24Over16777215 = 0,
  // The Cg re-implementation's DP3 with _depth_factor_precise = (0x3b800001, 0x37800001,
  // 0x33800001) on the integer bytes, evaluated in fp32. Within 1 ULP of the above.
  Fp32PreciseFactorsDp3,
};

// P1: which MRT rule the PS3 layer enforces.
enum class Ps3MrtRule : uint8_t {
  SameFormat = 0,  // inferred from the single colour-format field of SET_SURFACE_FORMAT
  SameBpp,         // the paper's wording and D3D9's generic rule
};

struct PlatformParams {
  // x360
  SignedK16Resolve signedK16Resolve = SignedK16Resolve::PreserveRawInt16;
  Msaa4xSampleOrder msaa4xSampleOrder = Msaa4xSampleOrder::XeniaMainline;
  MsaaSamplePositions msaaSamplePositions = MsaaSamplePositions::D3D10_1Standard;
  Edram64bppTileLayout edram64bppTileLayout = Edram64bppTileLayout::Xenia40x16;
  HalfPixelOffsetMapping halfPixelOffsetMapping = HalfPixelOffsetMapping::TrueMeansPixCenterHalf;
  bool halfPixelOffset = false;  // D3DRS_HALFPIXELOFFSET for screen-space passes; FALSE is the D3D default
  K16UnpackClamp k16UnpackClamp = K16UnpackClamp::Minus32;
  DsfResolvePath dsfResolvePath = DsfResolvePath::PaperSignedC;
  X360HdrFormat hdrFormat = X360HdrFormat::Fixed16x4;
  // ps3
  TexDepth2DPrecise texDepth2DPrecise = TexDepth2DPrecise::ExactD24Over16777215;
  Ps3MrtRule ps3MrtRule = Ps3MrtRule::SameFormat;
};

// Description of one parameter, for `parity explain`.
struct ParamInfo {
  std::string_view name;          // "x360.signed_k16_resolve"
  std::string_view section;       // pack section: "X3", ...
  int openQuestion;               // number in the pack's open-question list, 0 if not one
  std::string_view defaultValue;  // value name of the default
  std::string_view values;        // all value names, "|"-separated
  std::string_view explanation;   // one line
  // Its field of PlatformParams, read and written as the index of its value in `values`.
  int (*valueOf)(const PlatformParams&);
  void (*setValue)(PlatformParams&, int);
};

std::span<const ParamInfo> parameterCatalogue();
const ParamInfo* findParameter(std::string_view name);

// The value name a parameter has in `params` ("" for an unknown name).
std::string parameterValue(const PlatformParams& params, std::string_view name);
// Sets a parameter by names; false (and *error filled) for an unknown name or value.
bool setParameter(PlatformParams& params, std::string_view name, std::string_view value, std::string* error);
// "name = value" lines for every parameter, "(default)" marked.
std::string describeParameters(const PlatformParams& params);

}  // namespace parity::platforms
