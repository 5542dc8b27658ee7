// What a shader_test needs to know of a compiled module that OpenGL would tell by name: the
// location of a vertex input, and where a loose uniform lives in the default uniform block that
// glslang's relaxed rules gather them into (rhi::ShaderCompileOptions::openGlSource).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "harness/scripts/script.h"

namespace parity::harness::script {

// The Location of the Input variable called `name`; nothing when there is none.
std::optional<uint32_t> inputLocation(const std::vector<uint32_t>& spirv, const std::string& name);

// Whether the module declares a GroupNonUniform* capability (subgroup operations).
bool usesSubgroupOperations(const std::vector<uint32_t>& spirv);

// The module's OpExtension names ("SPV_KHR_subgroup_uniform_control_flow", ...).
std::vector<std::string> spirvExtensions(const std::vector<uint32_t>& spirv);

// The resource variables (with a Binding) that are arrays: several descriptors at one binding.
struct DescriptorArray {
  std::string name;
  uint32_t elements = 0;  // 0: unsized, or sized by a specialization constant
  bool nested = false;    // an array of arrays
  bool samplers = false;  // of separate samplers (`uniform sampler s[2]`)
};
std::vector<DescriptorArray> descriptorArrays(const std::vector<uint32_t>& spirv);

// The module's uniform blocks (Uniform variables of Block structs), with where their
// DescriptorSet and Binding operands lie, so that a caller can move them.
struct UniformBlockVariable {
  std::string typeName;  // the block's name ("gl_DefaultUniformBlock" for loose uniforms)
  uint32_t size = 0;     // bytes (of one element)
  uint32_t elements = 1; // an array of blocks: its length
  size_t setWord = 0, bindingWord = 0;  // indices into the module's words (0: not decorated)
};
std::vector<UniformBlockVariable> uniformBlocks(const std::vector<uint32_t>& spirv);

// The module's storage-buffer blocks (StorageBuffer variables of structs), in the same form
// (glslang's relaxed rules put the atomic counters of OpenGL binding N in "gl_AtomicCounterBlock_N").
std::vector<UniformBlockVariable> storageBlocks(const std::vector<uint32_t>& spirv);

// The module's located Input and Output variables other than built-ins, named as OpenGL links
// them across stages (a block by its block name), with where their Location and Component
// operands lie.
struct InterfaceVariable {
  std::string name;
  bool output = false, patch = false;
  uint32_t location = 0, component = 0;
  size_t locationWord = 0, componentWord = 0;  // indices into the module's words (0: not decorated)
};
std::vector<InterfaceVariable> interfaceVariables(const std::vector<uint32_t>& spirv);

// Where the module's located outputs end: the largest Location plus the locations the variable's
// type takes (a tessellation control shader's per-vertex outputs counted for one vertex:
// `perVertexOutputs`), and that variable's name; {0, ""} without located outputs.
struct OutputExtent {
  uint32_t end = 0;
  std::string name;
};
OutputExtent outputExtent(const std::vector<uint32_t>& spirv, bool perVertexOutputs);

// The members of the module's built-in block (gl_PerVertex) of Output (`output`) or Input
// variables, as GLSL member declarations in their order ("vec4 gl_Position;", "float
// gl_ClipDistance[2];", ...): what a generated neighbour stage redeclares to match it.
std::vector<std::string> perVertexMembers(const std::vector<uint32_t>& spirv, bool output);

// Whether the module declares an output of SPIR-V built-in `builtIn` (a variable or a member of
// an output block such as gl_PerVertex).
bool outputsBuiltIn(const std::vector<uint32_t>& spirv, uint32_t builtIn);
inline constexpr uint32_t kBuiltInViewportIndex = 10;

// The module's combined image-sampler and storage image variables (OpenGL's sampler and image
// uniforms), with where their DescriptorSet and Binding operands lie.
struct SamplerVariable {
  std::string name;
  uint32_t elements = 1;  // an array of samplers: its length
  bool storageImage = false;  // an image uniform (image2D, ...), not a sampler
  size_t setWord = 0, bindingWord = 0;  // indices into the module's words (0: not decorated)
  // The image type's shape: its SPIR-V Dim (0 1D, 1 2D, 2 3D, 3 Cube, 4 Rect, 5 Buffer, ...),
  // Arrayed, Depth and MS operands, and what a texel holds.
  uint32_t dim = 1;
  bool arrayed = false, depth = false, multisampled = false;
  enum class Texel : uint8_t { Float, Int, UInt } texel = Texel::Float;
};
std::vector<SamplerVariable> samplerVariables(const std::vector<uint32_t>& spirv);

// Renames the OpName `from` of a struct type to `to` (OpenGL links blocks of different stages by
// these names). False when no struct has that name.
bool renameStruct(std::vector<uint32_t>& spirv, const std::string& from, const std::string& to);

struct UniformBlockInfo {
  uint32_t set = 0, binding = 0;
  uint32_t size = 0;  // bytes
};
// The uniform block whose type is named `typeName` (e.g. "gl_DefaultUniformBlock").
std::optional<UniformBlockInfo> findUniformBlock(const std::vector<uint32_t>& spirv, const std::string& typeName);

// Where one uniform (a member path such as "color", "a[2]", "s.f", "m[1].v") of that block lies:
// `elements` elements (arrays: from the indexed one to the end) of `columns` columns of `rows`
// scalars.
struct UniformSlot {
  uint32_t offset = 0;
  Scalar scalar = Scalar::Float32;
  uint32_t rows = 1, columns = 1;
  uint32_t matrixStride = 0, arrayStride = 0, elements = 1;
  bool rowMajor = false;  // a matrix decorated RowMajor: matrixStride separates its rows
};
std::optional<UniformSlot> findUniform(const std::vector<uint32_t>& spirv, const std::string& typeName, const std::string& path);

}  // namespace parity::harness::script
