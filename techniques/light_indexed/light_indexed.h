// Light-indexed deferred rendering (Trebilco 2008): a depth pre-pass; the light volumes rendered
// with the depth test only into an RGBA8 light index texture; the geometry drawn again with
// forward shading that looks each indexed light up in light tables (colours RGBA8, position and
// 1 / radius RGBA32F, index 0 the null light). The packing of several indices per pixel is one of
// the paper's three (lidr_packing.h). Lights that reach a pixel but do not fit the packing are
// counted per pixel in the "lidr.dropped" target.
#pragma once

#include <memory>
#include <vector>

#include "techniques/common/light_volumes.h"
#include "techniques/light_indexed/lidr_packing.h"
#include "techniques/technique.h"

namespace parity::techniques {

class LightIndexedDeferred : public Technique {
 public:
  // `layout` is used by LidrPacking::Bits only.
  LightIndexedDeferred(LidrPacking packing, BitPackingLayout layout = {});
  std::string name() const override;
  std::vector<PassInfo> passes() const override;
  void prepare(rhi::Device& device, const RenderSettings& settings) override;
  rhi::TextureHandle render(rhi::Device& device, scene::SceneGpu& scene, const scene::Camera& camera) override;
  std::vector<NamedTarget> targets() const override;
  void release(rhi::Device& device) override;

  // Lights the packing can index (index 0 is the null light); lights beyond are never drawn into
  // the index texture and show up as dropped.
  uint32_t maxLights() const;
  // Per-pixel capacity of the packing (overlapping lights kept).
  uint32_t capacity() const;
  // CPU sorting only: the scene lights of the last render() that fitted none of the four arrays.
  const std::vector<uint32_t>& unplacedLights() const { return sort_.unplaced; }
  // Pixels of the last render() that lost at least one light (reads the dropped target back;
  // call after submit()).
  uint64_t pixelsThatLostLight(rhi::Device& device) const;

 private:
  rhi::PipelineHandle volumePipeline(rhi::Device& device, const std::string& label, uint8_t writeMask,
                                     const rhi::BlendState& blend, bool stencil, const rhi::StencilFaceState& face,
                                     rhi::Format format, uint32_t targetCount);
  void drawVolumes(rhi::Device& device, scene::SceneGpu& scene, const std::vector<uint32_t>& lights,
                   const std::vector<scene::GpuMaterial>& outputs);
  void releaseFrameResources(rhi::Device& device);

  LidrPacking packing_;
  BitPackingLayout layout_;
  RenderSettings settings_;
  std::unique_ptr<ShaderLibrary> shaders_;
  std::unique_ptr<LightVolumes> volumes_;
  rhi::PipelineHandle prepassPipeline_, countPipeline_, shadePipeline_;
  std::vector<rhi::PipelineHandle> indexPipelines_;  // sort: one per channel; max: RG, BA; bits: one
  rhi::TextureHandle depthStencil_, surfaceDepth_, overlapCount_, indexA_, indexB_, color_, dropped_;
  // Per frame: light tables and volume model matrices.
  rhi::TextureHandle lightColors_, lightData_;
  rhi::BufferHandle volumeModels_;
  ChannelSort sort_;
};

}  // namespace parity::techniques
