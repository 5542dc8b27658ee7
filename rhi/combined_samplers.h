// SPIRV-Cross's combined image-sampler analysis, in one place: reflection (which pairs a shader
// combines, for validation and binding) and the GL backend (which must emit GLSL sampler2D
// variables for them) call the same function, so both always see the same pairs.
#pragma once

#include <spirv_cross/spirv_cross_c.h>

#include <cstdint>
#include <vector>

#include "rhi/shader_reflection.h"

namespace parity::rhi {

struct CombinedPair {
  SeparatePair pair;
  spvc_variable_id combinedVariable = 0;  // the variable SPIRV-Cross adds for the pair
};

// Runs the analysis on `compiler` (made from `spirv`, its entry point chosen) and lists every
// combination the entry point makes, in SPIRV-Cross's order (not unique). False when SPIRV-Cross
// refuses the module.
bool combineSeparatePairs(spvc_compiler compiler, const std::vector<uint32_t>& spirv, std::vector<CombinedPair>* out);

}  // namespace parity::rhi
