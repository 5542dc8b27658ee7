// OpenGL GLSL (piglit's shaders) made compilable by glslang's SPIR-V path, which knows no
// GL_ARB_* extension directives and no SPIR-V form of GLSL before 1.40: the #version is raised to
// the first one in which every extension the shader enables is core (GL 4.5 has them all), and
// what that version removed (attribute, varying, gl_FragColor, gl_FragData) is spelled anew. A
// vertex shader before 1.40 that reads gl_Vertex reads the input parity_Vertex instead.
#pragma once

#include <optional>
#include <set>
#include <string>
#include <vector>

#include "harness/scripts/script.h"

namespace parity::harness::script {

struct OpenGlGlsl {
  std::string source;       // with its #version line replaced (same line count)
  std::string declarations; // to insert after the #version and #extension lines (e.g. a gl_FragColor output)
};

// `defaultVersion`: the version of a source without #version (piglit uses the [require] one).
// The compatibility profile's shadow2D(), shadow2DRect(), shadow2DArray(), shadow1DArray() and their GradARB forms
// become texture() and textureGrad() on a sampler*Shadow (a rectangle's texel coordinates divided by its size),
// their float result filled into a vec4 by the texture's GL_DEPTH_TEXTURE_MODE, which the shader
// reads from the int uniform depthModeUniform(sampler) (0: GL's default, luminance).
// `fixedFunction`: the compatibility state that changes what the shaders compute. A vertex shader
// writing gl_ClipVertex clips by the planes in the uniform kClipPlaneUniform. The stage
// `lastBeforeRasterisation` maps OpenGL's clip-space depth (-w..w) to the RHI's (0..w).
OpenGlGlsl prepareOpenGlGlsl(const std::string& source, Stage stage, int defaultVersion = 110, const FixedFunctionState& fixedFunction = {},
                             bool lastBeforeRasterisation = false);
inline constexpr const char* kClipPlaneUniform = "parity_ClipPlane";

// The source for a driver that compiles OpenGL GLSL itself (rhi::ShaderDesc::openGlGlsl): as
// written, but for what the runner keeps in uniforms and generic inputs where OpenGL keeps
// compatibility state (the matrices of kCompatibilityMatrices and ftransform(), gl_Vertex before
// 1.40, gl_MultiTexCoord0), which `declarations` #define to the port's names (prepareOpenGlGlsl),
// so that the program and its port read the same uniforms and inputs.
OpenGlGlsl nativeOpenGlGlsl(const std::string& source, Stage stage, int defaultVersion = 110);
// The shader's declarations only: each function definition left as its prototype, and an empty
// main where the shader defines main (comments blanked, lines kept). What the program declares
// (uniforms, inputs, outputs, blocks, samplers, layouts) compiles for a port that places a
// program whose code glslang cannot port, where the driver runs the code itself.
std::string declarationsOnly(const std::string& source);

// Whether the port enables an OpenGL extension that is neither GL_ARB_ nor GL_KHR_ under the
// name and version glslang knows it by (GL_AMD_conservative_depth as GL_ARB_conservative_depth,
// GL_NV_shader_atomic_float as GL_EXT_shader_atomic_float, ...).
bool portsExtension(const std::string& extension);

// The version a shader is compiled with: its #version, else `defaultVersion`.
int openGlGlslVersion(const std::string& source, int defaultVersion);

// The compatibility profile's transformation matrices, which the rewrite reads from uniforms of
// these names (ftransform() is the model-view-projection matrix times gl_Vertex). The runner
// sets them as OpenGL's matrix stacks hold them: the identity, until `ortho` loads a projection.
struct CompatibilityMatrix {
  const char* builtIn;
  const char* uniform;
  const char* type;  // piglit's type name for `uniform TYPE NAME values`
};
inline constexpr CompatibilityMatrix kCompatibilityMatrices[] = {
    {"gl_ModelViewProjectionMatrix", "parity_ModelViewProjectionMatrix", "mat4"},
    {"gl_ModelViewMatrix", "parity_ModelViewMatrix", "mat4"},
    {"gl_ProjectionMatrix", "parity_ProjectionMatrix", "mat4"},
    {"gl_NormalMatrix", "parity_NormalMatrix", "mat3"}};

enum class DepthTextureMode : int { Luminance = 0, Intensity = 1, Alpha = 2, Red = 3 };
// The shadow samplers of `source` whose results take a depth texture mode (see above).
std::vector<std::string> depthModeSamplers(const std::string& source);
inline std::string depthModeUniform(const std::string& sampler) { return "parity_depth_mode_" + sampler; }

// Valid OpenGL GLSL that glslang cannot compile, named from its error `log` (the construct and
// glslang's fault, for a SKIP); nothing when the error is the shader's own. `source` is the
// shader as written, its first line at line `firstLine` of the file the log names.
std::optional<std::string> glslangLimitation(const std::string& source, int firstLine, const std::string& log);

// The inputs (or outputs) the shader places with layout(location = ...), by the name OpenGL links
// them by (a block by its block name): OpenGL matches those by location, the others by name.
std::set<std::string> explicitlyLocated(const std::string& source, bool outputs);

// The literal initialisers of a shader's uniforms (`uniform vec4 c = vec4(1.0);`,
// `uniform S s = S(2.0, vec2(0.5));`, `uniform float a[] = {1.0, 2.0};`), which glslang drops:
// one entry per scalar, vector or matrix they set, named as a `uniform` command names it ("c",
// "s.f", "a[1]") with its components in GLSL order (vec4(x) fills all four, mat3(x) is a
// diagonal). An initialiser may name a constant whose value is such a literal; other
// initialisers (calls, expressions) are left out.
struct UniformInitialValue {
  std::string path;
  std::vector<Value> values;
};
std::vector<UniformInitialValue> uniformInitializers(const std::string& source);

}  // namespace parity::harness::script
