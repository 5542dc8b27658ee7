#include "techniques/hdr/hdr.h"

#include <algorithm>

namespace parity::techniques {

namespace {

rhi::ResourceBinding sampled(uint32_t binding, rhi::TextureHandle texture, rhi::SamplerHandle sampler = {}) {
  rhi::ResourceBinding b;
  b.binding = binding;
  b.kind = rhi::BindingKind::SampledTexture;
  b.texture = texture;
  b.sampler = sampler;
  return b;
}

rhi::ResourceBinding storage(uint32_t binding, rhi::BufferHandle buffer) {
  rhi::ResourceBinding b;
  b.binding = binding;
  b.kind = rhi::BindingKind::StorageBuffer;
  b.buffer = buffer;
  return b;
}

}  // namespace

std::vector<PassInfo> HdrToneMapping::passes() const {
  return {{"shade", "forward shading into a 16-bit float light accumulation target", {"hdr.accumulation", "depth"}},
          {"luminance", "compute: log(delta + L) summed per 16x16 block, then the blocks summed: the log-average", {}},
          {"bright", "bloom source: light above the threshold, then a 2x2 box mip chain", {"hdr.bloom"}},
          {"tonemap", "Reinhard global operator on the accumulation plus the bloom summed over the mips", {"color"}}};
}

void HdrToneMapping::prepare(rhi::Device& device, const RenderSettings& settings) {
  settings_ = settings;
  if (!device.info().caps.compute) throw TechniqueError("hdr: the device has no compute shaders");
  shaders_ = std::make_unique<ShaderLibrary>(device);

  rhi::PipelineDesc p;
  p.vertexShader = shaders_->load("forward/forward.vert", settings.shaderOptions);
  p.fragmentShader = shaders_->load("forward/forward_single_pass.frag", settings.shaderOptions);
  scene::SceneGpu::describeVertexLayout(p);
  p.raster.cull = rhi::CullMode::Back;
  p.depthStencil.depthCompare = rhi::CompareOp::Less;
  p.depthStencil.depthWrite = true;
  p.colorTargets[0].format = rhi::Format::RGBA16F;
  p.colorTargetCount = 1;
  p.depthStencilFormat = rhi::Format::D32F;
  p.label = "hdr shade";
  shade_ = device.createPipeline(p);

  rhi::PipelineDesc f;
  f.vertexShader = shaders_->load("platforms/fullscreen.vert", settings.shaderOptions);
  f.fragmentShader = shaders_->load("effects/hdr_bright.frag", settings.shaderOptions);
  f.colorTargets[0].format = rhi::Format::RGBA16F;
  f.colorTargetCount = 1;
  f.label = "hdr bright";
  bright_ = device.createPipeline(f);
  f.fragmentShader = shaders_->load("effects/hdr_tonemap.frag", settings.shaderOptions);
  f.colorTargets[0].format = settings.colorFormat;
  f.label = "hdr tonemap";
  tonemap_ = device.createPipeline(f);
  rhi::ComputePipelineDesc c;
  c.computeShader = shaders_->load("effects/hdr_luminance.comp", settings.shaderOptions);
  c.label = "hdr luminance";
  reduce_ = device.createComputePipeline(c);
  if (!shade_ || !bright_ || !tonemap_ || !reduce_) throw TechniqueError("hdr: the device rejected a pipeline");

  rhi::TextureDesc t;
  t.format = rhi::Format::RGBA16F;
  t.width = settings.width;
  t.height = settings.height;
  t.label = "hdr accumulation";
  accumulation_ = device.createTexture(t);
  t.format = rhi::Format::D32F;
  t.label = "hdr depth";
  depth_ = device.createTexture(t);
  t.format = settings.colorFormat;
  t.label = "hdr color";
  color_ = device.createTexture(t);
  // The bloom chain starts at half resolution, as the blur it stands for would.
  uint32_t bw = std::max(1u, settings.width / 2), bh = std::max(1u, settings.height / 2);
  levels_ = 1;
  while (levels_ < params_.bloomLevels && (bw >> levels_) > 0 && (bh >> levels_) > 0) ++levels_;
  rhi::TextureDesc b;
  b.format = rhi::Format::RGBA16F;
  b.width = bw;
  b.height = bh;
  b.mipLevels = levels_;
  b.label = "hdr bloom";
  bloom_ = device.createTexture(b);
  if (!accumulation_ || !depth_ || !color_ || !bloom_) throw TechniqueError("hdr: cannot create render targets");
  for (uint32_t l = 0; l < levels_; ++l) {
    rhi::TextureViewDesc v;
    v.parent = bloom_;
    v.baseMip = l;
    v.mipCount = 1;
    v.label = "hdr bloom level " + std::to_string(l);
    bloomLevels_.push_back(device.createTextureView(v));
    if (!bloomLevels_.back()) throw TechniqueError("hdr: cannot create a view of bloom level " + std::to_string(l));
  }

  blockCount_ = ((settings.width + 15) / 16) * ((settings.height + 15) / 16);
  rhi::BufferDesc pb;
  pb.size = sizeof(float) * blockCount_;
  pb.usage = rhi::BufferUsage_Storage;
  pb.label = "hdr luminance partial sums";
  partials_ = device.createBuffer(pb);
  pb.size = 16;
  pb.label = "hdr luminance result";
  result_ = device.createBuffer(pb);
  rhi::SamplerDesc s;
  s.minFilter = s.magFilter = rhi::Filter::Linear;
  s.mipFilter = rhi::MipFilter::Nearest;
  s.label = "hdr bloom levels";
  mipSampler_ = device.createSampler(s);
  if (!partials_ || !result_ || !mipSampler_) throw TechniqueError("hdr: cannot create buffers");
}

rhi::TextureHandle HdrToneMapping::render(rhi::Device& device, scene::SceneGpu& scene, const scene::Camera& camera) {
  scene.setCamera(camera, static_cast<float>(settings_.width) / static_cast<float>(settings_.height));
  rhi::PassDesc pass;
  pass.colors[0].texture = accumulation_;
  pass.colors[0].clearColor = {0.0f, 0.0f, 0.0f, 1.0f};
  pass.depthStencil.texture = depth_;
  pass.label = "shade";
  device.beginPass(pass);
  device.setPipeline(shade_);
  for (const scene::Mesh& mesh : scene.scene().meshes) scene.drawMesh(mesh);
  device.endPass();

  struct Reduce {
    uint32_t mode[4];
    float params[4];
  };
  device.setComputePipeline(reduce_);
  const rhi::ResourceBinding reduceBindings[] = {sampled(4, accumulation_), storage(8, partials_), storage(9, result_)};
  device.setBindings(reduceBindings);
  Reduce blocks{{0, blockCount_, settings_.width, settings_.height}, {params_.delta, 0, 0, 0}};
  device.pushConstants(&blocks, sizeof(blocks));
  device.dispatch(blockCount_);
  Reduce total{{1, blockCount_, settings_.width, settings_.height}, {params_.delta, 0, 0, 0}};
  device.pushConstants(&total, sizeof(total));
  device.dispatch(1);

  struct Bright {
    float params[4];
  };
  for (uint32_t l = 0; l < levels_; ++l) {
    rhi::PassDesc bp;
    bp.colors[0].texture = bloom_;
    bp.colors[0].mip = l;
    bp.colors[0].load = rhi::LoadOp::DontCare;
    bp.label = l == 0 ? "bright" : "bloom mip";
    device.beginPass(bp);
    device.setPipeline(bright_);
    // Level 0 takes the threshold of the accumulation at half resolution: each texel reads the
    // top-left pixel of its 2x2 block, then the chain averages 2x2 blocks of the level above.
    const rhi::ResourceBinding source[] = {sampled(4, l == 0 ? accumulation_ : bloomLevels_[l - 1])};
    device.setBindings(source);
    Bright b{{params_.bloomThreshold, l == 0 ? 1.0f : 0.0f, 0, 0}};
    device.pushConstants(&b, sizeof(b));
    device.draw(3);
    device.endPass();
  }

  rhi::PassDesc tp;
  tp.colors[0].texture = color_;
  tp.colors[0].load = rhi::LoadOp::DontCare;
  tp.label = "tonemap";
  device.beginPass(tp);
  device.setPipeline(tonemap_);
  const rhi::ResourceBinding tb[] = {sampled(4, accumulation_), sampled(5, bloom_, mipSampler_), storage(9, result_)};
  device.setBindings(tb);
  float tonemap[4] = {params_.key, params_.bloomStrength, static_cast<float>(levels_), 0.0f};
  device.pushConstants(tonemap, sizeof(tonemap));
  device.draw(3);
  device.endPass();
  return color_;
}

std::vector<NamedTarget> HdrToneMapping::targets() const {
  return {{"hdr.accumulation", accumulation_}, {"depth", depth_}, {"hdr.bloom", bloom_}, {"color", color_}};
}

void HdrToneMapping::release(rhi::Device& device) {
  for (rhi::TextureHandle v : bloomLevels_) device.destroy(v);
  bloomLevels_.clear();
  for (rhi::PipelineHandle p : {shade_, bright_, tonemap_}) device.destroy(p);
  device.destroy(reduce_);
  for (rhi::TextureHandle t : {accumulation_, depth_, bloom_, color_}) device.destroy(t);
  device.destroy(partials_);
  device.destroy(result_);
  device.destroy(mipSampler_);
  shaders_.reset();
}

}  // namespace parity::techniques
