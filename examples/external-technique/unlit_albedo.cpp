#include "unlit_albedo.h"

namespace albedo {

namespace pt = parity::techniques;
namespace rhi = parity::rhi;

std::vector<pt::PassInfo> UnlitAlbedo::passes() const {
  return {{"albedo", "geometry drawn once; each fragment writes its material's diffuse colour", {"color", "depth"}}};
}

// Planned by the platform like every parity technique: on x360 the colour lives in EDRAM and is
// resolved, on ps3 and dx10 the platform picks the surfaces.
std::vector<parity::platforms::LogicalTarget> UnlitAlbedo::logicalTargets(const pt::RenderSettings& settings) const {
  return {pt::outputColorTarget(settings, "albedo"), pt::sceneDepthTarget("albedo")};
}

void UnlitAlbedo::prepare(rhi::Device& device, const pt::RenderSettings& settings) {
  settings_ = settings;
  shaders_ = std::make_unique<pt::ShaderLibrary>(device);
  targets_ = std::make_unique<pt::PlannedTargets>(device, settings, logicalTargets(settings), name());
  const rhi::ShaderCompileOptions options = targets_->shaderOptions(settings);
  rhi::PipelineDesc p;
  // parity's own vertex shader (installed with it), this project's fragment shader.
  p.vertexShader = shaders_->load("forward/forward.vert", options);
  p.fragmentShader = shaders_->load(ALBEDO_SHADER_DIR "/unlit_albedo.frag", options);
  parity::scene::SceneGpu::describeVertexLayout(p);
  p.raster.cull = rhi::CullMode::Back;
  p.depthStencil.depthCompare = rhi::CompareOp::Less;
  p.depthStencil.depthWrite = true;
  p.colorTargets[0].format = targets_->format(pt::kOutputColor);
  p.colorTargetCount = 1;
  p.depthStencilFormat = targets_->format(pt::kSceneDepth);
  p.label = "unlit albedo";
  pipeline_ = device.createPipeline(p);
  if (!pipeline_) throw pt::TechniqueError("unlit-albedo: the device rejected the pipeline");
}

rhi::TextureHandle UnlitAlbedo::render(rhi::Device& device, parity::scene::SceneGpu& scene,
                                       const parity::scene::Camera& camera) {
  scene.setCamera(camera, static_cast<float>(settings_.width) / static_cast<float>(settings_.height));
  rhi::PassDesc pass;
  pass.colors[0].texture = targets_->attachment(pt::kOutputColor);
  pass.colors[0].clearColor = {0.0f, 0.0f, 0.0f, 0.0f};  // as deferred clears its G-buffer
  pass.depthStencil.texture = targets_->attachment(pt::kSceneDepth);
  pass.label = "albedo";
  device.beginPass(pass);
  device.setPipeline(pipeline_);
  for (const parity::scene::Mesh& mesh : scene.scene().meshes) scene.drawMesh(mesh);
  device.endPass();
  return targets_->present();
}

std::vector<pt::NamedTarget> UnlitAlbedo::targets() const {
  if (!targets_) return {};
  return {{pt::kOutputColor, targets_->readTexture(pt::kOutputColor)}};
}

void UnlitAlbedo::release(rhi::Device& device) {
  device.destroy(pipeline_);
  targets_.reset();
  shaders_.reset();
}

}  // namespace albedo
