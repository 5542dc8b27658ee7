// The rewrite that feeds 64-bit vertex inputs from 32-bit word attributes
// (rhi/double_vertex_inputs.h), checked on modules without a device: what it produces must pass
// spirv-val, keep no 64-bit Input, and refuse what it cannot feed. Whether the words read back
// the attributes' doubles is RhiConformanceTest.DoubleVertex* on every backend.
#include <gtest/gtest.h>

#include <spirv_cross/spirv.h>

#include <algorithm>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "rhi/double_vertex_inputs.h"
#include "rhi/shader_compiler.h"
#include "rhi/shader_reflection.h"  // forEachInstruction

namespace parity::rhi {
namespace {

std::vector<uint32_t> vertexModule(const std::string& inputs, const std::string& use) {
  const std::string source = "#version 450\n" + inputs + "\nvoid main() { gl_Position = vec4(float(" + use + ")); }\n";
  CompiledShader c = compileGlslSource(source, "doubles.vert", ShaderStage::Vertex);
  EXPECT_TRUE(c.ok()) << c.error;
  return c.spirv;
}

// The Locations of the module's Input variables and whether each is made of 64-bit floats.
struct InputFacts {
  std::vector<uint32_t> wordLocations, doubleLocations;
};
InputFacts inputsOf(const std::vector<uint32_t>& spirv) {
  std::map<uint32_t, uint32_t> location, pointee;
  std::set<uint32_t> wide;  // 64-bit float types and the vectors, matrices and arrays of them
  std::vector<uint32_t> inputs;
  forEachInstruction(spirv, [&](uint32_t op, size_t at, uint32_t n) {
    const uint32_t* w = spirv.data() + at;
    if (op == SpvOpDecorate && n >= 4 && w[2] == SpvDecorationLocation) location[w[1]] = w[3];
    if (op == SpvOpTypeFloat && w[2] == 64) wide.insert(w[1]);
    if ((op == SpvOpTypeVector || op == SpvOpTypeMatrix || op == SpvOpTypeArray) && wide.count(w[2])) wide.insert(w[1]);
    if (op == SpvOpTypePointer) pointee[w[1]] = w[3];
    if (op == SpvOpVariable && w[3] == SpvStorageClassInput) inputs.push_back(w[2]), pointee[w[2]] = pointee[w[1]];
  });
  InputFacts facts;
  for (uint32_t v : inputs) {
    if (!location.count(v)) continue;
    (wide.count(pointee[v]) ? facts.doubleLocations : facts.wordLocations).push_back(location[v]);
  }
  std::sort(facts.wordLocations.begin(), facts.wordLocations.end());
  return facts;
}

TEST(DoubleVertexInputs, EveryFedInputBecomesWordInputsThatSpirvValAccepts) {
  std::vector<uint32_t> spirv = vertexModule(
      "layout(location = 0) in dmat2x3 m;\nlayout(location = 4) in dvec2 a[2];\n"
      "layout(location = 6) in double d;\nlayout(location = 7) in dvec4 partial;\nlayout(location = 9) in vec4 plain;",
      "m[1].z + a[1].y + d + partial.w + double(plain.x)");
  const std::vector<DoubleAttribute> fed{{0, 3}, {2, 3}, {4, 2}, {5, 2}, {6, 1}, {7, 2}};
  ASSERT_EQ(readDoubleInputsAsWords(spirv, fed), "");
  std::string error;
  EXPECT_TRUE(validateSpirv(spirv, &error)) << error;
  const InputFacts facts = inputsOf(spirv);
  EXPECT_TRUE(facts.doubleLocations.empty());
  // dvec3 columns: words at L and L+1; a dvec4 fed by a Double2: words at 7 only; `plain` kept.
  EXPECT_EQ(facts.wordLocations, (std::vector<uint32_t>{0, 1, 2, 3, 4, 5, 6, 7, 9}));
}

TEST(DoubleVertexInputs, AnInputTheAttributesDoNotFeedIsLeftAsItWas) {
  const std::vector<uint32_t> before = vertexModule("layout(location = 0) in dvec2 v;", "v.y");
  std::vector<uint32_t> spirv = before;
  EXPECT_EQ(readDoubleInputsAsWords(spirv, {{3, 2}}), "");
  EXPECT_EQ(spirv, before);
}

TEST(DoubleVertexInputs, AnInputOnlyPartlyFedIsRefused) {
  std::vector<uint32_t> spirv = vertexModule("layout(location = 0) in dmat2 m;", "m[1].y");
  EXPECT_EQ(readDoubleInputsAsWords(spirv, {{0, 2}}),
            "the 64-bit vertex input at location 0 is only partly fed by 64-bit attributes");
}

// Before SPIR-V 1.4 an entry point lists only its Input and Output variables: the private copy
// must leave the list.
TEST(DoubleVertexInputs, SpirV10ModulesKeepPrivateCopiesOutOfTheInterface) {
  CompiledShader c = assembleSpirv(R"(
OpCapability Shader
OpCapability Float64
OpMemoryModel Logical GLSL450
OpEntryPoint Vertex %main "main" %d %pos
OpDecorate %d Location 0
OpDecorate %pos BuiltIn Position
%void = OpTypeVoid
%fn = OpTypeFunction %void
%f32 = OpTypeFloat 32
%f64 = OpTypeFloat 64
%v4 = OpTypeVector %f32 4
%pin = OpTypePointer Input %f64
%pout = OpTypePointer Output %v4
%d = OpVariable %pin Input
%pos = OpVariable %pout Output
%main = OpFunction %void None %fn
%label = OpLabel
%x = OpLoad %f64 %d
%f = OpFConvert %f32 %x
%v = OpCompositeConstruct %v4 %f %f %f %f
OpStore %pos %v
OpReturn
OpFunctionEnd
)", "doubles.spvasm");
  ASSERT_TRUE(c.ok()) << c.error;
  std::vector<uint32_t> spirv = c.spirv;
  ASSERT_EQ(spirv[1], 0x00010000u);
  ASSERT_EQ(readDoubleInputsAsWords(spirv, {{0, 1}}), "");
  std::string error;
  EXPECT_TRUE(validateSpirv(spirv, &error)) << error;
  EXPECT_EQ(inputsOf(spirv).wordLocations, (std::vector<uint32_t>{0}));
}

}  // namespace
}  // namespace parity::rhi
