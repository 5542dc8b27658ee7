// The log-average luminance of the HDR image (Reinhard et al. 2002, eq. 1: exp(mean(log(delta +
// L)))), by one of two paths chosen from the device's capabilities:
//  * compute (hdr_luminance.comp): one workgroup sums each 16x16 block by a tree in shared
//    memory, a second sums the blocks' partial sums the same way;
//  * where the device has no compute shaders (ps3 and x360; dx10, where compute is optional):
//    the chain of pixel passes a port takes (hdr_luminance_chain.frag), each level an R32Float
//    target of the platform, adding the same values in the same order as the compute tree, so
//    that both paths give the same float bit for bit (tests/effects_hdr_test.cpp).
// Either way the result is the compute path's: x the log-average, y the mean log, z the pixels
// counted; the bright and tone-mapping passes read it at one binding (hdr_log_average.glsl).
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "techniques/common/planned_targets.h"
#include "techniques/technique.h"

namespace parity::techniques {

class LogAverageLuminance {
 public:
  static bool usesCompute(const rhi::Capabilities& caps) { return caps.compute; }
  // The pixel path's levels as target plans (none on a device with compute shaders).
  static std::vector<Technique::SizedTargets> targetPlans(const RenderSettings& settings);
  static PortPath portPath();

  // `options`: the technique's shader options (the platform's defines).
  void prepare(rhi::Device& device, const RenderSettings& settings, ShaderLibrary& shaders,
               const rhi::ShaderCompileOptions& options, float delta);
  // Records the reduction of `hdrImage` (the accumulation's read texture).
  void record(rhi::Device& device, rhi::TextureHandle hdrImage);
  // Where a later pass reads the result at `binding`: the result buffer, or the result level's
  // texture (the shaders compile with HDR_LUMINANCE_TEXTURE then: shaderDefines()).
  rhi::ResourceBinding result(uint32_t binding) const;
  std::vector<std::pair<std::string, std::string>> shaderDefines() const;
  // x, y, z, w of the result after the frame was submitted.
  std::array<float, 4> read(rhi::Device& device) const;
  void release(rhi::Device& device);

 private:
  struct Step {
    int mode = 0;                       // hdr_luminance_chain.frag's
    std::array<int32_t, 4> block{};     // its push constants
    TargetExtent extent;
  };
  static std::vector<Step> chain(const RenderSettings& settings);

  RenderSettings settings_;
  float delta_ = 0;
  bool compute_ = true;
  // Compute path.
  rhi::ComputePipelineHandle reduce_;
  rhi::BufferHandle partials_, result_;
  uint32_t blockCount_ = 0;
  // Pixel path: one plan per level, the last the result.
  rhi::PipelineHandle fold_;
  std::vector<Step> steps_;
  std::vector<std::unique_ptr<PlannedTargets>> levels_;
};

}  // namespace parity::techniques
