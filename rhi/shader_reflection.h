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
  // Elements of a descriptor array (`sampler2D s[4]`: 4); 1 for a binding that is no array.
  uint32_t arraySize = 1;
  // Texture kinds (SampledTexture, StorageTexture, SeparateTexture):
  bool multisampled = false;  // sampler2DMS / texture2DMS
  bool arrayed = false;       // sampler2DArray / texture2DArray
  bool cube = false;          // samplerCube / textureCube
  uint32_t dimensions = 2;    // 1: sampler1D / image1D, 3: sampler3D / image3D; 2 otherwise
  bool depthCompare = false;  // SampledTexture: sampler2DShadow
  bool integer = false;       // usampler / uimage / utexture
};

// A SeparateTexture and a SeparateSampler the shader combines (`sampler2D(tex, smp)`), as
// SPIRV-Cross's combined-image-sampler analysis finds them. A texture read without a sampler
// (texelFetch on a texture2D) has samplerBinding kNoSamplerBinding.
constexpr uint32_t kNoSamplerBinding = 0xFFFFFFFFu;
struct SeparatePair {
  uint32_t textureBinding = 0;
  uint32_t samplerBinding = kNoSamplerBinding;
  bool depthCompare = false;  // combined as a shadow sampler (sampler2DShadow(tex, smp))
  bool operator==(const SeparatePair&) const = default;
};

struct ShaderReflection {
  ShaderStage stage = ShaderStage::Vertex;
  std::vector<ShaderResource> resources;  // sorted by binding
  std::vector<SeparatePair> separatePairs;  // sorted by (textureBinding, samplerBinding), unique
  uint32_t pushConstantSize = 0;          // bytes, 0 when the module declares none
  std::vector<uint32_t> inputLocations;   // vertex stage: attribute locations read
  // Vertex stage: the inputs whose vectors take two locations each (64-bit vectors of three or
  // four components: dvec3, dvec4, matrices and arrays of them), as (first location, vectors).
  // OpenGL gives each such vector one location from the first; the GL backend feeds it there.
  std::vector<std::pair<uint32_t, uint32_t>> doubleWideInputs;
  uint32_t colorOutputs = 0;              // fragment stage: bit i set when location i is written
  std::array<uint32_t, 3> localSize{1, 1, 1};  // compute
  // Stages before rasterisation: the size of the gl_ClipDistance array the module outputs (0:
  // none). Vulkan clips by each of them; GL only by those enabled (the GL backend enables these).
  uint32_t clipDistances = 0;
  // Vertex stage: the module declares BuiltIn BaseVertex (gl_BaseVertex), which Vulkan defines as
  // firstVertex for non-indexed draws and GL as 0 there (the GL backend draws those indexed).
  bool readsBaseVertex = false;
};

// Calls visit(op, at, words) for each instruction of the module after its header: `at` indexes
// the instruction's first word, `words` is its length. Stops at a malformed instruction.
template <class Visit>
void forEachInstruction(const std::vector<uint32_t>& spirv, Visit&& visit) {
  for (size_t i = 5; i < spirv.size();) {
    const uint32_t words = spirv[i] >> 16, op = spirv[i] & 0xFFFF;
    if (words == 0 || i + words > spirv.size()) return;
    visit(op, i, words);
    i += words;
  }
}

// The literal string of an instruction's operands from word `from` up to `end` (nul-terminated,
// four characters a word, the first in the low byte).
inline std::string spirvLiteralString(const std::vector<uint32_t>& spirv, size_t from, size_t end) {
  std::string out;
  for (size_t w = from; w < end && w < spirv.size(); ++w)
    for (int byte = 0; byte < 4; ++byte) {
      const char ch = static_cast<char>((spirv[w] >> (8 * byte)) & 0xFF);
      if (ch == 0) return out;
      out += ch;
    }
  return out;
}

// Returns false and sets *error (one line) when the module cannot be parsed or breaks the
// binding model of rhi.h (a set other than 0, a binding >= kMaxBindings, more than
// kMaxSeparatePairs separate texture/sampler pairs, a descriptor array that is unsized, of
// arrays or of more than kMaxArrayElements, ...).
bool reflectSpirv(const std::vector<uint32_t>& spirv, ShaderStage stage, ShaderReflection* out,
                  std::string* error);

// Whether the module combines the separate texture variable `imageVar` and sampler variable
// `samplerVar` as a shadow sampler (an OpSampledImage of a depth image type whose operands are
// loaded from the two variables). Pairs combined inside functions that receive the texture or
// sampler as parameters are not traced and count as non-shadow.
bool sampledAsShadow(const std::vector<uint32_t>& spirv, uint32_t imageVar, uint32_t samplerVar);

// The union of the stages' separate texture/sampler pairs, sorted and unique: the pairs of a
// pipeline (on GL, pair k is texture unit kMaxBindings + k).
std::vector<SeparatePair> mergeSeparatePairs(const std::vector<const ShaderReflection*>& stages);

}  // namespace parity::rhi
