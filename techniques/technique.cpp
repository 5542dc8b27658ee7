#include "techniques/technique.h"

#include <filesystem>

#include "techniques/forward/forward.h"
#include "techniques/forward_multipass/forward_multipass.h"

namespace parity::techniques {

const std::vector<TechniqueEntry>& techniqueRegistry() {
  static const std::vector<TechniqueEntry> registry = {
      {"forward", "single-pass forward shading: ambient, one directional and N point/spot lights in one shader",
       [] { return std::make_unique<ForwardSinglePass>(); }},
      {"forward-multipass",
       "multi-pass forward shading (thesis 3.1.3): ambient + directional pass, then one additive pass per light "
       "over its light list",
       [] { return std::make_unique<ForwardMultiPass>(); }},
  };
  return registry;
}

std::unique_ptr<Technique> createTechnique(const std::string& name) {
  for (const TechniqueEntry& e : techniqueRegistry())
    if (e.name == name) return e.create();
  return nullptr;
}

ShaderLibrary::~ShaderLibrary() {
  for (rhi::ShaderHandle h : shaders_) device_.destroy(h);
}

rhi::ShaderHandle ShaderLibrary::load(const std::string& path, const rhi::ShaderCompileOptions& options) {
  rhi::ShaderStage stage;
  if (!rhi::stageFromPath(path, &stage)) throw TechniqueError(path + ": error: unknown shader stage (extension)");
  std::string full = (std::filesystem::path(rhi::shaderDirectory()) / path).string();
  rhi::CompiledShader compiled = rhi::compileGlslFile(full, stage, options);
  if (!compiled.ok()) throw TechniqueError(compiled.error);
  rhi::ShaderDesc desc;
  desc.stage = stage;
  desc.spirv = std::move(compiled.spirv);
  desc.label = path;
  rhi::ShaderHandle h = device_.createShader(desc);
  if (!h) throw TechniqueError(path + ": error: the device rejected the shader");
  shaders_.push_back(h);
  return h;
}

}  // namespace parity::techniques
