#include "techniques/common/planned_targets.h"

namespace parity::techniques {

platforms::LogicalTarget outputColorTarget(const RenderSettings& settings, const std::string& pass) {
  platforms::LogicalTarget t;
  t.name = kOutputColor;
  t.format = platforms::LogicalFormat::Output;
  t.readLater = true;  // the harness reads it: on x360 it is resolved out of EDRAM
  t.pass = pass;
  t.outputFormat = settings.colorFormat;
  return t;
}

platforms::LogicalTarget sceneDepthTarget(const std::string& pass, bool readLater, bool stencil) {
  platforms::LogicalTarget t;
  t.name = kSceneDepth;
  t.format = platforms::LogicalFormat::Depth24Stencil8;
  t.readLater = readLater;
  t.pass = pass;
  t.stencil = stencil;
  return t;
}

PlannedTargets::PlannedTargets(rhi::Device& device, const RenderSettings& settings,
                               const std::vector<platforms::LogicalTarget>& logical, const std::string& technique,
                               TargetExtent extent)
    : technique_(technique) {
  if (extent.width == 0 || extent.height == 0) extent = {settings.width, settings.height};
  const platforms::TargetPlan plan =
      platforms::planTargets(settings.platform, logical, extent.width, extent.height, settings.platformParams);
  targets_ = std::make_unique<platforms::GpuTargets>(device, plan);
  for (const platforms::LogicalTarget& t : logical)
    if (!targets_->attachment(t.name) || !targets_->readTexture(t.name))
      throw TechniqueError(technique + ": cannot create target '" + t.name + "'");
}

rhi::Format PlannedTargets::format(const std::string& name) const {
  const platforms::PhysicalTarget* t = plan().find(name);
  return t ? t->attachmentFormat : rhi::Format::Undefined;
}

rhi::ShaderCompileOptions PlannedTargets::shaderOptions(const RenderSettings& settings) const {
  return mergeShaderOptions(settings.shaderOptions, platforms::platformShaderOptions(plan()));
}

void PlannedTargets::resolve(const std::string& name, uint32_t sourceSamples, const rhi::Rect& rect) {
  if (!targets_->resolve(name, sourceSamples, rect))
    throw TechniqueError(technique_ + ": resolve of '" + name + "' failed: " + targets_->error());
}

rhi::TextureHandle PlannedTargets::present(const std::string& name) {
  resolve(name);
  return targets_->readTexture(name);
}

}  // namespace parity::techniques
