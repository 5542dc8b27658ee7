// Edits of a SPIR-V module before it becomes a pipeline: Amber's SHADER_OPTIMIZATION passes, the
// remapping of a script's descriptor sets and bindings onto the RHI's one set, and specialisation
// constants written into the module.
#pragma once

#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace parity::harness::script::runner {

// (set, binding) of a script's descriptor.
using SetBinding = std::pair<uint32_t, uint32_t>;

// SHADER_OPTIMIZATION: the named spirv-opt passes, in order, as Amber runs them on the module
// before the pipeline is made. Amber's documentation writes the flags with and without "--".
void optimizeSpirv(std::vector<uint32_t>& module, const std::vector<std::string>& passes, const std::string& shader);

std::set<SetBinding> spirvBindings(const std::vector<uint32_t>& spirv);

void remapSpirv(std::vector<uint32_t>& spirv, const std::map<SetBinding, uint32_t>& map);

// OpenGL's SPIR-V (GL_ARB_gl_spirv) decorates resources with a Binding and no DescriptorSet, which
// Vulkan requires: DescriptorSet 0, OpenGL's one set, is added where it is missing.
void addMissingDescriptorSets(std::vector<uint32_t>& spirv);

// OpenGL's SPIR-V may give a uniform (a sampler, say) a Location, its glUniform location, which
// Vulkan forbids outside inputs and outputs: those decorations go (the Binding places it).
void dropUniformLocations(std::vector<uint32_t>& spirv);

// OpenGL's SPIR-V fragment shaders may say OriginLowerLeft, which Vulkan forbids. OpenGL's window
// origin is its first row, the bottom, and so is the RHI's (gl_FragCoord.y = 0.5 is row 0,
// rhi/rhi.h): in the RHI's terms that is OriginUpperLeft, which the module gets instead.
void originAtFirstRow(std::vector<uint32_t>& spirv);

// The name (or %id) of a UniformConstant variable that is not opaque (no image, sampler or
// acceleration structure): OpenGL's loose uniforms, which Vulkan has no place for. Empty if none.
std::string looseUniformOf(const std::vector<uint32_t>& spirv);

// SPECIALIZE: the default value of each OpSpecConstant whose SpecId is given is replaced in the
// module itself, so both backends see constants with those values and neither API's
// specialization mechanism is needed (GL's glSpecializeShader takes no SPIR-V through
// SPIRV-Cross; on GL the cross-compiled GLSL keeps the defaults as its constants).
void specializeSpirv(std::vector<uint32_t>& spirv, const std::map<uint32_t, uint32_t>& values, const std::string& shader);

}  // namespace parity::harness::script::runner
