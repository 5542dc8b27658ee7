#include "techniques/deferred/light_volume_pass.h"

#include <glm/glm.hpp>

namespace parity::techniques {

LightVolumePass::LightVolumePass(rhi::Device& device, rhi::PipelineDesc base) : device_(device) {
  volumes_ = std::make_unique<LightVolumes>(device);
  LightVolumes::describeVertexLayout(base);
  base.depthStencil.depthWrite = false;

  rhi::PipelineDesc outside = base;
  outside.raster.cull = rhi::CullMode::Back;
  outside.depthStencil.depthCompare = rhi::CompareOp::LessEqual;
  outside.label = base.label + " (outside: front faces)";
  outside_ = device.createPipeline(outside);

  rhi::PipelineDesc inside = base;
  inside.raster.cull = rhi::CullMode::Front;
  inside.depthStencil.depthCompare = rhi::CompareOp::GreaterEqual;
  inside.label = base.label + " (inside: back faces)";
  inside_ = device.createPipeline(inside);
}

LightVolumePass::~LightVolumePass() {
  device_.destroy(outside_);
  device_.destroy(inside_);
  if (transforms_) device_.destroy(transforms_);
}

void LightVolumePass::upload(const scene::Scene& scene) {
  drawn_ = inside_count_ = 0;
  std::vector<glm::mat4> models;
  for (const scene::Light& light : scene.lights) models.push_back(LightVolumes::model(light));
  if (models.empty()) models.push_back(glm::mat4(1.0f));  // storage buffers may not be empty
  size_t bytes = models.size() * sizeof(glm::mat4);
  if (bytes > transformCapacity_) {
    if (transforms_) device_.destroy(transforms_);
    rhi::BufferDesc d;
    d.size = bytes;
    d.usage = rhi::BufferUsage_Storage;
    d.label = "light volume transforms";
    transforms_ = device_.createBuffer(d);
    transformCapacity_ = bytes;
  }
  device_.writeBuffer(transforms_, 0, models.data(), bytes);
}

void LightVolumePass::draw(scene::SceneGpu& scene, const scene::LightLists& lists, const scene::Camera& camera,
                           float aspect, const std::vector<rhi::ResourceBinding>& bindings, const LightFilter& filter) {
  std::vector<rhi::ResourceBinding> all = bindings;
  rhi::ResourceBinding b;
  b.binding = 0;
  b.kind = rhi::BindingKind::UniformBuffer;
  b.buffer = scene.frameBuffer();
  all.push_back(b);
  b.binding = 1;
  b.kind = rhi::BindingKind::StorageBuffer;
  b.buffer = scene.lightBuffer();
  all.push_back(b);
  b.binding = 3;
  b.buffer = transforms_;
  all.push_back(b);

  const std::vector<scene::Light>& lights = scene.scene().lights;
  rhi::PipelineHandle current;
  for (uint32_t l = 0; l < lights.size() && l < lists.perLight.size(); ++l) {
    if (lists.perLight[l].empty() || (filter.include && !filter.include(l))) continue;
    bool inside = cameraInsideLightVolume(lights[l], camera, aspect);
    rhi::PipelineHandle p = inside ? inside_ : outside_;
    if (p != current) {
      device_.setPipeline(p);
      device_.setBindings(all);
      current = p;
    }
    if (filter.beforeDraw) filter.beforeDraw(l);
    scene::GpuMaterial m{};
    m.flags.y = l;
    device_.pushConstants(&m, sizeof(m));
    volumes_->draw(lights[l]);
    ++drawn_;
    if (inside) ++inside_count_;
  }
}

}  // namespace parity::techniques
