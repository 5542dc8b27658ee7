// GLSL 450 (Vulkan flavour: set/binding, push constants) to SPIR-V with glslang, at run time.
//
// Why run time: shader-test scripts bring their own GLSL, and a technique's variants differ by
// defines; compiling is a few milliseconds per stage on llvmpipe-class machines. Results are
// memoised per process by (stage, expanded source, defines). Every shader under shaders/ is
// compiled and checked with spirv-val by the test suite, so a broken shader fails CI even if no
// technique uses it yet.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "rhi/rhi.h"

namespace parity::rhi {

struct ShaderCompileOptions {
  // Extra folders searched by #include "..." after the including file's own folder.
  // The project's shaders/include is always searched last.
  std::vector<std::string> includeDirs;
  std::vector<std::pair<std::string, std::string>> defines;  // name, value ("" for a bare define)
  // The source is OpenGL GLSL (piglit-style shader tests): compiled with glslang's relaxed Vulkan
  // rules, so that loose uniforms become members of one block ("gl_DefaultUniformBlock" at
  // defaultUniformSet/defaultUniformBinding), atomic counters storage buffers, and resources and
  // stage interfaces without explicit bindings or locations get them assigned in declaration order.
  bool openGlSource = false;
  uint32_t defaultUniformSet = 0, defaultUniformBinding = 0;
  // Further compilation units of the same stage, linked with the source into one module, as
  // OpenGL links several shader objects of one stage (and glslangValidator several files): one
  // unit may call a function another defines. Each is compiled with these same options.
  std::vector<std::string> linkedSources;
  // OpenGL's named strings (GL_ARB_shading_language_include): `#include` finds these instead of
  // files. A path is absolute ("/dir/name"); "..." resolves against the including string's folder,
  // then the search paths, <...> against the search paths only, in their order.
  std::vector<std::pair<std::string, std::string>> namedStrings;  // path, text
  std::vector<std::string> namedStringSearchPaths;
};

struct CompiledShader {
  std::vector<uint32_t> spirv;
  std::string error;  // "file:line: message" lines from the compiler; empty on success
  bool ok() const { return error.empty() && !spirv.empty(); }
};

// Stage from the file extension: .vert, .frag, .comp (also *.vert.glsl etc.).
bool stageFromPath(const std::string& path, ShaderStage* stage);

CompiledShader compileGlslFile(const std::string& path, ShaderStage stage,
                               const ShaderCompileOptions& options = {});
// `name` is used for error messages and relative includes (its folder is searched first).
CompiledShader compileGlslSource(const std::string& source, const std::string& name,
                                 ShaderStage stage, const ShaderCompileOptions& options = {});

// One stage of a program: its source, and the options it is compiled with (its further units in
// options.linkedSources).
struct ProgramStageSource {
  ShaderStage stage = ShaderStage::Vertex;
  std::string source;
  ShaderCompileOptions options;
};

// What glslang says of a whole program, its stages compiled and linked together as OpenGL links a
// program object: glslang's linker checks its rules within each stage and across the stages.
struct ProgramLink {
  std::string compileError;  // a unit glslang does not compile, or a refusal that names no linker rule
  std::string linkError;     // the linker's rules the program breaks ("ERROR: Linking <stage> stage: ...")
  bool ok() const { return compileError.empty() && linkError.empty(); }
};
// Links without producing modules (compileGlslSource makes each stage's). `name` is the units'
// file name in messages.
ProgramLink linkGlslProgram(const std::vector<ProgramStageSource>& stages, const std::string& name);

// SPIR-V assembly (spirv-as syntax) to a module. Errors are "name:line: message" with the line
// counted from firstLine (the assembly's first line in the file that holds it).
// spirvMinor selects the SPIR-V version the text is written for (1.0 .. 1.6; Amber's TARGET_ENV
// spv1.x): StorageBuffer and other later-core features need no OpExtension from their version on.
CompiledShader assembleSpirv(const std::string& text, const std::string& name, int firstLine = 1, int spirvMinor = 0);

// spirv-val for the Vulkan 1.3 environment. Returns false with a message on invalid modules.
bool validateSpirv(const std::vector<uint32_t>& spirv, std::string* error);

// Folder of parity's data (shaders/, golden/, tests/scripts/): PARITY_DATA_DIR in the environment,
// else an installed layout beside the executable (<prefix>/share/parity for <prefix>/bin/parity,
// wherever the prefix was moved), else the data of the installed package a program of another
// project was linked from (setPackageDataDirectory), else the source tree the libraries were
// built from.
std::string dataDirectory();
// Called by a file find_package(parity) compiles into every program linking parity::rhi
// (cmake/parity-config.cmake.in), with that package's <prefix>/share/parity as found at
// configure time: a program built outside parity's tree finds the shaders it was built against.
bool setPackageDataDirectory(const std::string& dir);
// Folder holding the project's shaders (PARITY_SHADER_DIR in the environment overrides the
// build-time source path, so an installed or relocated build still finds them).
std::string shaderDirectory();

}  // namespace parity::rhi
