// A small deferred technique written as a console port should be, and every porting mistake the
// platform rules know, planted one at a time (tests/platform_porting_mistakes_test.cpp).
//
// The clean technique: a G-buffer pass (albedo 8-bit, a two-16-bit "normal" written through the
// platform's exact path, scene depth), each resolved; a light pass adding the lit G-buffer into an
// HDR light buffer; a compose pass tone-mapping it into the frame colour. Every target is planned
// by the platform, every screen-space pass that samples interpolated coordinates offsets its
// viewport by -TargetPlan::pixelCenterOffset, as a D3D9 port offsets its quads. Each Mistake
// changes one thing a port gets wrong; renderFrameTexels renders it like any technique.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "techniques/common/planned_targets.h"
#include "techniques/technique.h"

namespace parity::test {

enum class Mistake {
  None,
  PackedBlend,            // the normal target blended (multiplicatively)
  PackedFilter,           // the normal's surface sampled through a bilinear sampler
  PackedWriteMask,        // the normal written with a write mask that splits its 16-bit values
  HdrAbove32,             // light values beyond +-32
  HdrNaN,                 // a NaN light value
  HdrMultiplyBlend,       // the light buffer blended by DEST_COLOR
  DepthFeedback,          // depth sampled while the pass writes it
  DepthFiltered,          // depth sampled through a bilinear sampler
  DepthSurfaceSampled,    // the depth surface sampled itself, not its resolve or copy
  DepthSampledWhileBound, // the depth surface sampled by a pass that has it attached
  OwnFloatDepthSampled,   // a D32F depth texture of the technique's own sampled
  MsaaDepthSampled,       // a 4x depth texture of the technique's own sampled
  SampleBeforeResolve,    // the albedo sampled without its resolve
  SampleEdramSurface,     // the albedo's surface sampled, not its resolved texture
  StaleResolve,           // the albedo rendered again after its resolve, then sampled
  MixedMrt,               // the G-buffer pass binds an HDR target beside the 8-bit ones
  SharedBlend,            // two targets of one pass blended with different functions
  OwnRg16Target,          // a two-16-bit texture of the technique's own rendered into
  PackedMsaaResolve,      // a 4x two-16-bit target resolved by averaging
  UnalignedResolve,       // a resolve of a rectangle that is not 8-pixel aligned
  D3D10Centres,           // a screen-space pass without the -0.5 of D3D9 centres
  QuadD3D10Centres,       // the same pass drawn as a quad from a vertex buffer
  MixedCentres,           // one pass with draws at both conventions
  LBufferBeforeResolve,   // an L-buffer over the G-buffer tiles written before their resolve
  LBufferOverDepth,       // an L-buffer placed over the depth its pass tests against
  GBufferSameBase,        // two G-buffer targets declared live apart but bound together
  ScratchOverDepth,       // a target over the depth's tiles drawn before the depth's resolve
  SurfaceTooLarge,        // a 4x target too large for EDRAM
  MrtMsaaMismatch,        // 1x and 4x targets bound together
  NormalOutOfRange,       // values outside [0, 1] written to the two-16-bit target
  OwnTargetSampled,       // a render target of the technique's own, outside the plan, sampled
};

struct MistakeInfo {
  Mistake mistake;
  std::string name;  // "packed-blend"
  std::string what;  // one line for the table
};
const std::vector<MistakeInfo>& allMistakes();

class MiniPort final : public techniques::Technique {
 public:
  explicit MiniPort(Mistake mistake) : mistake_(mistake) {}
  std::string name() const override;
  std::vector<techniques::PassInfo> passes() const override;
  std::vector<platforms::LogicalTarget> logicalTargets(const techniques::RenderSettings& settings) const override;
  void prepare(rhi::Device& device, const techniques::RenderSettings& settings) override;
  rhi::TextureHandle render(rhi::Device& device, scene::SceneGpu& scene, const scene::Camera& camera) override;
  std::vector<techniques::NamedTarget> targets() const override;
  void release(rhi::Device& device) override;

 private:
  // `state` with `vertex` (default: the full-screen triangle) and `fragment` compiled with the
  // plan's defines and `defines`.
  rhi::PipelineHandle pipeline(rhi::Device& device, const char* fragment, std::vector<std::pair<std::string, std::string>> defines,
                               rhi::PipelineDesc state, const char* vertex = nullptr);
  void fullScreen(rhi::Device& device, bool compensated = true);
  bool depthBoundInLight() const;

  Mistake mistake_;
  techniques::RenderSettings settings_;
  std::unique_ptr<techniques::PlannedTargets> targets_;
  std::vector<rhi::ShaderHandle> shaders_;
  std::vector<rhi::PipelineHandle> pipelines_;
  rhi::PipelineHandle gbuffer_, light_, compose_, plain_, plainMsaa_, packedMsaa_;
  rhi::BufferHandle quad_;  // QuadD3D10Centres: the compose pass's quad (position, uv)
  rhi::SamplerHandle nearest_, linear_;
  rhi::TextureHandle own_;  // a texture of the technique's own (OwnFloatDepthSampled, MsaaDepthSampled, OwnRg16Target)
};

// Registers "mini-port" and "mini-port:<mistake>" for every mistake (once per process).
void registerMiniPorts();

}  // namespace parity::test
