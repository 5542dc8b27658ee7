// HDR rendering with tone mapping and bloom (Ferko 2012, §6's pipeline; Reinhard et al. 2002):
// forward shading accumulates light in a 16-bit float target; a reduction gives the log-average
// luminance on the GPU (compute, or the pixel passes a port takes where there is none:
// luminance.h); a bright pass keeps what the exposure takes above a threshold and builds a
// chain of halved levels; the tone-mapping pass adds the bloom summed over the levels and applies
// Reinhard's global operator.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "techniques/common/planned_targets.h"
#include "techniques/hdr/luminance.h"
#include "techniques/technique.h"

namespace parity::techniques {

class HdrToneMapping : public Technique {
 public:
  struct Params {
    float key = 0.18f;           // Reinhard's key value a
    float delta = 1e-4f;         // log(delta + L) keeps black pixels finite
    float bloomThreshold = 1.0f; // exposed luminance (key / log-average x L) above which light blooms
    float bloomStrength = 0.5f;
    uint32_t bloomLevels = 5;    // at most kMaxBloomLevels
  };
  HdrToneMapping() = default;
  explicit HdrToneMapping(Params params) : params_(params) {}
  std::string name() const override { return "hdr"; }
  std::vector<PassInfo> passes() const override;
  static constexpr uint32_t kMaxBloomLevels = 5;  // the tone-mapping shader's bloom bindings
  // The light accumulation (Rgba16Hdr: RGBA16F on dx10 and ps3, k_16_16_16_16 on x360, float on
  // the reference) and the shading pass's depth; each bloom level is a Rgba16Hdr plan of its own
  // size (from half resolution down), so a console holds and resolves it like the accumulation.
  std::vector<platforms::LogicalTarget> logicalTargets(const RenderSettings&) const override;
  // The bloom levels, and the luminance chain's levels where the device has no compute shaders.
  std::vector<SizedTargets> furtherTargetPlans(const RenderSettings& settings) const override;
  std::vector<PortPath> portPaths(const rhi::Capabilities& caps) const override;
  void prepare(rhi::Device& device, const RenderSettings& settings) override;
  rhi::TextureHandle render(rhi::Device& device, scene::SceneGpu& scene, const scene::Camera& camera) override;
  std::vector<NamedTarget> targets() const override;
  void release(rhi::Device& device) override;

  const Params& params() const { return params_; }
  // After render() and submit: log-average luminance, mean log, pixel count, 0.
  std::array<float, 4> readLuminance(rhi::Device& device) const;

 private:
  Params params_;
  RenderSettings settings_;
  std::unique_ptr<ShaderLibrary> shaders_;
  std::vector<SizedTargets> bloomPlans(const RenderSettings& settings) const;

  rhi::PipelineHandle shade_, bright_, tonemap_;
  LogAverageLuminance luminance_;
  std::unique_ptr<PlannedTargets> targets_;  // accumulation and depth
  std::vector<std::unique_ptr<PlannedTargets>> bloom_;  // one plan per level, level 0 at half size
  rhi::SamplerHandle bilinear_;
  uint32_t levels_ = 0;
};

}  // namespace parity::techniques
