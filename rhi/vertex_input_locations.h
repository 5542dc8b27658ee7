// Vertex input locations of a module compiled from OpenGL GLSL, counted as Vulkan counts them.
#pragma once

#include <cstdint>
#include <vector>

namespace parity::rhi {

// OpenGL counts a 64-bit vertex input of three or four components (dvec3, dvec4 and the matrices
// with such columns) as one location per vector; Vulkan counts two (SPIR-V 2.16.2, "Location
// Assignment"), and so do the vertex attributes a Vulkan pipeline feeds. glslang assigns and
// checks OpenGL's count in either target, so such an input overlaps the next one in a module for
// Vulkan. Where inputs overlap under Vulkan's count, each is moved up just past the one before
// it, in the order of their OpenGL locations; a module without overlaps is left as it was. The
// inputs keep their names, by which OpenGL programs and scripts find them.
void vulkanVertexInputLocations(std::vector<uint32_t>& spirv);

}  // namespace parity::rhi
