// OpenGL's names of a uniform's type (glGetActiveUniformsiv's GL_UNIFORM_TYPE, as piglit's
// `active uniform NAME GL_UNIFORM_TYPE GL_FLOAT_VEC4` writes them), read from a port's SPIR-V.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "harness/scripts/script.h"

namespace parity::harness::script {

// A scalar, vector or matrix of `columns` columns of `rows` components: "GL_FLOAT_VEC3",
// "GL_FLOAT_MAT2x3", "GL_UNSIGNED_INT", "GL_DOUBLE_MAT4" ... nullopt for a scalar type OpenGL
// has no uniform type of (8- and 16-bit ones). A 32-bit unsigned integer is GL_UNSIGNED_INT*:
// glslang stores a block's booleans as such, so a port cannot tell them from bools.
std::optional<std::string> openGlValueTypeName(Scalar scalar, uint32_t rows, uint32_t columns);

// The type of the sampler or image variable `name` of the module, read with SPIRV-Cross
// ("GL_SAMPLER_2D", "GL_INT_SAMPLER_CUBE", "GL_UNSIGNED_INT_IMAGE_2D_ARRAY", ...); nullopt when
// the module has no such variable.
std::optional<std::string> openGlOpaqueTypeName(const std::vector<uint32_t>& spirv, const std::string& name);

}  // namespace parity::harness::script
