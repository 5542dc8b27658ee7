#include "techniques/forward/forward.h"

namespace parity::techniques {

std::vector<PassInfo> ForwardSinglePass::passes() const {
  return {{"shade", "geometry drawn once; ambient + directional + every local light summed per fragment",
           {"color", "depth"}}};
}

void ForwardSinglePass::prepare(rhi::Device& device, const RenderSettings& settings) {
  settings_ = settings;
  shaders_ = std::make_unique<ShaderLibrary>(device);

  rhi::PipelineDesc p;
  p.vertexShader = shaders_->load("forward/forward.vert", settings.shaderOptions);
  p.fragmentShader = shaders_->load("forward/forward_single_pass.frag", settings.shaderOptions);
  scene::SceneGpu::describeVertexLayout(p);
  p.raster.cull = rhi::CullMode::Back;
  p.depthStencil.depthCompare = rhi::CompareOp::Less;
  p.depthStencil.depthWrite = true;
  p.colorTargets[0].format = settings.colorFormat;
  p.colorTargetCount = 1;
  p.depthStencilFormat = rhi::Format::D32F;
  p.label = "forward shade";
  pipeline_ = device.createPipeline(p);
  if (!pipeline_) throw TechniqueError("forward: the device rejected the shading pipeline");

  rhi::TextureDesc c;
  c.format = settings.colorFormat;
  c.width = settings.width;
  c.height = settings.height;
  c.label = "forward color";
  color_ = device.createTexture(c);
  rhi::TextureDesc d = c;
  d.format = rhi::Format::D32F;
  d.label = "forward depth";
  depth_ = device.createTexture(d);
  if (!color_ || !depth_) throw TechniqueError("forward: cannot create render targets");
}

rhi::TextureHandle ForwardSinglePass::render(rhi::Device& device, scene::SceneGpu& scene,
                                             const scene::Camera& camera) {
  scene.setCamera(camera, static_cast<float>(settings_.width) / static_cast<float>(settings_.height));
  rhi::PassDesc pass;
  pass.colors[0].texture = color_;
  pass.colors[0].clearColor = {0.0f, 0.0f, 0.0f, 1.0f};
  pass.depthStencil.texture = depth_;
  pass.label = "shade";
  device.beginPass(pass);
  device.setPipeline(pipeline_);
  for (const scene::Mesh& mesh : scene.scene().meshes) scene.drawMesh(mesh);
  device.endPass();
  return color_;
}

void ForwardSinglePass::release(rhi::Device& device) {
  device.destroy(pipeline_);
  device.destroy(color_);
  device.destroy(depth_);
  shaders_.reset();
}

}  // namespace parity::techniques
