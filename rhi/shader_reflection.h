// What a SPIR-V module declares, read with SPIRV-Cross: both backends build their binding
// tables from it (Vulkan descriptor set layouts, GL binding points), and validation checks
// draws against it.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "rhi/rhi.h"

namespace parity::rhi {

struct ShaderResource {
  uint32_t binding = 0;
  BindingKind kind = BindingKind::UniformBuffer;
  std::string name;
  bool multisampled = false;  // SampledTexture: sampler2DMS
  bool arrayed = false;       // SampledTexture: sampler2DArray
  bool cube = false;          // SampledTexture: samplerCube
  bool depthCompare = false;  // SampledTexture: sampler2DShadow
  bool integer = false;       // SampledTexture/StorageTexture: usampler / uimage
};

struct ShaderReflection {
  ShaderStage stage = ShaderStage::Vertex;
  std::vector<ShaderResource> resources;  // sorted by binding
  uint32_t pushConstantSize = 0;          // bytes, 0 when the module declares none
  std::vector<uint32_t> inputLocations;   // vertex stage: attribute locations read
  uint32_t colorOutputs = 0;              // fragment stage: bit i set when location i is written
  std::array<uint32_t, 3> localSize{1, 1, 1};  // compute
};

// Returns false and sets *error (one line) when the module cannot be parsed or breaks the
// binding model of rhi.h (a set other than 0, a binding >= kMaxBindings, ...).
bool reflectSpirv(const std::vector<uint32_t>& spirv, ShaderStage stage, ShaderReflection* out,
                  std::string* error);

}  // namespace parity::rhi
