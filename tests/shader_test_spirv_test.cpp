// piglit's SPIR-V programs ([require] SPIRV, GL_ARB_gl_spirv) as the parser reads them: which
// shader sections make the program, and the name-free commands (`block ...`, `uniform` at a block
// position, the program queries). tests/scripts/shader_test/piglit_spirv_blocks.shader_test runs
// one on both backends.
#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <set>

#include "harness/scripts/runner/spirv_edit.h"
#include "harness/scripts/script.h"
#include "harness/scripts/shader_test_parser.h"
#include "rhi/shader_compiler.h"

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

TEST(ShaderTestSpirv, SpecializationSectionsSpecializeTheSpirvShaderOfEveryPipeline) {
  std::string text = file("SPIRV YES\n", "draw rect -1 -1 2 2\n");
  text.replace(text.find("[fragment shader spirv]"), 0, "[fragment shader specializations]\nfloat 5 1.5\nuint 6 0x10\ndouble 7 1.0\n\n");
  ParseResult r = parseShaderTest(text, "t.shader_test");
  ASSERT_TRUE(r.ok) << r.error;
  ASSERT_FALSE(r.script.pipelines.empty());
  for (const Pipeline& p : r.script.pipelines) {
    auto spec = p.specializations.find("fragment");
    ASSERT_NE(spec, p.specializations.end()) << p.name;
    float f = 0;
    std::memcpy(&f, &spec->second.at(5), sizeof f);
    EXPECT_EQ(f, 1.5f);
    EXPECT_EQ(spec->second.at(6), 16u);
    EXPECT_FALSE(spec->second.count(7));
  }
  ASSERT_EQ(r.script.unsupported.size(), 1u);
  EXPECT_EQ(r.script.unsupported[0].feature, "[fragment shader specializations] of type double (32-bit constants only)");
  // With the GLSL sections the program (SPIRV NO), piglit specializes nothing.
  std::string glsl = text;
  glsl.replace(glsl.find("SPIRV YES"), 9, "SPIRV NO");
  ParseResult g = parseShaderTest(glsl, "t.shader_test");
  ASSERT_TRUE(g.ok) << g.error;
  for (const Pipeline& p : g.script.pipelines) EXPECT_TRUE(p.specializations.empty()) << p.name;
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

// OpenGL's SPIR-V: resources with a Binding and no DescriptorSet (Vulkan requires one), and loose
// uniforms (non-opaque UniformConstant variables), which Vulkan has no place for.
TEST(ShaderTestSpirv, OpenGlModulesGetSetZeroAndTheirLooseUniformsAreNamed) {
  const std::string assembly = R"(               OpCapability Shader
               OpMemoryModel Logical GLSL450
               OpEntryPoint Fragment %main "main"
               OpExecutionMode %main OriginLowerLeft
               OpName %u_idx "u_idx"
               OpMemberDecorate %Block 0 Offset 0
               OpDecorate %Block Block
               OpDecorate %blocks Binding 5
               OpDecorate %tex DescriptorSet 0
               OpDecorate %tex Binding 1
               OpDecorate %u_idx Location 10
       %void = OpTypeVoid
          %3 = OpTypeFunction %void
      %float = OpTypeFloat 32
    %v4float = OpTypeVector %float 4
      %Block = OpTypeStruct %v4float
%_ptr_Uniform_Block = OpTypePointer Uniform %Block
     %blocks = OpVariable %_ptr_Uniform_Block Uniform
      %image = OpTypeImage %float 2D 0 0 0 1 Unknown
    %sampled = OpTypeSampledImage %image
%_ptr_UniformConstant_sampled = OpTypePointer UniformConstant %sampled
        %tex = OpVariable %_ptr_UniformConstant_sampled UniformConstant
        %int = OpTypeInt 32 1
%_ptr_UniformConstant_int = OpTypePointer UniformConstant %int
      %u_idx = OpVariable %_ptr_UniformConstant_int UniformConstant
       %main = OpFunction %void None %3
          %5 = OpLabel
               OpReturn
               OpFunctionEnd
)";
  parity::rhi::CompiledShader c = parity::rhi::assembleSpirv(assembly, "t.shader_test", 1, 0);
  ASSERT_TRUE(c.ok()) << c.error;
  std::vector<uint32_t> spirv = c.spirv;
  EXPECT_EQ(runner::looseUniformOf(spirv), "u_idx");
  auto setDecorations = [](const std::vector<uint32_t>& words) {
    std::map<uint32_t, uint32_t> sets;  // id -> set
    for (size_t i = 5; i < words.size() && (words[i] >> 16) != 0; i += words[i] >> 16)
      if ((words[i] & 0xFFFF) == 71 && words[i + 2] == 34) sets[words[i + 1]] = words[i + 3];
    return sets;
  };
  EXPECT_EQ(setDecorations(spirv).size(), 1u);  // the texture's only
  runner::addMissingDescriptorSets(spirv);
  EXPECT_EQ(setDecorations(spirv).size(), 2u);  // and now the block's, set 0
  for (const auto& [id, set] : setDecorations(spirv)) EXPECT_EQ(set, 0u) << id;
  EXPECT_EQ(runner::spirvBindings(spirv), (std::set<runner::SetBinding>{{0, 1}, {0, 5}}));
  // OpenGL's lower-left origin is the RHI's first row: OriginUpperLeft (7), not OriginLowerLeft (8).
  auto origins = [](const std::vector<uint32_t>& words) {
    std::vector<uint32_t> modes;
    for (size_t i = 5; i < words.size() && (words[i] >> 16) != 0; i += words[i] >> 16)
      if ((words[i] & 0xFFFF) == 16) modes.push_back(words[i + 2]);  // OpExecutionMode
    return modes;
  };
  EXPECT_EQ(origins(spirv), std::vector<uint32_t>{8});
  runner::originAtFirstRow(spirv);
  EXPECT_EQ(origins(spirv), std::vector<uint32_t>{7});
  // A uniform's Location (its glUniform location) goes; the others stay.
  auto locations = [](const std::vector<uint32_t>& words) {
    size_t n = 0;
    for (size_t i = 5; i < words.size() && (words[i] >> 16) != 0; i += words[i] >> 16)
      if ((words[i] & 0xFFFF) == 71 && words[i + 2] == 30) ++n;  // OpDecorate Location
    return n;
  };
  EXPECT_EQ(locations(spirv), 1u);
  runner::dropUniformLocations(spirv);
  EXPECT_EQ(locations(spirv), 0u);
  // A module with only opaque uniforms has no loose ones.
  std::string opaque = assembly;
  opaque.replace(opaque.find("      %u_idx = OpVariable"), std::string("      %u_idx = OpVariable %_ptr_UniformConstant_int UniformConstant\n").size(), "");
  opaque.replace(opaque.find("               OpName %u_idx"), std::string("               OpName %u_idx \"u_idx\"\n").size(), "");
  opaque.replace(opaque.find("               OpDecorate %u_idx Location 10"), std::string("               OpDecorate %u_idx Location 10\n").size(), "");
  parity::rhi::CompiledShader withoutLoose = parity::rhi::assembleSpirv(opaque, "t.shader_test", 1, 0);
  ASSERT_TRUE(withoutLoose.ok()) << withoutLoose.error;
  EXPECT_EQ(runner::looseUniformOf(withoutLoose.spirv), "");
}

}  // namespace
