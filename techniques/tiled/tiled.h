// Tiled shading (thesis §2.4 and ch. 5: Andersson 2009, Olsson 2011). A compute pass builds a
// light list per 16 x 16 pixel tile from the world-space bounds of the tile's visible surface
// (depth) — where the device has no compute shaders the CPU builds them from each tile's
// frustum, as a console port does (cpu_light_culling.h); then either
//  * tiled deferred: a G-buffer pass (depth, normal, diffuse + specular power, specular) and
//    one full-screen pass that shades each pixel over its tile's list, or
//  * tiled forward: a depth pre-pass and a forward geometry pass that loops over the tile's
//    list instead of every light.
// On a platform the G-buffer is three Rgba16Hdr targets (FP16 on dx10/ps3, k_16_16_16_16 on
// x360, whose +-32 range clamps specular powers above 32) and the culling reads the scene depth
// as the platform reads depth; tiled forward's pre-pass keeps depth in an R32Float target, the
// same 32 bits on every platform (lossless: its images are the reference's on dx10 and ps3).
#pragma once

#include <memory>
#include <vector>

#include "techniques/common/planned_targets.h"
#include "techniques/technique.h"

namespace parity::techniques {

enum class TiledMode { Deferred, Forward };

class TiledShading : public Technique {
 public:
  static constexpr uint32_t kTileSize = 16;
  static constexpr uint32_t kMaxLights = 4096;  // light_cull.comp's bit mask

  explicit TiledShading(TiledMode mode) : mode_(mode) {}
  std::string name() const override { return mode_ == TiledMode::Deferred ? "tiled-deferred" : "tiled-forward"; }
  std::vector<PassInfo> passes() const override;
  std::vector<platforms::LogicalTarget> logicalTargets(const RenderSettings& settings) const override;
  std::vector<PortPath> portPaths(const rhi::Capabilities& caps) const override;
  void prepare(rhi::Device& device, const RenderSettings& settings) override;
  rhi::TextureHandle render(rhi::Device& device, scene::SceneGpu& scene, const scene::Camera& camera) override;
  std::vector<NamedTarget> targets() const override;
  void release(rhi::Device& device) override;

  uint32_t tilesX() const { return (settings_.width + kTileSize - 1) / kTileSize; }
  uint32_t tilesY() const { return (settings_.height + kTileSize - 1) / kTileSize; }
  // The light list of every tile of the last render(), row by row (reads the list buffer back;
  // call after submit()).
  std::vector<std::vector<uint32_t>> readTileLists(rhi::Device& device) const;

 private:
  TiledMode mode_;
  RenderSettings settings_;
  std::unique_ptr<ShaderLibrary> shaders_;
  rhi::PipelineHandle geometryPipeline_, shadePipeline_;
  rhi::ComputePipelineHandle cullPipeline_;
  std::unique_ptr<PlannedTargets> targets_;  // every target of the technique (logicalTargets)
  rhi::BufferHandle tileLists_, tileParams_;
  uint32_t stride_ = 0;
};

}  // namespace parity::techniques
