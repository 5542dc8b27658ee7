#include "techniques/ssao/deferred_ssao.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "techniques/common/planned_targets.h"

namespace parity::techniques {

namespace {

const char* const kDepth = "ssao.depth";
const char* const kNormals = "ssao.normals";
const char* const kDiffuse = "ssao.diffuse";
const char* const kRawOcclusion = "ssao.raw";
const char* const kBlurScratch = "ssao.blur";  // the horizontal blur's output
const char* const kOcclusion = "ssao";

// The targets of the SSAO geometry pass (the deferred technique's own are private to it).
std::vector<platforms::LogicalTarget> geometryTargets(const RenderSettings& settings) {
  using platforms::LogicalFormat;
  using platforms::TargetRole;
  return {{kNormals, LogicalFormat::Rg16Unorm, true, TargetRole::GBuffer, "ssao geometry"},
          {kDiffuse, LogicalFormat::Rgba8Unorm, true, TargetRole::GBuffer, "ssao geometry"},
          {kDepth, LogicalFormat::Depth24Stencil8, true, TargetRole::GBuffer, "ssao geometry"},
          outputColorTarget(settings, "apply")};
}

// The occlusion at reduced resolution, one 8-bit channel each: the raw term and the two blur passes.
std::vector<platforms::LogicalTarget> occlusionTargets() {
  using platforms::LogicalFormat;
  using platforms::TargetRole;
  return {{kRawOcclusion, LogicalFormat::R8Unorm, true, TargetRole::Plain, "ssao"},
          {kBlurScratch, LogicalFormat::R8Unorm, true, TargetRole::Plain, "ssao blur h"},
          {kOcclusion, LogicalFormat::R8Unorm, true, TargetRole::Plain, "ssao blur v"}};
}

rhi::ResourceBinding sampled(uint32_t binding, rhi::TextureHandle texture, rhi::SamplerHandle sampler = {}) {
  rhi::ResourceBinding b;
  b.binding = binding;
  b.kind = rhi::BindingKind::SampledTexture;
  b.texture = texture;
  b.sampler = sampler;
  return b;
}

constexpr size_t kParamSlot = 256;  // uniform offsets: the strictest alignment of either API

struct BlurParams {
  int32_t axis[4];
  float params[4];
};

rhi::ResourceBinding frameBlock(const scene::SceneGpu& scene) {
  rhi::ResourceBinding b;
  b.binding = 0;
  b.kind = rhi::BindingKind::UniformBuffer;
  b.buffer = scene.frameBuffer();
  return b;
}

// 4x4 random unit vectors (Ferko §5.1's random-vector texture), deterministic: an integer hash,
// so every run and backend gets the same texels.
std::vector<uint8_t> randomVectorTexels() {
  std::vector<uint8_t> texels(16 * 4);
  uint32_t state = 0x9E3779B9u;
  auto next = [&] {
    state ^= state << 13, state ^= state >> 17, state ^= state << 5;
    return static_cast<float>(state & 0xFFFFFF) / 16777215.0f * 2.0f - 1.0f;
  };
  for (int i = 0; i < 16; ++i) {
    float v[3], len;
    do {
      for (float& c : v) c = next();
      len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    } while (len < 0.1f || len > 1.0f);
    for (int c = 0; c < 3; ++c) texels[i * 4 + c] = static_cast<uint8_t>(std::lround((v[c] / len * 0.5f + 0.5f) * 255.0f));
    texels[i * 4 + 3] = 255;
  }
  return texels;
}

}  // namespace

std::vector<PassInfo> DeferredSsao::passes() const {
  std::vector<PassInfo> p = lit_.passes();
  p.push_back({"ssao geometry", "depth and view-space normals for SSAO, diffuse colour for the ambient term",
               {kDepth, kNormals, kDiffuse}});
  p.push_back({"ssao", "Ferko 5.1: 16 hemisphere-corrected samples rotated per pixel, O(d) = 1/(1+d^2), reduced resolution",
               {"ssao.raw"}});
  p.push_back({"ssao blur", "Ferko 5.2: separable cross-bilateral blur, horizontal then vertical", {"ssao"}});
  p.push_back({"apply", "the occlusion applied to the ambient term only: lit - (1 - AO) x diffuse x ambient", {"color"}});
  return p;
}

std::vector<platforms::LogicalTarget> DeferredSsao::logicalTargets(const RenderSettings& settings) const {
  std::vector<platforms::LogicalTarget> t;
  for (platforms::LogicalTarget& l : lit_.logicalTargets(settings)) {
    // The lit image is an intermediate here (RGBA32F, see prepare), planned by the lit pass.
    if (l.name == kOutputColor) l.name = "lit.color";
    t.push_back(l);
  }
  for (const platforms::LogicalTarget& g : geometryTargets(settings)) t.push_back(g);
  return t;
}

std::vector<Technique::SizedTargets> DeferredSsao::furtherTargetPlans(const RenderSettings& settings) const {
  std::vector<SizedTargets> plans = lit_.furtherTargetPlans(settings);
  const uint32_t reduction = std::max(1u, params_.reduction);
  plans.push_back({"ssao", {std::max(1u, settings.width / reduction), std::max(1u, settings.height / reduction)},
                   occlusionTargets()});
  return plans;
}

void DeferredSsao::prepare(rhi::Device& device, const RenderSettings& settings) {
  settings_ = settings;
  // The lit image stays unclamped (RGBA32F, the accumulation's values as they are): the apply
  // pass takes the occluded share of the ambient term out of it before the final format clamps.
  RenderSettings litSettings = settings;
  litSettings.colorFormat = rhi::Format::RGBA32F;
  lit_.prepare(device, litSettings);
  shaders_ = std::make_unique<ShaderLibrary>(device);
  const std::vector<platforms::LogicalTarget> logical = geometryTargets(settings);
  targets_ = std::make_unique<PlannedTargets>(device, settings, logical, "deferred-ssao");
  const platforms::TargetPlan& plan = targets_->plan();
  const rhi::ShaderCompileOptions options = targets_->shaderOptions(settings);

  rhi::PipelineDesc g;
  g.vertexShader = shaders_->load("forward/forward.vert", options);
  g.fragmentShader = shaders_->load("effects/ssao_gbuffer.frag", options);
  scene::SceneGpu::describeVertexLayout(g);
  g.raster.cull = rhi::CullMode::Back;
  g.depthStencil.depthCompare = rhi::CompareOp::Less;
  g.depthStencil.depthWrite = true;
  g.colorTargets[0].format = plan.find(kNormals)->attachmentFormat;
  g.colorTargets[1].format = plan.find(kDiffuse)->attachmentFormat;
  g.colorTargetCount = 2;
  g.depthStencilFormat = plan.find(kDepth)->attachmentFormat;
  g.label = "ssao geometry";
  geometry_ = device.createPipeline(g);

  rhi::PipelineDesc f;
  f.vertexShader = shaders_->load("platforms/fullscreen.vert", options);
  f.colorTargetCount = 1;
  const SizedTargets chain = furtherTargetPlans(settings).back();
  aoWidth_ = chain.extent.width;
  aoHeight_ = chain.extent.height;
  occlusion_ = std::make_unique<PlannedTargets>(device, settings, chain.targets, "deferred-ssao", chain.extent);
  f.colorTargets[0].format = occlusion_->format(kRawOcclusion);
  f.fragmentShader = shaders_->load("effects/ssao.frag", options);
  f.label = "ssao";
  ssao_ = device.createPipeline(f);
  f.fragmentShader = shaders_->load("effects/ssao_blur.frag", options);
  f.label = "ssao blur";
  blur_ = device.createPipeline(f);
  f.colorTargets[0].format = plan.find(kOutputColor)->attachmentFormat;
  f.fragmentShader = shaders_->load("effects/ssao_apply.frag", options);
  f.label = "ssao apply";
  apply_ = device.createPipeline(f);
  if (!geometry_ || !ssao_ || !blur_ || !apply_) throw TechniqueError("deferred-ssao: the device rejected a pipeline");

  std::vector<uint8_t> random = randomVectorTexels();
  rhi::TextureDesc r;
  r.format = rhi::Format::RGBA8;
  r.width = r.height = 4;
  r.usage = rhi::TextureUsage_Sampled;
  r.initialData = random.data();
  r.label = "ssao random vectors";
  randomVectors_ = device.createTexture(r);
  rhi::SamplerDesc s;
  s.minFilter = s.magFilter = rhi::Filter::Linear;
  s.label = "ssao upsample";
  linear_ = device.createSampler(s);
  rhi::BufferDesc pb;
  pb.size = 3 * kParamSlot;
  pb.usage = rhi::BufferUsage_Uniform;
  pb.label = "ssao pass parameters";
  passParams_ = device.createBuffer(pb);
  if (!randomVectors_ || !linear_ || !passParams_)
    throw TechniqueError("deferred-ssao: cannot create render targets");
}

rhi::TextureHandle DeferredSsao::render(rhi::Device& device, scene::SceneGpu& scene, const scene::Camera& camera) {
  rhi::TextureHandle lit = lit_.render(device, scene, camera);

  rhi::PassDesc g;
  g.colors[0].texture = targets_->attachment(kNormals);
  g.colors[1].texture = targets_->attachment(kDiffuse);
  g.depthStencil.texture = targets_->attachment(kDepth);
  g.label = "ssao geometry";
  device.beginPass(g);
  device.setPipeline(geometry_);
  for (const scene::Mesh& mesh : scene.scene().meshes) scene.drawMesh(mesh);
  device.endPass();
  for (const char* name : {kNormals, kDiffuse, kDepth})
    targets_->resolve(name);

  const float ratio = static_cast<float>(settings_.width) / static_cast<float>(aoWidth_);
  const float sigma = std::max(1.0f, params_.blurRadius / 2.0f);
  std::vector<uint8_t> slots(3 * kParamSlot, 0);
  const float ssaoParams[4] = {params_.radius, ratio, 0.0f, 0.0f};
  std::memcpy(slots.data(), ssaoParams, sizeof(ssaoParams));
  for (int axis = 0; axis < 2; ++axis) {
    BlurParams b{{axis == 0 ? 1 : 0, axis == 0 ? 0 : 1, params_.blurRadius, 0}, {0.01f, ratio, sigma, 0.0f}};
    std::memcpy(slots.data() + (1 + axis) * kParamSlot, &b, sizeof(b));
  }
  device.writeBuffer(passParams_, 0, slots.data(), slots.size());
  auto paramSlot = [&](int slot) {
    rhi::ResourceBinding b;
    b.binding = 3;
    b.kind = rhi::BindingKind::UniformBuffer;
    b.buffer = passParams_;
    b.offset = slot * kParamSlot;
    b.size = kParamSlot;
    return b;
  };
  rhi::ResourceBinding lightBlock;  // declared by scene_data.glsl, so bound although unread
  lightBlock.binding = 1;
  lightBlock.kind = rhi::BindingKind::StorageBuffer;
  lightBlock.buffer = scene.lightBuffer();
  const rhi::ResourceBinding gbuffer[] = {frameBlock(scene), lightBlock, sampled(4, targets_->readTexture(kDepth)),
                                          sampled(5, targets_->readTexture(kNormals))};
  auto fullscreen = [&](rhi::TextureHandle target, const char* label) {
    rhi::PassDesc p;
    p.colors[0].texture = target;
    p.colors[0].load = rhi::LoadOp::DontCare;
    p.label = label;
    device.beginPass(p);
  };

  fullscreen(occlusion_->attachment(kRawOcclusion), "ssao");
  device.setPipeline(ssao_);
  device.setBindings(gbuffer);
  const rhi::ResourceBinding random[] = {sampled(6, randomVectors_), paramSlot(0)};
  device.setBindings(random);
  device.draw(3);
  device.endPass();
  occlusion_->resolve(kRawOcclusion);

  const char* const chain[2][2] = {{kRawOcclusion, kBlurScratch}, {kBlurScratch, kOcclusion}};
  for (int pass = 0; pass < 2; ++pass) {
    fullscreen(occlusion_->attachment(chain[pass][1]), pass == 0 ? "ssao blur h" : "ssao blur v");
    device.setPipeline(blur_);
    device.setBindings(gbuffer);
    const rhi::ResourceBinding source[] = {sampled(6, occlusion_->readTexture(chain[pass][0])), paramSlot(1 + pass)};
    device.setBindings(source);
    device.draw(3);
    device.endPass();
    occlusion_->resolve(chain[pass][1]);
  }

  fullscreen(targets_->attachment(kOutputColor), "apply");
  device.setPipeline(apply_);
  const rhi::ResourceBinding apply[] = {frameBlock(scene), lightBlock, sampled(6, occlusion_->readTexture(kOcclusion), linear_), sampled(7, lit),
                                        sampled(8, targets_->readTexture(kDiffuse))};
  device.setBindings(apply);
  device.draw(3);
  device.endPass();
  return targets_->present();
}

std::vector<NamedTarget> DeferredSsao::targets() const {
  std::vector<NamedTarget> t;
  for (const NamedTarget& n : lit_.targets())
    if (n.name != "color") t.push_back(n);  // this technique's final colour replaces the lit one
  if (targets_) {
    t.push_back({kDepth, targets_->attachment(kDepth)});
    t.push_back({kNormals, targets_->attachment(kNormals)});
    t.push_back({kDiffuse, targets_->attachment(kDiffuse)});
  }
  if (occlusion_) {
    t.push_back({kRawOcclusion, occlusion_->readTexture(kRawOcclusion)});
    t.push_back({kOcclusion, occlusion_->readTexture(kOcclusion)});
  }
  if (targets_) t.push_back({kOutputColor, targets_->readTexture(kOutputColor)});
  return t;
}

void DeferredSsao::release(rhi::Device& device) {
  lit_.release(device);
  for (rhi::PipelineHandle p : {geometry_, ssao_, blur_, apply_}) device.destroy(p);
  device.destroy(randomVectors_);
  occlusion_.reset();
  device.destroy(linear_);
  device.destroy(passParams_);
  targets_.reset();
  shaders_.reset();
}

}  // namespace parity::techniques
