// OpenGL GLSL (piglit's shaders) made compilable by glslang's SPIR-V path, which knows no
// GL_ARB_* extension directives and no SPIR-V form of GLSL before 1.40: the #version is raised to
// the first one in which every extension the shader enables is core (GL 4.5 has them all), and
// what that version removed (attribute, varying, gl_FragColor, gl_FragData) is spelled anew. A
// vertex shader before 1.40 that reads gl_Vertex reads the input parity_Vertex instead.
#pragma once

#include <string>

#include "harness/script_parser.h"

namespace parity::harness::script {

struct OpenGlGlsl {
  std::string source;       // with its #version line replaced (same line count)
  std::string declarations; // to insert after the #version and #extension lines (e.g. a gl_FragColor output)
};

// `defaultVersion`: the version of a source without #version (piglit uses the [require] one).
OpenGlGlsl prepareOpenGlGlsl(const std::string& source, Stage stage, int defaultVersion = 110);

}  // namespace parity::harness::script
