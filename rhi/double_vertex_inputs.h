// 64-bit vertex inputs fed as 32-bit words, for devices whose vertex buffers have no 64-bit
// formats (lavapipe in Mesa 22.3 has shaderFloat64 but no R64* vertex buffer format).
//
// Each double, dvecN, dmat or array of them that the pipeline feeds from VertexFormat::Double*
// becomes a private copy that the entry point fills first from uint inputs at the same locations:
// the attribute's words bitcast back to doubles, bit for bit. Components the attribute lacks read
// as they would from a 64-bit format (0.0, and 1.0 for w).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace parity::rhi {

// One 64-bit vertex attribute as the pipeline feeds it.
struct DoubleAttribute {
  uint32_t location = 0;
  uint32_t components = 1;  // 1-4
};

// A 32-bit attribute that replaces part of a 64-bit one: its location, its uint components (2 or
// 4) and its byte offset from the 64-bit attribute's. Components 0-1 come from `location`, 2-3
// from `location + 1`, as Vulkan places the second half of a dvec3 or dvec4.
struct WordAttribute {
  uint32_t location = 0;
  uint32_t words = 2;
  uint32_t offset = 0;
};
std::vector<WordAttribute> wordAttributes(const DoubleAttribute& attribute);

// Rewrites the vertex module's inputs fed by `attributes` as described above. Returns "" on
// success (also when no input is fed by them), else a one-line reason: an input only partly fed
// by 64-bit attributes, or one placed with a Component decoration.
std::string readDoubleInputsAsWords(std::vector<uint32_t>& spirv, const std::vector<DoubleAttribute>& attributes);

}  // namespace parity::rhi
