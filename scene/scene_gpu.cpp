#include "scene/scene_gpu.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cstring>

namespace parity::scene {

SceneGpu::SceneGpu(rhi::Device& device, const Scene& scene) : device_(device), scene_(scene) {
  rhi::BufferDesc vb;
  vb.size = scene.vertices.size() * sizeof(Vertex);
  vb.usage = rhi::BufferUsage_Vertex;
  vb.initialData = scene.vertices.data();
  vb.label = scene.name + " vertices";
  vertices_ = device.createBuffer(vb);

  rhi::BufferDesc ib;
  ib.size = scene.indices.size() * sizeof(uint32_t);
  ib.usage = rhi::BufferUsage_Index;
  ib.initialData = scene.indices.data();
  ib.label = scene.name + " indices";
  indices_ = device.createBuffer(ib);

  rhi::BufferDesc fb;
  fb.size = sizeof(FrameData);
  fb.usage = rhi::BufferUsage_Uniform;
  fb.label = "frame data";
  frame_ = device.createBuffer(fb);

  std::vector<GpuLight> lights;
  for (const Light& l : scene.lights) {
    GpuLight g;
    g.positionRadius = glm::vec4(l.position, l.radius);
    g.colorK = glm::vec4(l.color, l.attenuationK());
    uint32_t type = static_cast<uint32_t>(l.type);
    float typeBits;
    std::memcpy(&typeBits, &type, sizeof(type));
    g.directionType = glm::vec4(glm::normalize(l.direction), typeBits);
    g.cone = glm::vec4(l.cosOuter, l.cosInner, 0.0f, 0.0f);
    lights.push_back(g);
  }
  if (lights.empty()) lights.push_back({});  // storage buffers may not be empty
  rhi::BufferDesc lb;
  lb.size = lights.size() * sizeof(GpuLight);
  lb.usage = rhi::BufferUsage_Storage;
  lb.initialData = lights.data();
  lb.label = "lights";
  lights_ = device.createBuffer(lb);

  for (const Texture& t : scene.textures) {
    rhi::TextureDesc td;
    td.format = rhi::Format::RGBA8;
    td.width = t.width;
    td.height = t.height;
    td.usage = rhi::TextureUsage_Sampled;
    td.initialData = t.rgba8.data();
    td.label = t.name;
    textures_.push_back(device.createTexture(td));
  }
  const uint8_t white[4] = {255, 255, 255, 255};
  rhi::TextureDesc wd;
  wd.usage = rhi::TextureUsage_Sampled;
  wd.initialData = white;
  wd.label = "white";
  white_ = device.createTexture(wd);
  const uint8_t flat[4] = {128, 128, 255, 255};
  rhi::TextureDesc nd = wd;
  nd.initialData = flat;
  nd.label = "flat normal";
  flatNormal_ = device.createTexture(nd);

  rhi::SamplerDesc sd;
  sd.minFilter = rhi::Filter::Linear;
  sd.magFilter = rhi::Filter::Linear;
  sd.addressU = sd.addressV = rhi::AddressMode::Repeat;
  sd.label = "material sampler";
  sampler_ = device.createSampler(sd);
}

SceneGpu::~SceneGpu() {
  device_.destroy(vertices_);
  device_.destroy(indices_);
  device_.destroy(frame_);
  device_.destroy(lights_);
  for (rhi::TextureHandle t : textures_) device_.destroy(t);
  device_.destroy(white_);
  device_.destroy(flatNormal_);
  device_.destroy(sampler_);
}

void SceneGpu::setCamera(const Camera& camera, float aspect) {
  FrameData f{};
  f.viewProj = camera.viewProjection(aspect);
  f.cameraPos = glm::vec4(camera.position, 1.0f);
  f.ambient = glm::vec4(scene_.ambient, 0.0f);
  f.directionalDir = glm::vec4(glm::normalize(scene_.directionalDir), 0.0f);
  f.directionalColor = glm::vec4(scene_.directionalColor, 0.0f);
  f.counts = glm::uvec4(static_cast<uint32_t>(scene_.lights.size()), 0, 0, 0);
  f.view = glm::lookAtRH(camera.position, camera.target, camera.up);
  f.invViewProj = glm::inverse(f.viewProj);
  f.nearFar = glm::vec4(camera.nearPlane, camera.farPlane, 0.0f, 0.0f);
  device_.writeBuffer(frame_, 0, &f, sizeof(f));
}

GpuMaterial SceneGpu::material(int index) const {
  const Material& m = scene_.materials.at(static_cast<size_t>(index));
  GpuMaterial g;
  g.diffuse = glm::vec4(m.diffuse, 1.0f);
  g.specular = glm::vec4(m.specular, m.specularPower);
  uint32_t textures = (m.diffuseTexture >= 0 ? kMaterialDiffuseTexture : 0u) |
                      (m.normalTexture >= 0 ? kMaterialNormalMap : 0u);
  g.flags = glm::uvec4(textures, 0, 0, 0);
  return g;
}

rhi::TextureHandle SceneGpu::diffuseTexture(int materialIndex) const {
  int t = scene_.materials.at(static_cast<size_t>(materialIndex)).diffuseTexture;
  return t >= 0 ? textures_.at(static_cast<size_t>(t)) : white_;
}

rhi::TextureHandle SceneGpu::normalTexture(int materialIndex) const {
  int t = scene_.materials.at(static_cast<size_t>(materialIndex)).normalTexture;
  return t >= 0 ? textures_.at(static_cast<size_t>(t)) : flatNormal_;
}

void SceneGpu::describeVertexLayout(rhi::PipelineDesc& desc) {
  desc.attributes[0] = {0, rhi::VertexFormat::Float3, offsetof(Vertex, position), 0};
  desc.attributes[1] = {1, rhi::VertexFormat::Float3, offsetof(Vertex, normal), 0};
  desc.attributes[2] = {2, rhi::VertexFormat::Float2, offsetof(Vertex, uv), 0};
  desc.attributeCount = 3;
  desc.vertexBuffers[0].stride = sizeof(Vertex);
}

void SceneGpu::drawMesh(const Mesh& mesh) { drawMesh(mesh, 0u); }

void SceneGpu::drawMesh(const Mesh& mesh, uint32_t lightIndex) {
  rhi::ResourceBinding bindings[4];
  bindings[0].binding = 0;
  bindings[0].kind = rhi::BindingKind::UniformBuffer;
  bindings[0].buffer = frame_;
  bindings[1].binding = 1;
  bindings[1].kind = rhi::BindingKind::StorageBuffer;
  bindings[1].buffer = lights_;
  bindings[2].binding = 2;
  bindings[2].kind = rhi::BindingKind::SampledTexture;
  bindings[2].texture = diffuseTexture(mesh.material);
  bindings[2].sampler = sampler_;
  bindings[3].binding = kNormalMapBinding;
  bindings[3].kind = rhi::BindingKind::SampledTexture;
  bindings[3].texture = normalTexture(mesh.material);
  bindings[3].sampler = sampler_;
  device_.setBindings(bindings);
  GpuMaterial m = material(mesh.material);
  m.flags.y = lightIndex;
  device_.pushConstants(&m, sizeof(m));
  device_.setVertexBuffer(0, vertices_);
  device_.setIndexBuffer(indices_, rhi::IndexType::UInt32);
  device_.drawIndexed(mesh.indexCount, 1, mesh.firstIndex);
}

}  // namespace parity::scene
