#include "platforms/shader_use.h"

#include <map>
#include <set>
#include <string>

namespace parity::platforms {

namespace {
constexpr uint32_t kOpFunction = 54, kOpVariable = 59, kOpDecorate = 71;
constexpr uint32_t kDecorationBuiltIn = 11, kDecorationBinding = 33, kStorageInput = 1;

// OpImageSampleImplicitLod .. OpImageSampleProjDrefExplicitLod, OpImageGather, OpImageDrefGather.
bool isFilteredSample(uint32_t op) { return (op >= 87 && op <= 94) || op == 96 || op == 97; }
}  // namespace

ShaderUse shaderUse(const std::vector<uint32_t>& spirv, rhi::ShaderStage stage) {
  ShaderUse use;
  use.stage = stage;
  rhi::ShaderReflection r;
  std::string error;
  if (rhi::reflectSpirv(spirv, stage, &r, &error)) {
    use.resources = r.resources;
    use.pairs = r.separatePairs;
  }
  // A variable's id among a function's operands is a use of its binding; a literal of the same
  // value counts too, which can only keep a resource, never drop one.
  std::set<uint32_t> inputs, builtIns, used;
  std::map<uint32_t, uint32_t> bindingOf;  // variable id -> binding
  bool inFunctions = false;
  rhi::forEachInstruction(spirv, [&](uint32_t op, size_t at, uint32_t words) {
    if (isFilteredSample(op)) use.filteredSampling = true;
    if (op == kOpVariable && words >= 4 && spirv[at + 3] == kStorageInput) inputs.insert(spirv[at + 2]);
    if (op == kOpDecorate && words >= 3 && spirv[at + 2] == kDecorationBuiltIn) builtIns.insert(spirv[at + 1]);
    if (op == kOpDecorate && words >= 4 && spirv[at + 2] == kDecorationBinding) bindingOf[spirv[at + 1]] = spirv[at + 3];
    inFunctions = inFunctions || op == kOpFunction;
    if (inFunctions)
      for (uint32_t w = 1; w < words; ++w)
        if (auto b = bindingOf.find(spirv[at + w]); b != bindingOf.end()) used.insert(b->second);
  });
  for (uint32_t v : inputs) use.userInputs = use.userInputs || !builtIns.count(v);
  std::erase_if(use.resources, [&](const rhi::ShaderResource& res) { return !used.count(res.binding); });
  return use;
}

}  // namespace parity::platforms
