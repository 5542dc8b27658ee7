// Conformance of rhi::ShaderDesc::arbProgram: a device that offers "arbAssemblyPrograms" (GL in a
// compatibility context) draws with the driver's ARB assembly programs, which read OpenGL's
// matrices (setTransformMatrices), current attributes (setCurrentAttribute), their parameters
// (setProgramParameter) and texture unit N at
// the port's binding N; the others refuse such a shader with a note naming the limit.
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

constexpr uint32_t kSize = 8;
constexpr uint32_t kTextureUnit = 2;

// The position through the model-view-projection matrix; the colour an environment parameter
// times the current colour; the texture coordinate the current one of unit 1.
const char* kVertexProgram = R"(!!ARBvp1.0
PARAM mvp[4] = { state.matrix.mvp };
DP4 result.position.x, mvp[0], vertex.position;
DP4 result.position.y, mvp[1], vertex.position;
DP4 result.position.z, mvp[2], vertex.position;
DP4 result.position.w, mvp[3], vertex.position;
MUL result.color, program.env[0], vertex.color;
MOV result.texcoord[0], vertex.texcoord[1];
END
)";
// colour * local parameter 0 + the texel of unit 2.
const char* kFragmentProgram = R"(!!ARBfp1.0
TEMP t;
TEX t, fragment.texcoord[0], texture[2], 2D;
MAD result.color, fragment.color, program.local[0], t;
END
)";

// The ports: the vertex input at location 0, the fragment program's unit as a sampler at
// binding 2.
const char* kVertexPort = R"(#version 450
layout(location = 0) in vec4 position;
void main() { gl_Position = position; }
)";
const char* kFragmentPort = R"(#version 450
layout(binding = 2) uniform sampler2D unit2;
layout(location = 0) out vec4 color;
void main() { color = texture(unit2, vec2(0.5)); }
)";

std::vector<uint32_t> port(ShaderStage stage, const char* source) {
  CompiledShader c = compileGlslSource(source, "port", stage, {});
  EXPECT_TRUE(c.ok()) << c.error;
  return c.spirv;
}

class RhiArbProgramTest : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    DeviceDesc desc = parity::test::strictDeviceDesc(GetParam());
    desc.glCompatibilityProfile = true;  // where ARB assembly programs exist
    dev = parity::test::makeDeviceWith(desc);
    if (!dev) GTEST_SKIP() << "backend " << GetParam() << " unavailable";
    const auto& features = dev->info().features;
    assembles = std::find(features.begin(), features.end(), "arbAssemblyPrograms") != features.end();
  }
  void TearDown() override { dev.reset(); }

  ShaderHandle program(ShaderStage stage, const char* text, const char* portSource) {
    ShaderDesc d;
    d.stage = stage;
    d.spirv = port(stage, portSource);
    d.arbProgram = text;
    d.label = stage == ShaderStage::Vertex ? "vertex program" : "fragment program";
    return dev->createShader(d);
  }

  std::unique_ptr<Device> dev;
  bool assembles = false;
};

TEST_P(RhiArbProgramTest, GlDrawsWithTheProgramsParametersAndMatricesOthersRefuseThem) {
  // Mesa's GL offers the assembly languages in every compatibility context.
  EXPECT_EQ(assembles, GetParam() == "gl");
  ShaderHandle vs = program(ShaderStage::Vertex, kVertexProgram, kVertexPort);
  ShaderHandle fs = program(ShaderStage::Fragment, kFragmentProgram, kFragmentPort);
  if (!assembles) {
    EXPECT_FALSE(vs);
    EXPECT_FALSE(fs);
    const std::vector<std::string> notes = dev->takeNotes();
    ASSERT_EQ(notes.size(), 2u);
    for (const std::string& note : notes) EXPECT_NE(note.find("ARB assembly programs (GL only)"), std::string::npos) << note;
    return;
  }
  ASSERT_TRUE(vs && fs) << (dev->takeNotes().empty() ? "" : dev->takeNotes()[0]);

  // A triangle over [0, 2] x [0, 2], which covers the target only through glOrtho(0, 1, 0, 1)'s
  // matrix (without it, the lower left of clip space stays uncovered).
  const float positions[] = {0, 0, 2, 0, 0, 2};
  BufferDesc vb;
  vb.size = sizeof positions;
  vb.initialData = positions;
  BufferHandle vertices = dev->createBuffer(vb);
  const uint8_t texel[4] = {0, 0, 255, 0};
  TextureDesc td;
  td.initialData = texel;
  TextureHandle texture = dev->createTexture(td);

  PipelineDesc d;
  d.vertexShader = vs;
  d.fragmentShader = fs;
  d.attributeCount = 1;
  d.attributes[0].format = VertexFormat::Float2;
  d.vertexBuffers[0].stride = 8;
  d.colorTargetCount = 1;
  d.colorTargets[0].format = Format::RGBA8;
  d.label = "arb programs";
  PipelineHandle pipeline = dev->createPipeline(d);
  ASSERT_TRUE(pipeline) << (dev->takeNotes().empty() ? "" : dev->takeNotes()[0]);

  td = {};
  td.width = td.height = kSize;
  TextureHandle color = dev->createTexture(td);
  PassDesc pass;
  pass.colors[0].texture = color;
  pass.colors[0].clearColor = {1, 0, 0, 1};
  dev->beginPass(pass);
  dev->setPipeline(pipeline);
  dev->setTransformMatrices({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, {2, 0, 0, 0, 0, 2, 0, 0, 0, 0, -1, 0, -1, -1, 0, 1});
  dev->setProgramParameter(ShaderStage::Vertex, false, 0, {1.0f, 0.5f, 0.0f, 1.0f});
  dev->setProgramParameter(ShaderStage::Fragment, true, 0, {0.5f, 1.0f, 0.0f, 0.5f});
  dev->setCurrentAttribute(Device::CurrentAttribute::Color, 0, {0.5f, 1.0f, 1.0f, 1.0f});
  dev->setCurrentAttribute(Device::CurrentAttribute::TexCoord, 1, {0.5f, 0.5f, 0.0f, 1.0f});
  ResourceBinding binding;
  binding.binding = kTextureUnit;
  binding.kind = BindingKind::SampledTexture;
  binding.texture = texture;
  dev->setBindings({&binding, 1});
  dev->setVertexBuffer(0, vertices);
  dev->draw(3);
  dev->endPass();

  // (1, 0.5, 0, 1) * (0.5, 1, 1, 1) * (0.5, 1, 0, 0.5) + (0, 0, 1, 0).
  const int want[4] = {64, 128, 255, 128};
  const std::vector<uint8_t> rgba = dev->readTexture(color);
  ASSERT_EQ(rgba.size(), size_t(kSize) * kSize * 4);
  for (size_t i = 0; i < rgba.size(); i += 4)
    for (int c = 0; c < 4; ++c) ASSERT_NEAR(rgba[i + c], want[c], 1) << "pixel " << i / 4 << " channel " << c;
}

INSTANTIATE_TEST_SUITE_P(Backends, RhiArbProgramTest, ::testing::ValuesIn(allBackends()), BackendName());

}  // namespace
}  // namespace parity::rhi
