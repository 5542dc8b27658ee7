// Conformance of rhi::PipelineDesc::separablePrograms: on a device whose driver compiles OpenGL
// GLSL, the stages link as one separable program (GL_PROGRAM_SEPARABLE), where OpenGL wants a
// stage that uses gl_PerVertex's members to redeclare the block: the driver refuses what an
// ordinary program links, and links the same stages once they redeclare it. Other backends run
// the ports, which the flag does not change.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "rhi/rhi.h"
#include "rhi/shader_compiler.h"
#include "tests/test_support.h"

namespace parity::rhi {
namespace {

using parity::test::allBackends;
using parity::test::BackendName;

// The vertex stage writes gl_PointSize and the geometry stage reads it, neither redeclaring
// gl_PerVertex (or, with kRedeclared, both redeclaring it).
const char* kVs = R"(#version 150
in vec4 position;
void main() { gl_Position = position; gl_PointSize = 1.0; }
)";
const char* kVsRedeclared = R"(#version 150
#extension GL_ARB_separate_shader_objects : require
out gl_PerVertex { vec4 gl_Position; float gl_PointSize; };
in vec4 position;
void main() { gl_Position = position; gl_PointSize = 1.0; }
)";
const char* kGs = R"(#version 150
layout(points) in;
layout(points, max_vertices = 1) out;
out vec4 size;
void main() { size = vec4(gl_in[0].gl_PointSize); gl_Position = gl_in[0].gl_Position; EmitVertex(); }
)";
const char* kGsRedeclared = R"(#version 150
#extension GL_ARB_separate_shader_objects : require
layout(points) in;
layout(points, max_vertices = 1) out;
in gl_PerVertex { vec4 gl_Position; float gl_PointSize; } gl_in[];
out gl_PerVertex { vec4 gl_Position; };
out vec4 size;
void main() { size = vec4(gl_in[0].gl_PointSize); gl_Position = gl_in[0].gl_Position; EmitVertex(); }
)";
const char* kFs = R"(#version 150
in vec4 size;
out vec4 color;
void main() { color = size; }
)";

std::vector<uint32_t> port(ShaderStage stage, const char* source) { return parity::test::openGlPort(stage, source); }

class RhiSeparableProgramsTest : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    dev = parity::test::makeDeviceWith(parity::test::strictDeviceDesc(GetParam()));
    if (!dev) GTEST_SKIP() << "backend " << GetParam() << " unavailable";
    const auto& features = dev->info().features;
    driverCompiles = std::find(features.begin(), features.end(), "openGlGlsl") != features.end();
  }
  void TearDown() override { dev.reset(); }

  ShaderHandle shader(ShaderStage stage, const char* openGl) {
    ShaderDesc d;
    d.stage = stage;
    d.spirv = port(stage, openGl);
    d.openGlGlsl = {openGl};
    d.label = "separable";
    ShaderHandle h = dev->createShader(d);
    EXPECT_TRUE(h);
    return h;
  }
  PipelineDesc pipelineDesc(const char* vs, const char* gs, bool separable) {
    PipelineDesc d;
    d.vertexShader = shader(ShaderStage::Vertex, vs);
    d.geometryShader = shader(ShaderStage::Geometry, gs);
    d.fragmentShader = shader(ShaderStage::Fragment, kFs);
    d.topology = PrimitiveTopology::Points;
    d.attributeCount = 1;
    d.attributes[0].location = 0;
    d.attributes[0].format = VertexFormat::Float4;
    d.vertexBuffers[0].stride = 16;
    d.colorTargetCount = 1;
    d.colorTargets[0].format = Format::RGBA8;
    d.separablePrograms = separable;
    d.label = "separable";
    return d;
  }

  std::unique_ptr<Device> dev;
  bool driverCompiles = false;
};

TEST_P(RhiSeparableProgramsTest, ASeparableProgramMustRedeclareThePerVertexBlockItUses) {
  EXPECT_FALSE(PipelineDesc{}.separablePrograms);  // the default: an ordinary program
  PipelineHandle ordinary = dev->createPipeline(pipelineDesc(kVs, kGs, false));
  EXPECT_TRUE(ordinary);
  PipelineHandle separable = dev->createPipeline(pipelineDesc(kVs, kGs, true));
  if (driverCompiles) {
    EXPECT_FALSE(separable) << "the driver linked a separable program that uses gl_PerVertex without redeclaring it";
    std::string notes;
    for (const std::string& n : dev->takeNotes()) notes += n + "\n";
    EXPECT_NE(notes.find("gl_PerVertex"), std::string::npos) << notes;
  } else {
    EXPECT_TRUE(separable) << "the ports are separate modules whatever the flag";
  }
  EXPECT_TRUE(dev->createPipeline(pipelineDesc(kVsRedeclared, kGsRedeclared, true)));
}

INSTANTIATE_TEST_SUITE_P(Backends, RhiSeparableProgramsTest, ::testing::ValuesIn(allBackends()), BackendName());

}  // namespace
}  // namespace parity::rhi
