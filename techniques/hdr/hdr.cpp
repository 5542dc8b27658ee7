#include "techniques/hdr/hdr.h"

#include <algorithm>

#include "techniques/common/planned_targets.h"

namespace parity::techniques {

namespace {

const char* const kAccumulation = "hdr.accumulation";
const char* const kDepth = "depth";
const char* const kBloom = "hdr.bloom";
// Where the tone-mapping shader reads bloom level l (shaders/effects/hdr_tonemap.frag).
const uint32_t kBloomBindings[HdrToneMapping::kMaxBloomLevels] = {5, 6, 7, 10, 11};

rhi::ResourceBinding sampled(uint32_t binding, rhi::TextureHandle texture, rhi::SamplerHandle sampler = {}) {
  rhi::ResourceBinding b;
  b.binding = binding;
  b.kind = rhi::BindingKind::SampledTexture;
  b.texture = texture;
  b.sampler = sampler;
  return b;
}

}  // namespace

std::vector<PassInfo> HdrToneMapping::passes() const {
  return {{"shade", "forward shading into the platform's 16-bit light accumulation target (RGBA16F; k_16_16_16_16 on x360)", {"hdr.accumulation", "depth"}},
          {"luminance", "log(delta + L) summed per 16x16 block, then the blocks summed: the log-average (compute; pixel passes where there is none)", {}},
          {"bright", "bloom source: light whose exposed luminance (key / log-average x L) is above the threshold, then halved levels of 2x2 box averages", {"hdr.bloom"}},
          {"tonemap", "Reinhard global operator on the accumulation plus the bloom summed over the levels", {"color"}}};
}

std::vector<platforms::LogicalTarget> HdrToneMapping::logicalTargets(const RenderSettings& settings) const {
  using platforms::LogicalFormat;
  using platforms::TargetRole;
  return {{kAccumulation, LogicalFormat::Rgba16Hdr, true, TargetRole::Plain, "shade"},
          {kDepth, LogicalFormat::Depth24Stencil8, false, TargetRole::Plain, "shade"},
          outputColorTarget(settings, "tonemap")};
}

std::vector<Technique::SizedTargets> HdrToneMapping::furtherTargetPlans(const RenderSettings& settings) const {
  std::vector<SizedTargets> plans = bloomPlans(settings);
  for (SizedTargets& level : LogAverageLuminance::targetPlans(settings)) plans.push_back(std::move(level));
  return plans;
}

std::vector<PortPath> HdrToneMapping::portPaths(const rhi::Capabilities& caps) const {
  if (LogAverageLuminance::usesCompute(caps)) return {};
  return {LogAverageLuminance::portPath()};
}

std::array<float, 4> HdrToneMapping::readLuminance(rhi::Device& device) const { return luminance_.read(device); }

std::vector<Technique::SizedTargets> HdrToneMapping::bloomPlans(const RenderSettings& settings) const {
  // The bloom chain starts at half resolution, as the blur it stands for would.
  const uint32_t bw = std::max(1u, settings.width / 2), bh = std::max(1u, settings.height / 2);
  std::vector<SizedTargets> levels;
  for (uint32_t l = 0; l < std::min(params_.bloomLevels, kMaxBloomLevels) && (bw >> l) > 0 && (bh >> l) > 0; ++l) {
    const std::string pass = l == 0 ? "bright" : "bloom level " + std::to_string(l);
    levels.push_back({pass, {bw >> l, bh >> l},
                      {{kBloom, platforms::LogicalFormat::Rgba16Hdr, true, platforms::TargetRole::Plain, pass}}});
  }
  return levels;
}

void HdrToneMapping::prepare(rhi::Device& device, const RenderSettings& settings) {
  settings_ = settings;
  settings_.capabilities = runnableCapabilities(device, settings);
  shaders_ = std::make_unique<ShaderLibrary>(device);
  const std::vector<platforms::LogicalTarget> logical = logicalTargets(settings_);
  targets_ = std::make_unique<PlannedTargets>(device, settings_, logical, "hdr");
  const platforms::TargetPlan& plan = targets_->plan();
  rhi::ShaderCompileOptions options = targets_->shaderOptions(settings_);
  luminance_.prepare(device, settings_, *shaders_, options, params_.delta);
  rhi::ShaderCompileOptions readsLuminance = options;
  for (const auto& d : luminance_.shaderDefines()) readsLuminance.defines.push_back(d);
  rhi::ShaderCompileOptions shadeOptions = options;
  shadeOptions.defines.push_back({"FORWARD_HDR_TARGET", "1"});

  rhi::PipelineDesc p;
  p.vertexShader = shaders_->load("forward/forward.vert", options);
  p.fragmentShader = shaders_->load("forward/forward_single_pass.frag", shadeOptions);
  scene::SceneGpu::describeVertexLayout(p);
  p.raster.cull = rhi::CullMode::Back;
  p.depthStencil.depthCompare = rhi::CompareOp::Less;
  p.depthStencil.depthWrite = true;
  p.colorTargets[0].format = plan.find(kAccumulation)->attachmentFormat;
  p.colorTargetCount = 1;
  p.depthStencilFormat = plan.find(kDepth)->attachmentFormat;
  p.label = "hdr shade";
  shade_ = device.createPipeline(p);

  rhi::PipelineDesc f;
  f.vertexShader = shaders_->load("platforms/fullscreen.vert", options);
  f.fragmentShader = shaders_->load("effects/hdr_bright.frag", readsLuminance);
  for (const SizedTargets& level : bloomPlans(settings_))
    bloom_.push_back(std::make_unique<PlannedTargets>(device, settings_, level.targets, "hdr", level.extent));
  levels_ = uint32_t(bloom_.size());
  f.colorTargets[0].format = bloom_[0]->format(kBloom);
  f.colorTargetCount = 1;
  f.label = "hdr bright";
  bright_ = device.createPipeline(f);
  f.fragmentShader = shaders_->load("effects/hdr_tonemap.frag", readsLuminance);
  f.colorTargets[0].format = plan.find(kOutputColor)->attachmentFormat;
  f.label = "hdr tonemap";
  tonemap_ = device.createPipeline(f);
  rhi::SamplerDesc s;
  s.minFilter = s.magFilter = rhi::Filter::Linear;
  s.label = "hdr bloom upsample";
  bilinear_ = device.createSampler(s);
  if (!bilinear_) throw TechniqueError("hdr: cannot create the bloom sampler");
}

rhi::TextureHandle HdrToneMapping::render(rhi::Device& device, scene::SceneGpu& scene, const scene::Camera& camera) {
  scene.setCamera(camera, static_cast<float>(settings_.width) / static_cast<float>(settings_.height));
  rhi::PassDesc pass;
  pass.colors[0].texture = targets_->attachment(kAccumulation);
  pass.colors[0].clearColor = targets_->gpu().clearColor(kAccumulation, {0.0f, 0.0f, 0.0f, 1.0f});
  pass.depthStencil.texture = targets_->attachment(kDepth);
  pass.label = "shade";
  device.beginPass(pass);
  device.setPipeline(shade_);
  for (const scene::Mesh& mesh : scene.scene().meshes) scene.drawMesh(mesh);
  device.endPass();
  targets_->resolve(kAccumulation);
  const rhi::TextureHandle accumulation = targets_->readTexture(kAccumulation);

  luminance_.record(device, accumulation);

  struct Bright {
    float params[4];
  };
  for (uint32_t l = 0; l < levels_; ++l) {
    rhi::PassDesc bp;
    bp.colors[0].texture = bloom_[l]->attachment(kBloom);
    bp.colors[0].load = rhi::LoadOp::DontCare;
    bp.label = l == 0 ? "bright" : "bloom level " + std::to_string(l);
    device.beginPass(bp);
    device.setPipeline(bright_);
    // Level 0 takes the threshold of the accumulation at half resolution: each texel reads the
    // top-left pixel of its 2x2 block, then the chain averages 2x2 blocks of the level above.
    const rhi::ResourceBinding source[] = {sampled(4, l == 0 ? accumulation : bloom_[l - 1]->readTexture(kBloom)),
                                           luminance_.result(9)};
    device.setBindings(source);
    Bright b{{params_.bloomThreshold, l == 0 ? 1.0f : 0.0f, params_.key, 0}};
    device.pushConstants(&b, sizeof(b));
    device.draw(3);
    device.endPass();
    bloom_[l]->resolve(kBloom);
  }

  rhi::PassDesc tp;
  tp.colors[0].texture = targets_->attachment(kOutputColor);
  tp.colors[0].load = rhi::LoadOp::DontCare;
  tp.label = "tonemap";
  device.beginPass(tp);
  device.setPipeline(tonemap_);
  std::vector<rhi::ResourceBinding> tb = {sampled(4, accumulation), luminance_.result(9)};
  for (uint32_t l = 0; l < kMaxBloomLevels; ++l)  // unused bindings repeat the last level
    tb.push_back(sampled(kBloomBindings[l], bloom_[std::min(l, levels_ - 1)]->readTexture(kBloom), bilinear_));
  device.setBindings(tb);
  float tonemap[4] = {params_.key, params_.bloomStrength, static_cast<float>(levels_), 0.0f};
  device.pushConstants(tonemap, sizeof(tonemap));
  device.draw(3);
  device.endPass();
  return targets_->present();
}

std::vector<NamedTarget> HdrToneMapping::targets() const {
  if (!targets_) return {};
  return {{kAccumulation, targets_->attachment(kAccumulation)},
          {kDepth, targets_->attachment(kDepth)},
          {kBloom, bloom_.empty() ? rhi::TextureHandle{} : bloom_[0]->attachment(kBloom)},
          {kOutputColor, targets_->readTexture(kOutputColor)}};
}

void HdrToneMapping::release(rhi::Device& device) {
  for (rhi::PipelineHandle p : {shade_, bright_, tonemap_}) device.destroy(p);
  luminance_.release(device);
  bloom_.clear();
  targets_.reset();
  device.destroy(bilinear_);
  shaders_.reset();
}

}  // namespace parity::techniques
