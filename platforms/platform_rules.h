// A platform's rules as a layer over the frame's command stream (the consoles' validation layer).
//
// The PlatformDevice (platform_device.h) sees every call a technique makes and hands each rule
// set the stream in the terms the rules speak: the platform targets (Surface: a plan's physical
// target as GpuTargets created it, with what the frame did to it so far), which view of a surface
// a call reaches, the pass and what it binds, the pipeline of each draw or dispatch and what it
// samples with which sampler, copies and resolves. Each platform's rules live in its folder
// (x360/x360_rules.cpp, ps3/ps3_rules.cpp, dx10/dx10_rules.cpp) and report catalogue codes;
// the device stamps the pass and pipeline on what they report. The reference has none.
//
// Rules about values (x360 fixed-point range and NaN, 7e3 range, resolve clamps) are counted
// on the GPU by the platform's own passes (GpuTargets, texel_counters.h), not here.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "platforms/common/diagnostics.h"
#include "platforms/common/platform.h"
#include "platforms/common/platform_params.h"
#include "platforms/platform_layer.h"
#include "rhi/rhi.h"

namespace parity::platforms {

// Which memory a texture handle of a platform target reaches.
enum class SurfaceView : uint8_t {
  Attachment = 0,  // the surface rendered to (x360: EDRAM; ps3 packed: its A8R8G8B8 bytes; depth: the depth surface)
  Bits,            // the integer view of the surface (exact writes; x360: EDRAM, ps3: the packed words)
  ReadView,        // the view shaders read the surface through in place (ps3 packed: Y16_X16 of the same memory)
  Resolved,        // the texture the platform's resolve or copy fills (x360 resolves, the dx10/ps3 depth copy)
};
std::string_view surfaceViewName(SurfaceView view);

// A platform target: its plan's row and placement, and what the frame did to it so far.
struct Surface {
  uint32_t id = 0;
  uint32_t plan = 0;  // the GpuTargets it belongs to (x360 places each plan from tile 0)
  PhysicalTarget target;
  uint32_t width = 0, height = 0;
  // The frame so far (the PlatformDevice keeps these).
  bool written = false;              // cleared or drawn into at least once
  bool writtenSinceResolve = false;  // since the last resolve (or copy) into its Resolved texture
  bool resolved = false;             // resolved at least once
  const std::string& name() const { return target.logical.name; }
};

// A texture a call names, and the platform target behind it (surface null: a texture the
// technique created itself, in a host format).
struct TextureUse {
  rhi::TextureHandle texture;
  const Surface* surface = nullptr;
  SurfaceView view = SurfaceView::Attachment;
  std::string label;  // the surface's name, else the texture's label
  rhi::Format format = rhi::Format::Undefined;
  uint32_t samples = 1;
  uint32_t width = 0, height = 0;
  uint32_t root = 0;  // the texture a view was made of (its own id when not a view)
  // A texture of the technique's own (surface null) that a pass has rendered into: on a console
  // every render target is one, whatever the technique allocated.
  bool renderedOutsidePlan = false;
};

struct PassAttachment {
  TextureUse use;  // texture null: slot unused
  rhi::LoadOp load = rhi::LoadOp::Clear;
  bool resolvesTo = false;  // a resolveTarget (the host's MSAA resolve at the end of the pass)
};

struct PassState {
  std::string label;
  std::array<PassAttachment, rhi::kMaxColorTargets> colors{};
  PassAttachment depth;
};

// What the rules need of a pipeline (graphics or compute).
struct PipelineState {
  std::string label;
  bool compute = false;
  std::array<rhi::ColorTargetState, rhi::kMaxColorTargets> colors{};
  uint32_t colorCount = 0;
  bool depthWrite = false;
  bool depthTest = false;
  bool stencilWrite = false;
  // Screen space: no vertex input, every position made in the vertex shader (a full-screen
  // triangle or quad from the vertex index).
  bool screenSpace = false;
  // The fragment shader samples with filtered lookups (texture(), not texelFetch) and reads
  // interpolated inputs: texture coordinates carried from the vertices, which move with the
  // pixel centres.
  bool samplesInterpolatedCoordinates = false;
  // What its shaders need of the platform (capability_rules.h).
  bool geometryStage = false, tessellationStages = false;
  std::array<uint32_t, 3> workgroupSize{1, 1, 1};  // compute
  uint32_t sharedBytes = 0;                        // compute: workgroup-shared memory
  bool atomics = false;
  uint32_t storageBuffersWritten = 0;  // storage buffers its shaders write (UAVs)
  uint32_t storageImagesWritten = 0;   // storage images and texel buffers they write (typed UAVs)
  bool graphicsStorageWrites = false;  // a vertex, geometry, tessellation or fragment shader writes storage
  uint32_t interpolators = 0;          // locations of the fragment shader's user inputs
  uint32_t fragmentTextures = 0;       // texture elements the fragment shader reads
  uint32_t vertexTextures = 0;         // texture elements the stages before rasterisation read
};

// A texture a draw or dispatch reads through the sampler it is read with.
struct SampledTexture {
  uint32_t binding = 0;
  TextureUse use;
  bool filtered = false;  // a Linear min, mag or mip filter
  bool storage = false;   // a storage image (load/store, no sampler)
  bool integer = false;   // the shader reads it as integers (usampler; on D24S8: the stencil)
  bool vertexStage = false;  // a stage before rasterisation reads it (vertex texture fetch)
};

struct DrawState {
  const PassState* pass = nullptr;  // null for a dispatch
  const PipelineState* pipeline = nullptr;
  uint32_t vertices = 0;   // vertices (or indices) of one instance; 0 for a dispatch
  uint32_t instances = 0;
  std::vector<SampledTexture> sampled;
  // The viewport origin on the host after the platform's pixel-centre offset.
  float viewportX = 0, viewportY = 0;
  // The platform's pixel-centre offset (hostPixelCenterOffset): what the device adds.
  float pixelCenterOffset = 0;
};

struct ResolveEvent {
  const Surface* surface = nullptr;
  rhi::Rect rect;            // the rectangle resolved, in surface pixels
  bool whole = true;         // the platform's own rectangle (the padded surface), not one the technique chose
  bool averaging = false;    // the samples are averaged (a multisampled surface read as one)
};

class PlatformRules {
 public:
  virtual ~PlatformRules() = default;
  // A pass begins (its attachments as bound) / ends.
  virtual void beginPass(const PassState&, DiagnosticList&) {}
  virtual void endPass(const PassState&, DiagnosticList&) {}
  // A draw (pass set) or a dispatch (pass null), with the pipeline's state and what it samples.
  virtual void draw(const DrawState&, DiagnosticList&) {}
  // copyTexture by the technique (the platform's own copies are resolves).
  virtual void copy(const TextureUse&, const TextureUse&, DiagnosticList&) {}
  // A resolve (or the platform's copy) of a surface into its Resolved texture.
  virtual void resolve(const ResolveEvent&, DiagnosticList&) {}
  // The technique's GpuTargets for a plan is gone: forget its surfaces.
  virtual void forgetPlan(uint32_t) {}
};

// The rules of `platform` (the reference platform has none: an empty layer).
std::unique_ptr<PlatformRules> makePlatformRules(PlatformId platform, const PlatformParams& params);
// The platform's capability table as rules (capability_rules.cpp): every pass, draw and dispatch
// against what the platform can run at all (capabilities.h).
std::unique_ptr<PlatformRules> makeCapabilityRules(PlatformId platform);

namespace x360 {
std::unique_ptr<PlatformRules> makeRules(const PlatformParams& params);
}
namespace ps3 {
std::unique_ptr<PlatformRules> makeRules(const PlatformParams& params);
}
namespace dx10 {
std::unique_ptr<PlatformRules> makeRules(const PlatformParams& params);
}

// The rules' vocabulary for blend state (platform.h's BlendState, from the RHI's).
BlendState ruleBlend(const rhi::BlendState& blend);

}  // namespace parity::platforms
