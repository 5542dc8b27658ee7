// Rewrites that both backends apply to a module before they use it: constructs that a driver or
// the GL translator gets wrong, replaced by equivalents that every one of them gets right. Each
// rewrite leaves every result of the module unchanged, and each one the backend applies is
// reported (Device::takeNotes), so that a script's author sees what ran.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace parity::rhi {

// GLSL.std.450 Ldexp whose exponent is an 8-, 16- or 64-bit signed integer takes a 32-bit one:
// the exponent is clamped to the 32-bit range first (64-bit) and converted. No float format has
// an exponent range near 2^31, so ldexp(x, e) is the same for e and for the clamped e (0, ±inf or
// x itself for x = 0, ±inf, NaN). Why: lavapipe (Mesa 22.3, LLVM 15) crashes compiling ldexp with
// a non-32-bit exponent, and SPIRV-Cross's GLSL converts a 64-bit exponent to int by truncation
// (-9223372036854775803 becomes 5). Returns a one-line note of what changed, or "" when the
// module has no such ldexp (it is then left as it was).
std::string narrowLdexpExponents(std::vector<uint32_t>& spirv);

// SPV_AMD_shader_trinary_minmax's min3, max3 and mid3 (GLSL's GL_AMD_shader_trinary_minmax) as
// GLSL.std.450 min and max: min3(a, b, c) = min(min(a, b), c), max3 likewise, and
// mid3(a, b, c) = max(min(a, b), min(max(a, b), c)), the same values (NaN aside, which neither
// defines); the extension and its import leave the module. Why: few Vulkan drivers offer
// VK_AMD_shader_trinary_minmax (lavapipe does not), while GL drivers take the GLSL directly.
// Returns a one-line note, or "" when the module uses none (it is then left as it was).
std::string expandTrinaryMinMax(std::vector<uint32_t>& spirv);

// Every rewrite above, in order; returns their notes joined by "; ", or "".
std::string lowerForDrivers(std::vector<uint32_t>& spirv);

}  // namespace parity::rhi
