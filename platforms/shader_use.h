// What the platform rules need of a shader module (platform_rules.h): the resources its code
// really uses (a binding it declares and never reads is no read of what is bound there), whether
// it samples with filtered lookups (texture(), textureGather: not texelFetch), and whether it reads
// interpolated inputs (a fragment shader's coordinates carried from the vertices); and what the
// capability rules (capability_rules.h) count: workgroup-shared memory, atomics, the storage
// buffers and images the code writes, the interpolators a fragment shader reads.
#pragma once

#include <array>
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
  uint32_t inputLocations = 0;    // locations (vec4 slots) those inputs take
  uint32_t sharedBytes = 0;       // Workgroup variables (compute)
  std::array<uint32_t, 3> localSize{1, 1, 1};  // compute
  bool atomics = false;           // any atomic instruction
  std::vector<uint32_t> writtenBindings;  // storage buffers and images the code writes, sorted
};

// Reads `spirv` (a module reflectSpirv cannot parse uses no resources).
ShaderUse shaderUse(const std::vector<uint32_t>& spirv, rhi::ShaderStage stage);

}  // namespace parity::platforms
