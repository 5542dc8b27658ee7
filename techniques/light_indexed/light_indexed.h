// Light-indexed deferred rendering (Trebilco 2008): a depth pre-pass; the light volumes rendered
// with the depth test only into an RGBA8 light index texture; the geometry drawn again with
// forward shading that looks each indexed light up in light tables (colours RGBA8, position and
// 1 / radius RGBA32F, index 0 the null light). The packing of several indices per pixel is one of
// the paper's three (lidr_packing.h). Lights that reach a pixel but do not fit the packing are
// counted per pixel in the "lidr.dropped" target. On a platform every target is planned: the
// overlap count is R8Unorm and the light index and lost-light count Rgba8Bits (8 bits on every
// platform, the reference included: lossless, so dx10 and ps3 render the reference image), the
// pre-pass depth copy R32Float (lossless); multisampled, the 4x colour resolves by the
// platform's rule (x360's rounds ties up).
//
// LidrVolumes::FrontFacesMsaa is the paper's MSAA technique 2 ("Light Volume Front Faces"): the
// frame is rendered with 4x MSAA and resolved; the light index texture stays single-sample and
// holds every light whose volume's front faces lie in front of the farthest opaque sample of the
// pixel, i.e. every light whose volume the ray from the eye to any sample's opaque surface
// crosses. So every sample of the pixel, and every translucent surface in front of the opaque
// one, finds all the lights that can reach it (the paper's transparency path): translucent
// meshes (scene::Material::opacity < 1) are drawn after the opaque ones, back to front, blended
// with their opacity, over the same light index texture.
//
// Constraining lights to surfaces (the paper's per-surface light lookup tables): each mesh can be
// shaded with its own light table in which the lights it must not receive are nulled out (black).
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "techniques/common/light_volumes.h"
#include "techniques/common/planned_targets.h"
#include "techniques/light_indexed/lidr_packing.h"
#include "techniques/technique.h"

namespace parity::techniques {

// How the light volumes mark the light index texture.
enum class LidrVolumes {
  SurfaceInside,   // back faces, kept where the visible surface is inside the light (single-sample)
  FrontFacesMsaa,  // MSAA technique 2: front faces in front of the farthest sample; 4x MSAA
};

// Per-surface light tables: table t nulls the scene lights excluded[t]; mesh m is shaded with
// table meshTable[m] (meshes beyond the list, and table kAllLights, receive every light).
struct SurfaceLightTables {
  static constexpr uint32_t kAllLights = ~0u;
  std::vector<std::vector<uint32_t>> excluded;
  std::vector<uint32_t> meshTable;
};

class LightIndexedDeferred : public Technique {
 public:
  static constexpr uint32_t kMsaaSamples = 4;
  // `layout` is used by LidrPacking::Bits only (rows of one group and up to 8 index bits:
  // prepare() rejects the others).
  LightIndexedDeferred(LidrPacking packing, BitPackingLayout layout = {},
                       LidrVolumes volumes = LidrVolumes::SurfaceInside);
  std::string name() const override;
  std::vector<PassInfo> passes() const override;
  std::vector<platforms::LogicalTarget> logicalTargets(const RenderSettings& settings) const override;
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
  // Lights constrained to surfaces; takes effect from the next render().
  void setSurfaceLightTables(SurfaceLightTables tables) { surfaceTables_ = std::move(tables); }
  // Reference shading for tests: the forward pass lights every surface with every scene light of
  // its table (multi-light forward rendering) instead of the indexed ones, all passes unchanged.
  // Call before prepare().
  void setShadeEveryLight(bool every) { shadeEveryLight_ = every; }

 private:
  rhi::PipelineHandle volumePipeline(rhi::Device& device, const std::string& label, uint8_t writeMask,
                                     const rhi::BlendState& blend, bool stencil, const rhi::StencilFaceState& face,
                                     rhi::Format format, uint32_t targetCount, bool cameraInside = false);
  // Volume pipelines come in pairs: [0] camera outside the volume, [1] inside (FrontFacesMsaa).
  using VolumePipelines = std::array<rhi::PipelineHandle, 2>;
  VolumePipelines volumePipelines(rhi::Device& device, const std::string& label, uint8_t writeMask,
                                  const rhi::BlendState& blend, bool stencil, const rhi::StencilFaceState& face,
                                  rhi::Format format, uint32_t targetCount);
  void drawVolumes(rhi::Device& device, scene::SceneGpu& scene, const scene::Camera& camera,
                   const VolumePipelines& pipelines, const std::vector<rhi::ResourceBinding>& bindings,
                   const std::vector<uint32_t>& lights, const std::vector<scene::GpuMaterial>& outputs);
  uint32_t tableRow(size_t mesh) const;
  bool msaa() const { return volumes_mode_ == LidrVolumes::FrontFacesMsaa; }
  void releaseFrameResources(rhi::Device& device);

  LidrPacking packing_;
  BitPackingLayout layout_;
  LidrVolumes volumes_mode_;
  SurfaceLightTables surfaceTables_;
  bool shadeEveryLight_ = false;
  RenderSettings settings_;
  std::unique_ptr<ShaderLibrary> shaders_;
  std::unique_ptr<LightVolumes> volumes_;
  rhi::PipelineHandle prepassPipeline_, shadePipeline_;
  VolumePipelines countPipeline_{};
  std::vector<VolumePipelines> indexPipelines_;  // sort: one per channel; max: RG, BA; bits: one
  std::unique_ptr<PlannedTargets> targets_;  // every target of the technique (logicalTargets)
  static constexpr const char* kLightIndex = "lidr.index";
  static constexpr const char* kLightIndex2 = "lidr.index2";  // the 8x255 packing's second target
  static constexpr const char* kSurfaceDepth = "prepass.depth";  // the light volumes' test depth, as colour
  static constexpr const char* kOverlapCount = "lidr.count";
  static constexpr const char* kDropped = "lidr.dropped";
  // FrontFacesMsaa: the 4x depth-stencil of the pre-pass and forward pass, and the pre-pass's
  // 4x surface depth the farthest-sample pass reads sample by sample.
  static constexpr const char* kMsaaDepth = "msaa.depth";
  static constexpr const char* kMsaaSurfaceDepth = "msaa.prepass.depth";
  // FrontFacesMsaa: the farthest-sample pass and the translucent meshes' forward pipeline.
  rhi::PipelineHandle farthestPipeline_, translucentPipeline_;
  // Per frame: light tables and volume model matrices.
  rhi::TextureHandle lightColors_, lightData_;
  rhi::BufferHandle volumeModels_;
  ChannelSort sort_;
};

}  // namespace parity::techniques
