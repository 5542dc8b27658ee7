// piglit's and VkRunner's `.shader_test` files, read into the same Script the AmberScript runner
// executes (harness/scripts/script.h). docs/script-format.md, "shader_test files", has the grammar
// and what each command becomes.
//
// The two dialects share one parser: piglit's shaders are OpenGL GLSL (loose uniforms set by
// name, attributes bound by name, `draw rect` in normalised device coordinates, probes in window
// coordinates with y up), VkRunner's are Vulkan GLSL or SPIR-V assembly (push constants and
// buffers set by byte offset). Both draw into a 250x250 RGBA8 framebuffer unless told otherwise.
// A construct the runner cannot execute is listed in Script::unsupported with the command named,
// so the file is reported as skipped, never as a syntax error; a malformed line is an error
// naming the file and line.
#pragma once

#include <string>

#include "harness/scripts/script.h"

namespace parity::harness::script {

bool isShaderTestPath(const std::string& path);
ParseResult parseShaderTest(const std::string& text, const std::string& name);

}  // namespace parity::harness::script
