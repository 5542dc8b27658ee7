// ARB assembly programs (ARB_vertex_program, ARB_fragment_program) as Vulkan GLSL 4.50: the port
// a device without an assembly program path runs. What a program reads of OpenGL's state comes
// from one uniform block (ArbStateBlock) that the caller fills; the stages talk through fixed
// locations, so a vertex program's translation feeds any fragment
// program's. OpenGL's clip-space depth (-w..w) becomes the RHI's (0..w), and the primary and
// secondary colours a vertex program writes are clamped to [0, 1], as OpenGL clamps them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>

namespace parity::harness::script {

// The state block, std140: the model-view and projection matrices (column-major), the current
// colour, secondary colour and texture coordinates of units 0..7, then the program's
// program.env[0..envCount-1] and program.local[0..localCount-1].
struct ArbStateBlock {
  static constexpr size_t kModelView = 0, kProjection = 64, kColor = 128, kSecondaryColor = 144, kTexCoords = 160,
                          kEnv = 288;
  uint32_t envCount = 1, localCount = 1;
  size_t localOffset() const { return kEnv + 16 * size_t(envCount); }
  size_t bytes() const { return localOffset() + 16 * size_t(localCount); }
};

struct ArbProgramGlsl {
  bool vertex = false;          // a vertex program (else a fragment program)
  std::string glsl;             // empty where `unsupported` says why
  std::string unsupported;      // the construct the translation does not do
  ArbStateBlock state;          // the block's arrays, as large as the program reads
  std::map<uint32_t, std::string> textures;  // texture unit -> GLSL sampler type, at binding = unit
};

// `stateSet`/`stateBinding`: where the translation declares the state block.
ArbProgramGlsl translateArbProgram(const std::string& text, uint32_t stateSet, uint32_t stateBinding);

}  // namespace parity::harness::script
