// VkRunner's [test] grammar as its README gives it, each construct run through `parity test` on
// every backend: pipeline properties that change between draws (one pipeline per set of them),
// `STAGE entrypoint NAME`, `ubo|ssbo|push layout`, lines continued with '\'. Each probe fails
// where the construct is ignored: the defaults (all channels written, no culling, no blending,
// the first entry point, std430/std140 column-major) give another image or other values.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "harness/run/process.h"
#include "harness/scripts/script.h"
#include "harness/scripts/shader_test_parser.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace parity;

namespace {

using parity::test::requiredBackend;

class VkRunnerGrammar : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("parity-vkrunner-test-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  // `parity test FILE` on every backend: each case's (backend, result, reason).
  std::vector<std::tuple<std::string, std::string, std::string>> run(const std::string& name, const std::string& text) {
    const fs::path file = dir_ / name;
    std::ofstream(file) << text;
    auto r = harness::runProcess({PARITY_BINARY, "test", file.string(), "--platform", "reference", "--json"}, 280);
    std::vector<std::tuple<std::string, std::string, std::string>> out;
    nlohmann::json j = nlohmann::json::parse(r.out, nullptr, false);
    EXPECT_FALSE(j.is_discarded()) << r.out << r.err;
    if (j.is_discarded()) return out;
    for (const auto& c : j["cases"]) {
      std::string reason = c.value("reason", "");
      for (const auto& e : c.value("expects", nlohmann::json::array())) reason += " " + e.value("message", "");
      if (c["result"] == "SKIP" && reason.find("unavailable") != std::string::npos && !requiredBackend(c["backend"])) continue;
      out.emplace_back(c["backend"], c["result"], reason);
    }
    EXPECT_FALSE(out.empty()) << r.out << r.err;
    return out;
  }
  void expectPass(const std::string& name, const std::string& text) {
    for (const auto& [backend, result, reason] : run(name, text)) EXPECT_EQ(result, "PASS") << name << " on " << backend << ": " << reason;
  }
  fs::path dir_;
};

// README: "If multiple draw calls are issued with different values for these properties then a
// separate pipeline will be created for each set of state." Write masks, culling and blending
// with VkRunner's default factors (src alpha, one minus src alpha), each changed between draws;
// a line continued with '\' sets one of them.
TEST_F(VkRunnerGrammar, PropertiesChangeBetweenDraws) {
  expectPass("properties.shader_test", R"([vertex shader passthrough]
[fragment shader]
#version 450
layout(location = 0) out vec4 color;
void main() { color = vec4(1.0, 1.0, 1.0, 0.5); }
[test]
clear color 0 0 0 0
clear
colorWriteMask VK_COLOR_COMPONENT_R_BIT
draw rect -1 -1 1 1
colorWriteMask VK_COLOR_COMPONENT_G_BIT | \
               VK_COLOR_COMPONENT_B_BIT
draw rect 0 -1 1 1
colorWriteMask 15
# draw rect's triangles are clockwise in framebuffer coordinates (y down)
cullMode VK_CULL_MODE_FRONT_BIT
frontFace VK_FRONT_FACE_CLOCKWISE
draw rect -1 0 1 1
cullMode VK_CULL_MODE_NONE
blendEnable true
draw rect 0 0 1 1
probe rect rgba (0, 0, 125, 125) (1.0, 0.0, 0.0, 0.0)
probe rect rgba (125, 0, 125, 125) (0.0, 1.0, 1.0, 0.0)
probe rect rgba (0, 125, 125, 125) (0.0, 0.0, 0.0, 0.0)
probe rect rgba (125, 125, 125, 125) (0.5, 0.5, 0.5, 0.25)
)");
}

// Depth and stencil properties per draw: the first rect writes depth 0.5 and stencil 1 where
// it lands; the second, nearer everywhere, passes only where the stencil is 1 and the third,
// farther, only where the depth test is off.
TEST_F(VkRunnerGrammar, DepthAndStencilPropertiesPerDraw) {
  expectPass("depth-stencil.shader_test", R"([require]
depthstencil D24_UNORM_S8_UINT
[vertex shader]
#version 450
layout(location = 0) in vec4 position;
layout(push_constant) uniform block { float depth; vec4 color; };
void main() { gl_Position = vec4(position.xy, depth, 1.0); }
[fragment shader]
#version 450
layout(push_constant) uniform block { float depth; vec4 color; };
layout(location = 0) out vec4 out_color;
void main() { out_color = color; }
[test]
clear color 0 0 0 1
clear depth 1.0
clear stencil 0
clear
depthTestEnable true
depthWriteEnable true
depthCompareOp VK_COMPARE_OP_LESS
stencilTestEnable true
front.passOp VK_STENCIL_OP_REPLACE
back.passOp VK_STENCIL_OP_REPLACE
front.reference 1
back.reference 1
uniform float 0 0.5
uniform vec4 16 1 0 0 1
draw rect -1 -1 1 2
front.passOp VK_STENCIL_OP_KEEP
back.passOp VK_STENCIL_OP_KEEP
front.compareOp VK_COMPARE_OP_EQUAL
back.compareOp VK_COMPARE_OP_EQUAL
uniform float 0 0.25
uniform vec4 16 0 1 0 1
draw rect -1 -1 2 1
stencilTestEnable false
depthTestEnable false
uniform float 0 0.75
uniform vec4 16 0 0 1 1
draw rect -1 0 2 1
probe rect rgba (0, 0, 125, 125) (0.0, 1.0, 0.0, 1.0)
probe rect rgba (125, 0, 125, 125) (0.0, 0.0, 0.0, 1.0)
probe rect rgba (0, 125, 250, 125) (0.0, 0.0, 1.0, 1.0)
)");
}

// Stencil state of the front face alone, as VkRunner's files set it: the back face keeps
// VkRunner's defaults (compare always, keep), so its reference and masks (0, all ones) are never
// used and do not stand in the way of the RHI's single reference.
TEST_F(VkRunnerGrammar, StencilStateOfOneFace) {
  expectPass("front-stencil.shader_test", R"([require]
depthstencil D24_UNORM_S8_UINT
[vertex shader passthrough]
[fragment shader]
#version 450
layout(push_constant) uniform block { vec4 color; };
layout(location = 0) out vec4 out_color;
void main() { out_color = color; }
[test]
clear
stencilTestEnable true
frontFace VK_FRONT_FACE_CLOCKWISE
front.passOp VK_STENCIL_OP_REPLACE
front.reference 1
uniform vec4 0 1 0 0 1
draw rect -1 -1 1 2
front.passOp VK_STENCIL_OP_KEEP
front.compareOp VK_COMPARE_OP_EQUAL
uniform vec4 0 0 1 0 1
draw rect -1 -1 2 2
probe rect rgba (0, 0, 125, 250) (0.0, 1.0, 0.0, 1.0)
probe rect rgba (125, 0, 125, 250) (0.0, 0.0, 0.0, 0.0)
)");
}

// README: "STAGE entrypoint NAME sets the entrypoint function to NAME for the given stage. This
// will be used for subsequent draw calls or compute dispatches." One SPIR-V module with two
// fragment entry points.
TEST_F(VkRunnerGrammar, EntryPointsPerDraw) {
  expectPass("entrypoints.shader_test", R"([vertex shader passthrough]
[fragment shader spirv]
               OpCapability Shader
               OpMemoryModel Logical GLSL450
               OpEntryPoint Fragment %first "first" %out
               OpEntryPoint Fragment %second "second" %out
               OpExecutionMode %first OriginUpperLeft
               OpExecutionMode %second OriginUpperLeft
               OpDecorate %out Location 0
       %void = OpTypeVoid
         %fn = OpTypeFunction %void
      %float = OpTypeFloat 32
       %vec4 = OpTypeVector %float 4
        %ptr = OpTypePointer Output %vec4
        %out = OpVariable %ptr Output
       %zero = OpConstant %float 0
        %one = OpConstant %float 1
       %blue = OpConstantComposite %vec4 %zero %zero %one %one
     %yellow = OpConstantComposite %vec4 %one %one %zero %one
      %first = OpFunction %void None %fn
         %l1 = OpLabel
               OpStore %out %blue
               OpReturn
               OpFunctionEnd
     %second = OpFunction %void None %fn
         %l2 = OpLabel
               OpStore %out %yellow
               OpReturn
               OpFunctionEnd
[test]
fragment entrypoint second
draw rect -1 -1 2 1
fragment entrypoint first
draw rect -1 0 2 1
probe rect rgba (0, 0, 250, 125) (1.0, 1.0, 0.0, 1.0)
probe rect rgba (0, 125, 250, 125) (0.0, 0.0, 1.0, 1.0)
)");
}

// `ubo|ssbo|push layout [std140|std430] [row_major|column_major]`: how later commands lay out
// typed values in that kind of buffer. The shader copies a std140 push-constant array (a float
// every 16 bytes) and a std140 row-major matrix into std430 buffers, column- and row-major; the
// probes read them back in each layout, and the last one reads the row-major bytes as plain
// vectors. (A std140 *storage* block of a row-major mat2xN is left out: SPIRV-Cross declares it
// std430 on GL, docs/script-format.md.)
TEST_F(VkRunnerGrammar, BlockLayoutsOfTypedValues) {
  expectPass("layouts.shader_test", R"([compute shader]
#version 450
layout(local_size_x = 1) in;
layout(push_constant, std140) uniform push140 { float pushed[2]; };
layout(binding = 0, std140) uniform ubo140 { layout(row_major) mat2x3 m; };
layout(binding = 1, std430) buffer columns430 { float copied[2]; mat2x3 column; };
layout(binding = 2, std430) buffer rows430 { layout(row_major) mat2x3 row; };
void main() {
  copied[0] = pushed[0];
  copied[1] = pushed[1];
  column = m;
  row = m;
}
[test]
push layout std140
uniform float 0 1.5 2.5
ubo layout std140 row_major
uniform ubo 0 mat2x3 0 1 2 3 4 5 6
ssbo 1 64
ssbo 2 64
compute 1 1 1
probe ssbo float 1 0 == 1.5 2.5
probe ssbo mat2x3 1 16 == 1 2 3 4 5 6
ssbo layout row_major
probe ssbo mat2x3 2 0 == 1 2 3 4 5 6
ssbo layout column_major
probe ssbo vec2 2 0 == 1 4
probe ssbo vec2 2 8 == 2 5
)");
}

// Properties the RHI cannot express skip the file naming them, at the draw that uses them;
// values that are not the property's are errors naming the file and line.
TEST_F(VkRunnerGrammar, UnsupportedPropertiesSkipAndBadValuesAreErrors) {
  const std::string shaders = R"([vertex shader passthrough]
[fragment shader]
#version 450
layout(location = 0) out vec4 color;
void main() { color = vec4(1.0); }
[vertex data]
0/R32G32_SFLOAT
-1 -1
1 1
[test]
)";
  for (const auto& [backend, result, reason] : run("logic.shader_test", shaders + "logicOpEnable true\nlogicOp VK_LOGIC_OP_XOR\ndraw rect -1 -1 2 2\n")) {
    EXPECT_EQ(result, "SKIP") << backend;
    EXPECT_NE(reason.find("logicOpEnable"), std::string::npos) << reason;
  }
  // A wide line only matters to draws of lines.
  expectPass("wide.shader_test", shaders + "lineWidth 4.0\ndraw rect -1 -1 2 2\nprobe all rgba 1 1 1 1\n");
  for (const auto& [backend, result, reason] : run("wide-lines.shader_test", shaders + "lineWidth 4.0\ndraw arrays LINE_LIST 0 2\n")) {
    EXPECT_EQ(result, "SKIP") << backend;
    EXPECT_NE(reason.find("lineWidth 4"), std::string::npos) << reason;
  }
  auto parsed = harness::script::parseShaderTest(shaders + "cullMode VK_COMPARE_OP_LESS\n", "bad.shader_test");
  EXPECT_FALSE(parsed.ok);
  EXPECT_EQ(parsed.error.rfind("bad.shader_test:11: error: cullMode: unknown value 'VK_COMPARE_OP_LESS'", 0), 0u) << parsed.error;
  parsed = harness::script::parseShaderTest(shaders + "ssbo layout std999\n", "bad.shader_test");
  EXPECT_EQ(parsed.error.rfind("bad.shader_test:11: error: ssbo layout: expected std140", 0), 0u) << parsed.error;
  parsed = harness::script::parseShaderTest(shaders + "pixel entrypoint main\n", "bad.shader_test");
  EXPECT_EQ(parsed.error.rfind("bad.shader_test:11: error: unknown stage 'pixel'", 0), 0u) << parsed.error;
}

// One pipeline per set of properties, and no more: a draw that returns to the first draw's
// properties runs the first pipeline again.
TEST(VkRunnerGrammarParse, OnePipelinePerSetOfProperties) {
  auto r = harness::script::parseShaderTest(R"([vertex shader passthrough]
[fragment shader]
#version 450
layout(location = 0) out vec4 color;
void main() { color = vec4(1.0); }
[test]
depthTestEnable true
draw rect -1 -1 1 1
depthTestEnable false
draw rect 0 0 1 1
depthTestEnable true
draw rect 0 -1 1 1
depthTestEnable false
draw rect -1 0 1 1
)",
                                            "t.shader_test");
  ASSERT_TRUE(r.ok) << r.error;
  std::vector<std::string> used;
  for (const auto& c : r.script.commands)
    if (c.kind == harness::script::Command::Kind::DrawRect) used.push_back(c.pipeline);
  EXPECT_EQ(used, (std::vector<std::string>{"rect", "rect state 1", "rect", "rect state 1"}));
  EXPECT_TRUE(r.script.findPipeline("rect")->depthTest);
  EXPECT_FALSE(r.script.findPipeline("rect state 1")->depthTest);
}

}  // namespace
