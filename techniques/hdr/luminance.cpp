#include "techniques/hdr/luminance.h"

#include <cstring>

#include "techniques/common/pass_helpers.h"

namespace parity::techniques {

namespace {

const char* const kLevel = "hdr.luminance";
constexpr uint32_t kBlock = 16;      // hdr_luminance.comp's block and workgroup: 16 x 16 pixels
constexpr uint32_t kPartials = 256;  // its second dispatch's invocations
// hdr_luminance_chain.frag's modes.
constexpr int kFoldImage = 0, kFoldLevel = 1, kSumPartials = 2, kResult = 3;

struct Chain {
  int32_t block[4];  // xy: block size in the source, zw: offset of the texel added
  int32_t image[4];  // xy: the HDR image size, z: the partial sums, w: the mode
  float params[4];   // x: delta
};

}  // namespace

PortPath LogAverageLuminance::portPath() {
  return {"luminance",
          "pixel passes: 16x16 blocks folded in half eight times, the blocks' sums folded over 256 texels eight "
          "times, in the compute tree's order (the same float bit for bit)",
          platforms::Capability::Compute};
}

// The compute tree adds, within a 16x16 block (invocation x + 16 y), rows 8 apart, then 4, 2, 1,
// then columns 8 apart, 4, 2, 1: each fold below is one of those strides, a level a pass.
std::vector<LogAverageLuminance::Step> LogAverageLuminance::chain(const RenderSettings& settings) {
  std::vector<Step> steps;
  if (usesCompute(settings.capabilities)) return steps;
  const uint32_t bx = (settings.width + kBlock - 1) / kBlock, by = (settings.height + kBlock - 1) / kBlock;
  int32_t w = kBlock, h = kBlock;
  auto fold = [&](int mode, uint32_t blocksX, uint32_t blocksY, int32_t dx, int32_t dy) {
    steps.push_back({mode, {w, h, dx, dy}, {blocksX * uint32_t(w - dx), blocksY * uint32_t(h - dy)}});
    w -= dx;
    h -= dy;
  };
  for (int32_t d = kBlock / 2; d >= 1; d /= 2) fold(steps.empty() ? kFoldImage : kFoldLevel, bx, by, 0, d);
  for (int32_t d = kBlock / 2; d >= 1; d /= 2) fold(kFoldLevel, bx, by, d, 0);
  steps.push_back({kSumPartials, {int32_t(bx), 0, 0, 0}, {kPartials, 1}});
  w = kPartials;
  h = 1;
  for (int32_t d = kPartials / 2; d >= 1; d /= 2) fold(kFoldLevel, 1, 1, d, 0);
  steps.push_back({kResult, {0, 0, 0, 0}, {4, 1}});
  return steps;
}

std::vector<Technique::SizedTargets> LogAverageLuminance::targetPlans(const RenderSettings& settings) {
  std::vector<Technique::SizedTargets> plans;
  const std::vector<Step> steps = chain(settings);
  for (size_t i = 0; i < steps.size(); ++i) {
    const std::string pass = "luminance " + std::to_string(i + 1);
    plans.push_back({pass, steps[i].extent, {{kLevel, platforms::LogicalFormat::R32Float, true, platforms::TargetRole::Plain, pass}}});
  }
  return plans;
}

void LogAverageLuminance::prepare(rhi::Device& device, const RenderSettings& settings, ShaderLibrary& shaders,
                                  const rhi::ShaderCompileOptions& options, float delta) {
  settings_ = settings;
  delta_ = delta;
  compute_ = usesCompute(settings.capabilities);
  if (compute_) {
    rhi::ComputePipelineDesc c;
    c.computeShader = shaders.load("effects/hdr_luminance.comp", options);
    c.label = "hdr luminance";
    reduce_ = device.createComputePipeline(c);
    blockCount_ = ((settings.width + kBlock - 1) / kBlock) * ((settings.height + kBlock - 1) / kBlock);
    rhi::BufferDesc pb;
    pb.size = sizeof(float) * blockCount_;
    pb.usage = rhi::BufferUsage_Storage;
    pb.label = "hdr luminance partial sums";
    partials_ = device.createBuffer(pb);
    pb.size = 16;
    pb.label = "hdr luminance result";
    result_ = device.createBuffer(pb);
    if (!reduce_ || !partials_ || !result_) throw TechniqueError("hdr: cannot create the luminance reduction");
    return;
  }
  steps_ = chain(settings);
  for (const Technique::SizedTargets& level : targetPlans(settings))
    levels_.push_back(std::make_unique<PlannedTargets>(device, settings, level.targets, "hdr", level.extent));
  rhi::PipelineDesc f;
  f.vertexShader = shaders.load("platforms/fullscreen.vert", options);
  f.fragmentShader = shaders.load("effects/hdr_luminance_chain.frag", options);
  f.colorTargets[0].format = levels_.front()->format(kLevel);
  f.colorTargetCount = 1;
  f.label = "hdr luminance chain";
  fold_ = device.createPipeline(f);
  if (!fold_) throw TechniqueError("hdr: the device rejected the luminance chain's pipeline");
}

void LogAverageLuminance::record(rhi::Device& device, rhi::TextureHandle hdrImage) {
  struct Reduce {
    uint32_t mode[4];
    float params[4];
  };
  if (compute_) {
    device.setComputePipeline(reduce_);
    const rhi::ResourceBinding bindings[] = {sampled(4, hdrImage), storageBuffer(8, partials_), storageBuffer(9, result_)};
    device.setBindings(bindings);
    Reduce blocks{{0, blockCount_, settings_.width, settings_.height}, {delta_, 0, 0, 0}};
    device.pushConstants(&blocks, sizeof(blocks));
    device.dispatch(blockCount_);
    Reduce total{{1, blockCount_, settings_.width, settings_.height}, {delta_, 0, 0, 0}};
    device.pushConstants(&total, sizeof(total));
    device.dispatch(1);
    return;
  }
  const int32_t blocks =
      int32_t(((settings_.width + kBlock - 1) / kBlock) * ((settings_.height + kBlock - 1) / kBlock));
  for (size_t i = 0; i < steps_.size(); ++i) {
    const Step& s = steps_[i];
    rhi::PassDesc pass;
    pass.colors[0].texture = levels_[i]->attachment(kLevel);
    pass.colors[0].load = rhi::LoadOp::DontCare;
    pass.label = "luminance " + std::to_string(i + 1);
    device.beginPass(pass);
    device.setPipeline(fold_);
    const rhi::ResourceBinding source[] = {sampled(4, i == 0 ? hdrImage : levels_[i - 1]->readTexture(kLevel))};
    device.setBindings(source);
    Chain c{{s.block[0], s.block[1], s.block[2], s.block[3]},
            {int32_t(settings_.width), int32_t(settings_.height), blocks, s.mode},
            {delta_, 0, 0, 0}};
    device.pushConstants(&c, sizeof(c));
    device.draw(3);
    device.endPass();
    levels_[i]->resolve(kLevel);
  }
}

rhi::ResourceBinding LogAverageLuminance::result(uint32_t binding) const {
  return compute_ ? storageBuffer(binding, result_) : sampled(binding, levels_.back()->readTexture(kLevel));
}

std::vector<std::pair<std::string, std::string>> LogAverageLuminance::shaderDefines() const {
  if (compute_) return {};
  return {{"HDR_LUMINANCE_TEXTURE", "1"}};
}

std::array<float, 4> LogAverageLuminance::read(rhi::Device& device) const {
  std::array<float, 4> out{};
  std::vector<uint8_t> bytes;
  if (compute_) {
    bytes = device.readBuffer(result_, 0, 16);
  } else {
    // Row 0 first: its first four texels (a console's resolved texture may be padded).
    bytes = device.readTexture(levels_.back()->readTexture(kLevel));
  }
  if (bytes.size() >= sizeof(out)) std::memcpy(out.data(), bytes.data(), sizeof(out));
  return out;
}

void LogAverageLuminance::release(rhi::Device& device) {
  if (reduce_) device.destroy(reduce_);
  if (fold_) device.destroy(fold_);
  reduce_ = {};
  fold_ = {};
  if (partials_) device.destroy(partials_);
  if (result_) device.destroy(result_);
  partials_ = result_ = {};
  levels_.clear();
  steps_.clear();
}

}  // namespace parity::techniques
