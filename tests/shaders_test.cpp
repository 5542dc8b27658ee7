// Every shader of the project compiles with glslang, passes spirv-val, reflects within the
// binding model; compile errors name file and line.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "platforms/platform_layer.h"
#include "rhi/shader_compiler.h"
#include "rhi/shader_reflection.h"

namespace fs = std::filesystem;
using namespace parity;

namespace {

std::vector<std::string> projectShaders() {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(rhi::shaderDirectory())) {
    rhi::ShaderStage stage;
    if (e.is_regular_file() && rhi::stageFromPath(e.path().string(), &stage)) out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

TEST(Shaders, ProjectHasShaders) { EXPECT_GE(projectShaders().size(), 2u); }

// Every shader under every platform layer (technique shaders include "platform.glsl", which the
// platform's defines steer), with and without the explicit-arithmetic include.
TEST(Shaders, EveryShaderCompilesValidatesAndReflects) {
  using platforms::PlatformId;
  for (const std::string& path : projectShaders()) {
    for (PlatformId platform : {PlatformId::Reference, PlatformId::Dx10, PlatformId::Ps3, PlatformId::X360})
    for (bool plain : {false, true}) {
      SCOPED_TRACE(path + " on " + std::string(platforms::platformName(platform)) + (plain ? " (plain built-ins)" : ""));
      rhi::ShaderStage stage;
      ASSERT_TRUE(rhi::stageFromPath(path, &stage));
      rhi::ShaderCompileOptions options = platforms::platformShaderOptions(platforms::planTargets(platform, {}, 1, 1));
      if (plain) options.defines.push_back({"PARITY_PLAIN_BUILTINS", "1"});
      rhi::CompiledShader c = rhi::compileGlslFile(path, stage, options);
      ASSERT_TRUE(c.ok()) << c.error;
      std::string error;
      EXPECT_TRUE(rhi::validateSpirv(c.spirv, &error)) << error;
      rhi::ShaderReflection r;
      EXPECT_TRUE(rhi::reflectSpirv(c.spirv, stage, &r, &error)) << error;
    }
  }
}

TEST(Shaders, CompileErrorNamesFileAndLine) {
  fs::path dir = fs::temp_directory_path() / ("parity-shader-test-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  fs::path file = dir / "broken.frag";
  std::ofstream(file) << "#version 450\n"
                         "layout(location = 0) out vec4 color;\n"
                         "void main() {\n"
                         "  color = undefinedThing;\n"
                         "}\n";
  rhi::CompiledShader c = rhi::compileGlslFile(file.string(), rhi::ShaderStage::Fragment);
  EXPECT_FALSE(c.ok());
  EXPECT_NE(c.error.find(file.string() + ":4: error:"), std::string::npos) << c.error;
  EXPECT_NE(c.error.find("undefinedThing"), std::string::npos) << c.error;
  fs::remove_all(dir);
}

// Several compilation units of one stage link into one module, as OpenGL links several shader
// objects of one stage: main() calls a function only the second unit defines.
TEST(Shaders, LinkedUnitsOfOneStageFormOneModule) {
  const std::string main = "#version 450\n"
                           "layout(location = 0) out vec4 color;\n"
                           "vec4 shade(float x);\n"
                           "void main() { color = shade(0.25); }\n";
  rhi::ShaderCompileOptions options;
  options.linkedSources.push_back("#version 450\nvec4 shade(float x) { return vec4(x, 1.0 - x, 0.0, 1.0); }\n");
  rhi::CompiledShader linked = rhi::compileGlslSource(main, "linked.frag", rhi::ShaderStage::Fragment, options);
  ASSERT_TRUE(linked.ok()) << linked.error;
  std::string why;
  EXPECT_TRUE(rhi::validateSpirv(linked.spirv, &why)) << why;
  // Alone, the first unit calls a function nothing defines: a link error, not a cached success.
  rhi::CompiledShader alone = rhi::compileGlslSource(main, "linked.frag", rhi::ShaderStage::Fragment);
  EXPECT_FALSE(alone.ok());
  EXPECT_NE(alone.error.find("shade"), std::string::npos) << alone.error;
}

// A whole program linked as OpenGL links a program object: glslang's linker checks its rules across
// the stages (a vertex output and the fragment input of that name must have one type), and only
// its "ERROR: Linking" messages are link rules; a unit it does not compile is no link rule, nor
// the patch array between the tessellation stages that glslang 12 takes for a per-vertex one.
TEST(Shaders, ProgramLinkTellsLinkRulesFromCompileErrors) {
  auto stage = [](rhi::ShaderStage st, const std::string& source) {
    rhi::ProgramStageSource s;
    s.stage = st;
    s.source = "#version 450\n" + source;
    return s;
  };
  const rhi::ProgramStageSource vertex = stage(rhi::ShaderStage::Vertex, "layout(location = 0) out vec4 v;\nvoid main() { v = vec4(1.0); gl_Position = v; }\n");
  const std::string fragment = "layout(location = 0) out vec4 color;\nvoid main() { color = vec4(v.x); }\n";
  rhi::ProgramLink mismatch = rhi::linkGlslProgram({vertex, stage(rhi::ShaderStage::Fragment, "layout(location = 0) in vec3 v;\n" + fragment)}, "p");
  EXPECT_NE(mismatch.linkError.find("ERROR: Linking vertex and fragment stages: Types must match"), std::string::npos) << mismatch.linkError;
  EXPECT_TRUE(mismatch.compileError.empty()) << mismatch.compileError;
  rhi::ProgramLink matching = rhi::linkGlslProgram({vertex, stage(rhi::ShaderStage::Fragment, "layout(location = 0) in vec4 v;\n" + fragment)}, "p");
  EXPECT_TRUE(matching.ok()) << matching.linkError << matching.compileError;
  rhi::ProgramLink undeclared = rhi::linkGlslProgram({vertex, stage(rhi::ShaderStage::Fragment, fragment)}, "p");
  EXPECT_TRUE(undeclared.linkError.empty()) << undeclared.linkError;
  EXPECT_NE(undeclared.compileError.find("p:3: error:"), std::string::npos) << undeclared.compileError;
  rhi::ProgramLink patches = rhi::linkGlslProgram(
      {vertex,
       stage(rhi::ShaderStage::TessControl, "layout(vertices = 1) out;\nlayout(location = 1) patch out vec3 p[2];\n"
                                            "void main() { p[0] = vec3(0.0); p[1] = vec3(1.0); gl_TessLevelOuter[0] = 1.0; }\n"),
       stage(rhi::ShaderStage::TessEvaluation, "layout(isolines) in;\nlayout(location = 1) patch in vec3 p[2];\n"
                                               "void main() { gl_Position = vec4(p[1], 1.0); }\n")},
      "p");
  EXPECT_TRUE(patches.linkError.empty()) << patches.linkError;
  EXPECT_NE(patches.compileError.find("Array sizes must be compatible"), std::string::npos) << patches.compileError;
}

TEST(Shaders, ErrorInIncludedFileNamesTheIncludedFile) {
  fs::path dir = fs::temp_directory_path() / ("parity-shader-inc-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "helper.glsl") << "float helper() {\n  return missing;\n}\n";
  std::ofstream(dir / "main.frag") << "#version 450\n#include \"helper.glsl\"\n"
                                      "layout(location = 0) out vec4 color;\nvoid main() { color = vec4(helper()); }\n";
  rhi::CompiledShader c = rhi::compileGlslFile((dir / "main.frag").string(), rhi::ShaderStage::Fragment);
  EXPECT_FALSE(c.ok());
  EXPECT_NE(c.error.find("helper.glsl:2: error:"), std::string::npos) << c.error;
  fs::remove_all(dir);
}

TEST(Shaders, MissingFileIsAnError) {
  rhi::CompiledShader c = rhi::compileGlslFile("/nonexistent/x.frag", rhi::ShaderStage::Fragment);
  EXPECT_FALSE(c.ok());
  EXPECT_NE(c.error.find("/nonexistent/x.frag: error: cannot read"), std::string::npos) << c.error;
}

TEST(Shaders, ReflectionRejectsOtherDescriptorSets) {
  rhi::CompiledShader c = rhi::compileGlslSource(
      "#version 450\nlayout(set = 1, binding = 0) uniform U { vec4 v; } u;\n"
      "layout(location = 0) out vec4 color;\nvoid main() { color = u.v; }\n",
      "set1.frag", rhi::ShaderStage::Fragment);
  ASSERT_TRUE(c.ok()) << c.error;
  rhi::ShaderReflection r;
  std::string error;
  EXPECT_FALSE(rhi::reflectSpirv(c.spirv, rhi::ShaderStage::Fragment, &r, &error));
  EXPECT_NE(error.find("set 1"), std::string::npos) << error;
}

TEST(Shaders, ReflectionReportsBindingsAndPushConstants) {
  rhi::CompiledShader c = rhi::compileGlslSource(
      "#version 450\n"
      "layout(set = 0, binding = 3) uniform sampler2D tex;\n"
      "layout(set = 0, binding = 1, std430) buffer B { uint data[]; } b;\n"
      "layout(set = 0, binding = 0) uniform U { vec4 v; } u;\n"
      "layout(push_constant) uniform P { vec4 a; vec4 c; } pc;\n"
      "layout(location = 0) out vec4 color;\nlayout(location = 2) out vec4 other;\n"
      "void main() { color = u.v + texture(tex, vec2(0)) + pc.a + pc.c + float(b.data[0]); other = color; }\n",
      "refl.frag", rhi::ShaderStage::Fragment);
  ASSERT_TRUE(c.ok()) << c.error;
  rhi::ShaderReflection r;
  std::string error;
  ASSERT_TRUE(rhi::reflectSpirv(c.spirv, rhi::ShaderStage::Fragment, &r, &error)) << error;
  ASSERT_EQ(r.resources.size(), 3u);
  EXPECT_EQ(r.resources[0].binding, 0u);
  EXPECT_EQ(r.resources[0].kind, rhi::BindingKind::UniformBuffer);
  EXPECT_EQ(r.resources[1].binding, 1u);
  EXPECT_EQ(r.resources[1].kind, rhi::BindingKind::StorageBuffer);
  EXPECT_EQ(r.resources[2].binding, 3u);
  EXPECT_EQ(r.resources[2].kind, rhi::BindingKind::SampledTexture);
  EXPECT_EQ(r.pushConstantSize, 32u);
  EXPECT_EQ(r.colorOutputs, 0b101u);
  EXPECT_EQ(r.clipDistances, 0u);
}

// The size of the gl_ClipDistance array a stage outputs (what the GL backend enables): in the
// gl_PerVertex block or redeclared, and per vertex in a tessellation control shader.
TEST(Shaders, ReflectionCountsTheClipDistancesWritten) {
  struct Case {
    rhi::ShaderStage stage;
    const char* source;
    uint32_t clipDistances;
  };
  const Case cases[] = {
      {rhi::ShaderStage::Vertex, "#version 450\nvoid main() { gl_Position = vec4(0); }\n", 0},
      {rhi::ShaderStage::Vertex,
       "#version 450\nout float gl_ClipDistance[3];\nvoid main() { gl_Position = vec4(0); gl_ClipDistance[2] = 1.0; }\n", 3},
      {rhi::ShaderStage::TessControl,
       "#version 450\nlayout(vertices = 3) out;\nout gl_PerVertex { vec4 gl_Position; float gl_ClipDistance[5]; } gl_out[];\n"
       "void main() { gl_out[gl_InvocationID].gl_ClipDistance[4] = 1.0; }\n", 5},
  };
  for (const Case& c : cases) {
    rhi::CompiledShader compiled = rhi::compileGlslSource(c.source, "clip.glsl", c.stage);
    ASSERT_TRUE(compiled.ok()) << compiled.error;
    rhi::ShaderReflection r;
    std::string error;
    ASSERT_TRUE(rhi::reflectSpirv(compiled.spirv, c.stage, &r, &error)) << error;
    EXPECT_EQ(r.clipDistances, c.clipDistances) << c.source;
  }
}
