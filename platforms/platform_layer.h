// The platform layer between a technique and the RHI.
//
// A technique asks for LOGICAL targets ("two 16-bit unorm channels", "scene depth, readable
// later", "HDR light accumulation") and never learns which platform it runs on. The platform
// answers with a TargetPlan: the real RHI formats it allocates (and the views it reads them
// through), what a resolve does, the effective precision of each path, the EDRAM placement on
// x360, the diagnostics that fire, and the shader defines that select the platform's GLSL
// snippets (shaders/platforms/platform.glsl -> shaders/platforms/<platform>/targets.glsl).
//
// Shader contract (every platform's targets.glsl provides the same names):
//   vec4  parityWriteRg16(vec2 v)                  colour output for a Rg16Unorm target
//   PARITY_RG16_SAMPLER                            sampler type of the texture readTexture() gives
//   vec2  parityReadRg16(vec4 texel)               texelFetch/texture result -> logical value
//   PARITY_DEPTH_SAMPLER, PARITY_DEPTH_TEXEL       sampler and texel type of the depth read texture
//   PARITY_DEPTH_ARRAY_SAMPLER                     the same for a layered depth target (arrayLayers)
//   float parityReadDepth(PARITY_DEPTH_TEXEL t)    -> depth in [0, 1] as the platform reads it
//   vec4  parityWriteRgba16Hdr(vec4 v)             colour output for a Rgba16Hdr target (additive
//                                                  blending must stay correct: linear scaling only)
//   vec4  parityReadRgba16Hdr(vec4 texel)          its read texture's texel -> logical value
//   PARITY_RG16_BITS_TYPE                          fragment output type for GpuTargets::writeTarget()
//                                                  of a Rg16Unorm target (PhysicalTarget::writeFormat)
//   PARITY_RG16_BITS_TYPE parityWriteRg16Bits(vec2 v)  the stored words themselves, rounded in the
//                                                  shader as the CPU model rounds
//   PARITY_SAMPLES_SAMPLER, parityFetchSample(t, ivec2 p, int s)  sampler type of readTexture() of
//                                                  a target with readSamples, and sample s's texel
//                                                  (then read as the target's format is read)
// Depth is written by the depth test as usual; Rgba8Unorm targets are written and read directly.
//
// Two ways to write a Rg16Unorm target:
//  * parityWriteRg16Bits into writeTarget() (an integer view: RG16_UINT on dx10, ps3 and x360).
//    The shader computes every stored bit, so no driver float -> unorm/snorm conversion decides
//    them: bit-identical to the model on every conformant driver. Integer views cannot blend, so
//    this is the path for opaque writes (G-buffers, DSF data).
//  * parityWriteRg16 into attachment() (the float-typed attachment), for draws that blend. The
//    value is already quantised in the shader and offset by a quarter step (k + 0.25) / N, so
//    that round-to-nearest, round-half-even and truncating conversions, and any conversion
//    within the 0.6-ULP tolerance D3D10+ allows, all store k (NVIDIA truncates 16-bit unorm
//    conversions: 0.001 -> 65 where the model rounds to 66). Blended results are the
//    blend unit's own and only as exact as it is.
//
// GpuTargets allocates a plan's textures on a device, records the platform's resolve / copy
// passes (x360 EDRAM resolves, the DX10 copy of depth to R24X8, the PS3 bitcast of depth to
// ARGB8) and exports any emulated surface as the bytes the console would hold in memory.
// The CPU models in platforms/<platform>/ are the single source of truth the GPU path is tested
// against (tests/platform_gpu_test.cpp).
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "platforms/common/diagnostics.h"
#include "platforms/common/platform.h"
#include "platforms/common/platform_params.h"
#include "platforms/common/target_table.h"
#include "platforms/texel_counters.h"
#include "rhi/rhi.h"
#include "rhi/shader_compiler.h"

namespace parity::platforms {

// What the inferred-lighting rules (X4) need to know about a target.
enum class TargetRole : uint8_t { Plain = 0, GBuffer, LBuffer };

// A logical target as a technique asks for it.
struct LogicalTarget {
  std::string name;
  LogicalFormat format = LogicalFormat::Rgba8Unorm;
  bool readLater = true;  // a later pass samples it (it needs a read path / resolve)
  TargetRole role = TargetRole::Plain;
  std::string pass;       // the pass that renders it; targets with the same pass are bound together
  // Samples per pixel: 1, or 4 for MSAA (the counts the RHI offers). Every platform plans them;
  // a readLater target resolves by averaging the samples (x360: copy_sample_select k0123 of the
  // EDRAM surface, sized and placed for 4x; elsewhere the host's MSAA resolve).
  uint32_t samples = 1;
  // Depth24Stencil8: the technique uses the stencil. Every console keeps D24S8; the reference,
  // whose depth is D32F, then plans D24S8 too (the RHI has no D32F + S8 format).
  bool stencil = false;
  // LogicalFormat::Output: the host format of the image the harness reads (RenderSettings::colorFormat).
  rhi::Format outputFormat = rhi::Format::RGBA8;
  // 0: a 2D texture. N: a 2D array of N layers, each rendered on its own (a shadow map's cube
  // faces) and resolved layer by layer into an array read texture; depth targets only. The
  // console places and resolves one layer at a time, so EDRAM holds one layer.
  uint32_t arrayLayers = 0;
  // The passes during which the target's contents are live: those that bind it and those its
  // contents must survive (e.g. the depth a light pass tests against after the geometry pass).
  // Empty: live in `pass` only, placed after the targets listed before it. When set, x360 checks
  // it against every target live in one of these passes (X1) and may place it in the EDRAM tiles
  // of targets it is never live with, e.g. an L-buffer in resolved G-buffer colour tiles (X4).
  std::vector<std::string> livePasses;
  // A multisampled target a later pass reads sample by sample (PARITY_SAMPLES_SAMPLER,
  // parityFetchSample) instead of through an averaging resolve. Hosts read the samples in place;
  // x360, whose shaders cannot reach EDRAM, resolves each sample on its own (copy_sample_select
  // k0..k3, a point copy) into the layers of an array texture.
  bool readSamples = false;
};

// How a resolve (or the platform's equivalent copy) moves a target to its read texture.
struct ResolveSpec {
  bool needed = false;
  std::string description;  // e.g. "x360 resolve path C: signed k_16_16, raw int16 kept"
  double effectiveBits = 0;  // of the whole write -> resolve -> read path, for the logical range
};

// What the platform really allocates for one logical target.
struct PhysicalTarget {
  LogicalTarget logical;
  TargetMapping mapping;                               // console format, write and read rules
  rhi::Format attachmentFormat = rhi::Format::Undefined;  // the texture rendered to
  rhi::Format rawViewFormat = rhi::Format::Undefined;     // bit view of the attachment (x360: RG16_UINT)
  rhi::Format readFormat = rhi::Format::Undefined;        // the texture sampled later
  rhi::Format readViewFormat = rhi::Format::Undefined;    // view of it that shaders sample (Undefined: itself)
  // Format of GpuTargets::writeTarget(): the integer view exact writes render into
  // (parityWriteRg16Bits); equal to attachmentFormat when the target has none.
  rhi::Format writeFormat = rhi::Format::Undefined;
  ResolveSpec resolve;
  // Samples of the attachment (1 unless the platform plans MSAA; see LogicalTarget::samples).
  uint32_t samples = 1;
  // x360: EDRAM placement.
  bool inEdram = false;
  uint32_t edramBase = 0, edramTiles = 0;
};

struct TargetPlan {
  PlatformId platform = PlatformId::Reference;
  PlatformParams params;
  uint32_t width = 0, height = 0;
  // X5: the pixel-centre offset the platform device adds to every viewport (hostPixelCenterOffset:
  // 0.5 on x360 at D3D9 centres, else 0). A screen-space pass that samples coordinates
  // interpolated from its vertices sets its viewport origin to -pixelCenterOffset, as a D3D9
  // port offsets its quad by -0.5, and samples texel centres (W_D3D9_PIXEL_CENTER otherwise).
  float pixelCenterOffset = 0;
  std::vector<PhysicalTarget> targets;
  DiagnosticList diagnostics;
  std::vector<std::pair<std::string, std::string>> shaderDefines;
  const PhysicalTarget* find(const std::string& name) const;
};

// Decides formats, resolves, placements, diagnostics and shader defines for `targets`.
TargetPlan planTargets(PlatformId platform, std::span<const LogicalTarget> targets, uint32_t width, uint32_t height,
                       const PlatformParams& params = {});

// Compile options for a technique shader that includes "platform.glsl": the platform's defines
// and shaders/platforms as include folder.
rhi::ShaderCompileOptions platformShaderOptions(const TargetPlan& plan);
std::string platformShaderDirectory();  // <shaderDirectory()>/platforms

// Effective bits of each platform's Rg16Unorm path and depth read, as its target table states them
// (x360's DSF path: the CPU model of the path's precision).
double rg16EffectiveBits(PlatformId platform, const PlatformParams& params = {});
double depthEffectiveBits(PlatformId platform);

// X5: what a screen-space pass adds to its viewport origin, in pixels, so that the host's .5
// pixel centres sample where the console does: +0.5 on x360 when D3DRS_HALFPIXELOFFSET leaves
// PIX_CENTER at kD3DZero (the D3D9 convention; Xenia's and DXVK's viewport shift), 0 where
// centres are at .5 already (x360 with HALFPIXELOFFSET, DX10, PS3, reference).
float hostPixelCenterOffset(PlatformId platform, const PlatformParams& params = {});

// Fills t's mapping, formats and resolve from `row` (a resolve only when t.logical.readLater). An
// Output target is held in the format the harness reads (LogicalTarget::outputFormat): the
// console's display surface is 8-bit on every platform, the host keeps the unquantised image.
void applyTargetRow(const TargetRow& row, PhysicalTarget& t);

// Per-platform pieces (each implemented in the platform's folder: <platform>/<platform>_layer.cpp).
// planTarget applies the row of the platform's target table for t.logical (TargetRow) and what
// the parameters add.
namespace reference {
void planTarget(PhysicalTarget& t, const PlatformParams& params);
void shaderDefines(const PlatformParams& params, std::vector<std::pair<std::string, std::string>>& out);
}  // namespace reference
namespace dx10 {
void planTarget(PhysicalTarget& t, const PlatformParams& params);
void shaderDefines(const PlatformParams& params, std::vector<std::pair<std::string, std::string>>& out);
}  // namespace dx10
namespace ps3 {
void planTarget(PhysicalTarget& t, const PlatformParams& params);
void shaderDefines(const PlatformParams& params, std::vector<std::pair<std::string, std::string>>& out);
}  // namespace ps3
namespace x360 {
void planTarget(PhysicalTarget& t, const PlatformParams& params);
void shaderDefines(const PlatformParams& params, std::vector<std::pair<std::string, std::string>>& out);
// EDRAM placement (X1, X4), resolve precision and the rules of each whole-surface resolve (X3)
void checkPlan(TargetPlan& plan);
}  // namespace x360

// ---------------------------------------------------------------------------------------------
// GPU side
// ---------------------------------------------------------------------------------------------
class PlatformDevice;  // platforms/platform_device.h

class GpuTargets {
 public:
  // Creates every target of `plan` on `device` (attachment, views, read texture). `error` is
  // filled when a shader of the platform's resolve passes does not compile. Its own passes go
  // to hostDevice(device): resolves and copies are not the technique's draws (platform_device.h).
  // On a PlatformDevice the plan's diagnostics (those of its resolves included) go to its list.
  GpuTargets(rhi::Device& device, const TargetPlan& plan);
  ~GpuTargets();
  GpuTargets(const GpuTargets&) = delete;
  GpuTargets& operator=(const GpuTargets&) = delete;

  const TargetPlan& plan() const { return plan_; }
  // Render into this (colour or depth-stencil attachment).
  rhi::TextureHandle attachment(const std::string& name) const;
  // Render exact words into this (format PhysicalTarget::writeFormat; parityWriteRg16Bits). Same
  // memory as attachment(); the attachment itself when the target has no integer write view.
  rhi::TextureHandle writeTarget(const std::string& name) const;
  // Sample this after resolve() (bind it as PARITY_RG16_SAMPLER / PARITY_DEPTH_SAMPLER).
  rhi::TextureHandle readTexture(const std::string& name) const;
  // The clear colour of attachment(name) that stores the logical value `v`, as a draw writing v
  // would: on x360 a Rgba16Hdr surface holds the X2 encode of v (s * 2^-15). Identity for the
  // other platforms and formats (Rg16Unorm clears are not translated yet: clear those to 0,
  // which no pass reads back).
  std::array<float, 4> clearColor(const std::string& name, const std::array<float, 4>& v) const;
  // Records the platform's resolve / copy pass for `name` (nothing when the plan needs none).
  // `sourceSamples` > 1 resolves an x360 surface whose rows hold Xenos 2x samples (sample s of
  // pixel (x, y) at row 2y + s, X1) with averaging (copy_sample_select k01). An x360 target
  // planned with 4 samples (k_16_16 or k_16_16_16_16) resolves with averaging of all four
  // (k0123, X3), reading the MSAA attachment's samples in guest order; its other formats have
  // no GPU resolve yet (false, error() says so).
  // `rect` (width and height > 0): on x360 only that rectangle of the surface is resolved, into
  // the same place of the texture (X3: its origin and size must be multiples of 8,
  // E_RESOLVE_ALIGNMENT); elsewhere the whole target is copied. Without it x360 resolves the
  // whole surface as the port allocates it, padded to the resolve granularity (wholeSurfaceResolve).
  bool resolve(const std::string& name, uint32_t sourceSamples = 1, const rhi::Rect& rect = {});
  // x360 k_16_16_16_16 (Rgba16Hdr): stores the surface's values as the render backend does after
  // every write and blend (X2): clamped to the fixed-point range [0x8001, 0x7FFF], NaN as 0. The
  // shaders write the rounded fixed-point steps unclamped (parityWriteRgba16Hdr) and the float
  // host surface does not saturate, so call it after each pass that draws into the target; a
  // PlatformDevice does so by itself, and counts the samples it changes (W_FIXED16_RANGE_CLAMP,
  // W_FIXED16_NAN, naming the pass). Per pass, not per blend: exact when the draws of a pass add
  // values of one sign (the running sum is then monotone, so clamping once at the end stores what
  // clamping after each blend does), which holds for light accumulation. Nothing on other targets.
  void clampFixedPoint(const std::string& name);
  // x360 k_2_10_10_10_FLOAT (Rgba16Hdr under x360.hdr_format = k_2_10_10_10_float): rounds the
  // stored values to 7e3, as the render backend stores every write and blend (X2); the shaders
  // write floats. Call it after each pass that writes the target; a PlatformDevice does so, and
  // counts the samples outside 7e3's range (W_FLOAT7E3_RANGE_CLAMP).
  void quantiseFloat7e3(const std::string& name);
  // Reads the emulated surface back as console memory bytes, row-major, per pixel in the
  // console's byte order (ps3 A8R8G8B8: [A, R, G, B]; x360 k_16_16: little-endian dword, R low;
  // x360 k_16_16_16_16: 8 bytes, R and G in the low dword, B and A in the high one, as int16;
  // depth: the stored (D24 << 8) | stencil word in the console's byte order).
  // Single-sample surfaces only before the resolve (the RHI cannot read MSAA textures back; use
  // edramBytes()).
  std::vector<uint8_t> consoleBytes(const std::string& name, bool afterResolve = false);
  // x360: the surface as it lies in EDRAM (X1), produced on the GPU by a pass that applies the
  // address formula: the tiles [edramBase, edramBase + edramTiles) in order (tile edramBase
  // first, wrapping past 2047 as the hardware does), 5120 bytes each, dwords little-endian;
  // 64-bpp samples as two dwords, R and G low; padding samples (pitch beyond the width) zero.
  // Depth (D24S8): the stored (D24 << 8) | stencil dword per sample, in tiles whose two
  // 40-column halves are swapped relative to colour (X1). Honours the plan's 4x sample order and
  // 64-bpp tile layout parameters. Surfaces with 1 or 4 samples; empty on other platforms.
  std::vector<uint8_t> edramBytes(const std::string& name);
  const std::string& error() const { return error_; }

 private:
  struct Entry {
    const PhysicalTarget* target = nullptr;
    rhi::TextureHandle attachment, rawView, read, readView, readRawView;
    std::vector<rhi::TextureHandle> attachmentLayers;  // single-layer views a resolve reads, arrays only
    rhi::TextureHandle scratch;                         // x360: the copy storeThrough() reads
    uint32_t surface = 0;                               // the PlatformDevice's id of it (0: none)
  };
  rhi::PipelineHandle pipeline(const std::string& fragmentFile, rhi::Format colorFormat,
                               std::vector<std::pair<std::string, std::string>> defines,
                               const rhi::BlendState& blend = {}, uint32_t samples = 1);
  // The passes of resolve(): `rect` (x360 only) non-empty for a rectangle of the surface.
  bool recordResolve(Entry& e, const std::string& name, uint32_t sourceSamples, const rhi::Rect& rect);
  // x360 LogicalTarget::readSamples: one point resolve per sample into the read array's layers.
  bool resolveEachSample(Entry& e, const std::string& name);
  // The defines and bindings of a platform pass that counts what it changes into a new slot of
  // the PlatformDevice's counters (its index in *index, to push); PARITY_COUNT 0 without one.
  std::vector<std::pair<std::string, std::string>> countingInto(const Entry& e, TexelCounters::Slot slot,
                                                                std::vector<rhi::ResourceBinding>* bindings,
                                                                uint32_t* index);
  // Rewrites the surface through `fragmentFile` (reading a copy of it, sample by sample when
  // multisampled), as the render backend stores values; counts into `slot`.
  void storeThrough(Entry& e, const std::string& what, const std::string& fragmentFile, TexelCounters::Slot slot);

  rhi::Device& dev_;
  PlatformDevice* diagnosticsSink_ = nullptr;  // the technique's PlatformDevice, if any
  uint32_t planId_ = 0;                         // its id of this plan
  TargetPlan plan_;
  std::map<std::string, Entry> entries_;
  std::map<std::string, rhi::PipelineHandle> pipelines_;
  std::vector<rhi::ShaderHandle> shaders_;
  std::string error_;
};

}  // namespace parity::platforms
