// What the platform rules need of a shader module (platform_rules.h): the resources its code
// really uses (a binding it declares and never reads is no read of what is bound there), whether
// it samples with filtered lookups (texture(), textureGather: not texelFetch), and whether it reads
// interpolated inputs (a fragment shader's coordinates carried from the vertices).
#pragma once

#include <vector>

#include "rhi/rhi.h"
#include "rhi/shader_reflection.h"

namespace parity::platforms {

struct ShaderUse {
  rhi::ShaderStage stage = rhi::ShaderStage::Vertex;
  std::vector<rhi::ShaderResource> resources;  // those its functions use
  std::vector<rhi::SeparatePair> pairs;
  bool filteredSampling = false;  // OpImageSample* or OpImage*Gather
  bool userInputs = false;        // Input variables that are no built-in
};

// Reads `spirv` (a module reflectSpirv cannot parse uses no resources).
ShaderUse shaderUse(const std::vector<uint32_t>& spirv, rhi::ShaderStage stage);

}  // namespace parity::platforms
