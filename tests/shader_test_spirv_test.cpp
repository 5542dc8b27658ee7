// piglit's SPIR-V programs ([require] SPIRV, GL_ARB_gl_spirv) as the parser reads them: which
// shader sections make the program, and the name-free commands (`block ...`, `uniform` at a block
// position, the program queries). tests/scripts/shader_test/piglit_spirv_blocks.shader_test runs
// one on both backends.
#include <gtest/gtest.h>

#include <cstring>

#include "harness/scripts/script.h"
#include "harness/scripts/shader_test_parser.h"

using namespace parity::harness::script;

namespace {

const char* kSpirvFragment = R"(               OpCapability Shader
               OpMemoryModel Logical GLSL450
               OpEntryPoint Fragment %main "main" %color
               OpExecutionMode %main OriginLowerLeft
               OpDecorate %color Location 0
       %void = OpTypeVoid
          %3 = OpTypeFunction %void
      %float = OpTypeFloat 32
    %v4float = OpTypeVector %float 4
%_ptr_Output_v4float = OpTypePointer Output %v4float
      %color = OpVariable %_ptr_Output_v4float Output
    %float_1 = OpConstant %float 1
    %float_0 = OpConstant %float 0
      %green = OpConstantComposite %v4float %float_0 %float_1 %float_0 %float_1
       %main = OpFunction %void None %3
          %5 = OpLabel
               OpStore %color %green
               OpReturn
               OpFunctionEnd
)";

std::string file(const std::string& spirvLine, const std::string& test) {
  return "[require]\n" + spirvLine + "GLSL >= 4.50\nGL_ARB_gl_spirv\n\n[vertex shader passthrough]\n\n[fragment shader spirv]\n" +
         kSpirvFragment + "\n[fragment shader]\n#version 450\nout vec4 c;\nvoid main() { c = vec4(0.0, 0.0, 1.0, 1.0); }\n\n[test]\n" + test;
}

const Shader* fragment(const Script& s) {
  for (const Shader& sh : s.shaders)
    if (sh.stage == Stage::Fragment) return &sh;
  return nullptr;
}

TEST(ShaderTestSpirv, RequireSpirvChoosesTheSpirvSectionsAndNoTheGlsl) {
  for (const char* mode : {"YES", "ONLY"}) {
    ParseResult r = parseShaderTest(file(std::string("SPIRV ") + mode + "\n", "draw rect -1 -1 2 2\n"), "t.shader_test");
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_TRUE(r.script.unsupported.empty()) << mode << ": " << r.script.unsupported.front().feature;
    const Shader* fs = fragment(r.script);
    ASSERT_NE(fs, nullptr) << mode;
    EXPECT_EQ(fs->format, "SPIRV-ASM") << mode;
    EXPECT_FALSE(fs->openGl) << mode;
    EXPECT_EQ(r.script.shaders.size(), 2u) << mode;  // the pass-through vertex shader and this
  }
  for (const std::string spirvLine : {"SPIRV NO\n", ""}) {
    ParseResult r = parseShaderTest(file(spirvLine, "draw rect -1 -1 2 2\n"), "t.shader_test");
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_TRUE(r.script.unsupported.empty()) << spirvLine << ": " << r.script.unsupported.front().feature;
    const Shader* fs = fragment(r.script);
    ASSERT_NE(fs, nullptr);
    EXPECT_EQ(fs->format, "GLSL") << spirvLine;
    EXPECT_TRUE(fs->openGl) << spirvLine;
  }
  ParseResult bad = parseShaderTest(file("SPIRV MAYBE\n", ""), "t.shader_test");
  EXPECT_FALSE(bad.ok);
  EXPECT_EQ(bad.error, "t.shader_test:2: error: SPIRV takes YES, ONLY or NO, got 'SPIRV MAYBE'");
}

TEST(ShaderTestSpirv, UniformsGoToTheBlockPositionAndQueriesToTheBlockBinding) {
  ParseResult r = parseShaderTest(file("SPIRV YES\n", R"(block binding 3
block offset 8
uniform vec2 Anything.at 1.5 2.5
block array index 2
block offset 4
uniform int Anything.else 7
block array index 0
block offset 16
block matrix stride 16
block row major 1
uniform mat2 M.m 1 2 3 4
verify program_interface_query GL_UNIFORM_BLOCK B GL_BUFFER_DATA_SIZE 48
block binding 6
verify program_interface_query GL_SHADER_STORAGE_BLOCK S GL_NUM_ACTIVE_VARIABLES 2
verify program_query GL_ACTIVE_UNIFORMS 5
verify program_interface_query GL_UNIFORM_BLOCK B GL_TYPE 4
verify program_query GL_TRANSFORM_FEEDBACK_VARYINGS 1
uniform int 10 1
)"),
                                  "t.shader_test");
  ASSERT_TRUE(r.ok) << r.error;
  const Script& s = r.script;
  std::vector<const Command*> writes, queries;
  for (const Command& c : s.commands) {
    if (c.kind == Command::Kind::WriteBuffer) writes.push_back(&c);
    if (c.kind == Command::Kind::ExpectProgramQuery) queries.push_back(&c);
  }
  ASSERT_EQ(writes.size(), 3u);
  EXPECT_EQ(writes[0]->buffer, "ubo_0_3");
  EXPECT_EQ(writes[0]->px, 8u);
  ASSERT_EQ(writes[0]->bytes.size(), 8u);
  float f[2];
  std::memcpy(f, writes[0]->bytes.data(), 8);
  EXPECT_EQ(f[0], 1.5f);
  EXPECT_EQ(f[1], 2.5f);
  EXPECT_EQ(writes[1]->buffer, "ubo_0_3_2");  // element 2 of the array of blocks at binding 3
  EXPECT_EQ(writes[1]->px, 4u);
  // mat2 given column by column (1 2 | 3 4), stored row by row 16 bytes apart: 1 3 at 16, 2 4 at 32.
  EXPECT_EQ(writes[2]->px, 16u);
  ASSERT_EQ(writes[2]->bytes.size(), 24u);
  float m[6];
  std::memcpy(m, writes[2]->bytes.data(), 24);
  EXPECT_EQ(m[0], 1.0f);
  EXPECT_EQ(m[1], 3.0f);
  EXPECT_EQ(m[4], 2.0f);
  EXPECT_EQ(m[5], 4.0f);
  ASSERT_EQ(queries.size(), 3u);
  EXPECT_EQ(queries[0]->programInterface, "GL_UNIFORM_BLOCK");
  EXPECT_EQ(queries[0]->blockBinding, 3);
  EXPECT_EQ(queries[0]->other, "GL_BUFFER_DATA_SIZE");
  EXPECT_EQ(queries[0]->values.at(0).i, 48);
  EXPECT_EQ(queries[1]->programInterface, "GL_SHADER_STORAGE_BLOCK");
  EXPECT_EQ(queries[1]->blockBinding, 6);
  EXPECT_EQ(queries[2]->programInterface, "");
  EXPECT_EQ(queries[2]->other, "GL_ACTIVE_UNIFORMS");
  EXPECT_EQ(queries[2]->values.at(0).i, 5);
  // What cannot be answered from the modules, or set without a default uniform block, is named.
  ASSERT_EQ(s.unsupported.size(), 3u);
  EXPECT_EQ(s.unsupported[0].feature, "verify program_interface_query GL_UNIFORM_BLOCK GL_TYPE");
  EXPECT_EQ(s.unsupported[1].feature, "verify program_query GL_TRANSFORM_FEEDBACK_VARYINGS");
  EXPECT_NE(s.unsupported[2].feature.find("uniform int at location 10"), std::string::npos) << s.unsupported[2].feature;
}

TEST(ShaderTestSpirv, AUniformBeforeItsBlockBindingIsAnErrorNamingTheLine) {
  ParseResult r = parseShaderTest(file("SPIRV YES\n", "uniform vec4 B.v 1 2 3 4\n"), "t.shader_test");
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("t.shader_test:"), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("uniform B.v of a SPIR-V program needs a `block binding` first"), std::string::npos) << r.error;
  ParseResult junk = parseShaderTest(file("SPIRV YES\n", "block stride 4\n"), "t.shader_test");
  EXPECT_FALSE(junk.ok);
  EXPECT_NE(junk.error.find("unknown block command 'block stride'"), std::string::npos) << junk.error;
}

}  // namespace
