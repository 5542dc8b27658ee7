// Conformance of rhi::ShaderDesc::openGlGlsl on every backend: a device that offers "openGlGlsl"
// (GL) runs the OpenGL GLSL through its driver, placed by the port's interface (input locations
// by name, loose uniforms copied from the port's gl_DefaultUniformBlock, OpenGL's clip-space
// depth); the others run the port. The port here computes something else on purpose, so each
// image says which of the two ran.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "harness/scripts/spirv_interface.h"
#include "rhi/rhi.h"
#include "rhi/shader_compiler.h"
#include "tests/test_support.h"

namespace parity::rhi {
namespace {

using parity::test::allBackends;
using parity::test::BackendName;

constexpr uint32_t kSize = 8;

// GLSL 1.40 in a compatibility context: an input without a location, gl_FragColor, loose
// uniforms of several shapes (an array, a matrix, an int, a struct with a bool), and a uniform
// block of OpenGL's default `shared` layout, which Mesa packs otherwise than the port's std140.
const char* kOpenGlVs = R"(#version 140
in vec4 position;
void main() { gl_Position = position; }
)";
const char* kOpenGlFs = R"(#version 140
uniform Shared { float f[3]; };
uniform vec4 tint;
uniform float scale[2];
uniform mat3 m;
uniform int k;
struct S { vec2 a; bool b; };
uniform S s;
void main() {
  gl_FragColor = vec4(tint.r * scale[1], m[2][1], float(k) / 4.0, s.b ? s.a.y * f[2] : 0.0);
  gl_FragDepth = gl_FragCoord.z;
}
)";

// The ports, as glslang's OpenGL rules compile them (ShaderCompileOptions::openGlSource): the
// input at another location than OpenGL would give it, OpenGL's clip-space depth moved into the
// RHI's, the same uniforms, and a colour of its own.
const char* kPortVs = R"(#version 450
layout(location = 3) in vec4 position;
void main() { gl_Position = vec4(position.xy, (position.z + position.w) * 0.5, position.w); }
)";
const char* kPortFs = R"(#version 450
uniform Shared { float f[3]; };
uniform vec4 tint;
uniform float scale[2];
uniform mat3 m;
uniform int k;
struct S { vec2 a; bool b; };
uniform S s;
out vec4 color;
void main() {
  float unused = tint.r * scale[1] * m[2][1] * float(k) * s.a.y * float(s.b) * f[2];
  color = vec4(0.0, 0.0, 1.0, 1.0) + 0.0 * unused;
  gl_FragDepth = gl_FragCoord.z;
}
)";

constexpr uint32_t kUniformBinding = 1;

std::vector<uint32_t> port(ShaderStage stage, const char* source) { return parity::test::openGlPort(stage, source, kUniformBinding); }

class RhiOpenGlGlslTest : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    DeviceDesc desc = parity::test::strictDeviceDesc(GetParam());
    desc.glCompatibilityProfile = true;  // gl_FragColor
    dev = parity::test::makeDeviceWith(desc);
    if (!dev) GTEST_SKIP() << "backend " << GetParam() << " unavailable";
    const auto& features = dev->info().features;
    driverCompiles = std::find(features.begin(), features.end(), "openGlGlsl") != features.end();
  }
  void TearDown() override { dev.reset(); }

  ShaderHandle shader(ShaderStage stage, const char* openGl, const std::vector<uint32_t>& spirv) {
    ShaderDesc d;
    d.stage = stage;
    d.spirv = spirv;
    d.openGlGlsl = {openGl};
    d.label = "opengl glsl";
    ShaderHandle h = dev->createShader(d);
    EXPECT_TRUE(h);
    return h;
  }

  std::unique_ptr<Device> dev;
  bool driverCompiles = false;
};

void put(std::vector<uint8_t>& block, const std::vector<uint32_t>& spirv, const std::string& path, const void* value, size_t bytes) {
  std::optional<harness::script::UniformSlot> slot = harness::script::findUniform(spirv, "gl_DefaultUniformBlock", path);
  ASSERT_TRUE(slot) << path;
  ASSERT_LE(slot->offset + bytes, block.size()) << path;
  std::memcpy(block.data() + slot->offset, value, bytes);
}

TEST_P(RhiOpenGlGlslTest, TheDriverRunsTheOpenGlGlslWithThePortsInterfaceAndOtherBackendsThePort) {
  const std::vector<uint32_t> vsPort = port(ShaderStage::Vertex, kPortVs), fsPort = port(ShaderStage::Fragment, kPortFs);
  ASSERT_FALSE(vsPort.empty());
  ASSERT_FALSE(fsPort.empty());

  std::vector<uint8_t> block(256, 0);
  const float tint[4] = {0.5f, 0, 0, 0}, scale1 = 1.0f, m21 = 0.25f, a[2] = {0.0f, 1.0f};
  const int32_t k = 3;
  const uint32_t b = 1;
  put(block, fsPort, "tint", tint, sizeof tint);
  put(block, fsPort, "scale[1]", &scale1, sizeof scale1);
  std::optional<harness::script::UniformSlot> m = harness::script::findUniform(fsPort, "gl_DefaultUniformBlock", "m");
  ASSERT_TRUE(m);
  std::memcpy(block.data() + m->offset + 2 * m->matrixStride + 4, &m21, 4);  // column 2, row 1
  put(block, fsPort, "k", &k, sizeof k);
  put(block, fsPort, "s.a", a, sizeof a);
  put(block, fsPort, "s.b", &b, sizeof b);

  BufferDesc ubo;
  ubo.size = block.size();
  ubo.initialData = block.data();
  BufferHandle uniforms = dev->createBuffer(ubo);
  // The shared block, written in the port's layout.
  std::optional<harness::script::UniformBlockInfo> shared = harness::script::findUniformBlock(fsPort, "Shared");
  std::optional<harness::script::UniformSlot> f2 = harness::script::findUniform(fsPort, "Shared", "f[2]");
  ASSERT_TRUE(shared && f2);
  ASSERT_NE(shared->binding, kUniformBinding);
  std::vector<uint8_t> sharedBytes(std::max<size_t>(shared->size, 64), 0);
  const float one = 1.0f;
  std::memcpy(sharedBytes.data() + f2->offset, &one, 4);
  ubo.size = sharedBytes.size();
  ubo.initialData = sharedBytes.data();
  BufferHandle sharedBuffer = dev->createBuffer(ubo);
  // A triangle over the whole target at OpenGL's clip-space z = -0.5: depth (z + 1) / 2 = 0.25
  // (the RHI's own clip space would clip it away).
  const float positions[] = {-1, -1, -0.5f, 1, 3, -1, -0.5f, 1, -1, 3, -0.5f, 1};
  BufferDesc vb;
  vb.size = sizeof positions;
  vb.initialData = positions;
  BufferHandle vertices = dev->createBuffer(vb);

  PipelineDesc d;
  d.vertexShader = shader(ShaderStage::Vertex, kOpenGlVs, vsPort);
  d.fragmentShader = shader(ShaderStage::Fragment, kOpenGlFs, fsPort);
  d.attributeCount = 1;
  d.attributes[0].location = 3;
  d.attributes[0].format = VertexFormat::Float4;
  d.vertexBuffers[0].stride = 16;
  d.colorTargetCount = 1;
  d.colorTargets[0].format = Format::RGBA8;
  d.depthStencilFormat = Format::D32F;
  d.depthStencil.depthCompare = CompareOp::Always;
  d.depthStencil.depthWrite = true;
  d.label = "opengl glsl";
  PipelineHandle pipeline = dev->createPipeline(d);
  ASSERT_TRUE(pipeline);

  TextureDesc td;
  td.width = td.height = kSize;
  td.format = Format::RGBA8;
  TextureHandle color = dev->createTexture(td);
  td.format = Format::D32F;
  TextureHandle depth = dev->createTexture(td);
  PassDesc pass;
  pass.colors[0].texture = color;
  pass.depthStencil.texture = depth;
  dev->beginPass(pass);
  dev->setPipeline(pipeline);
  ResourceBinding bindings[2];
  bindings[0].binding = kUniformBinding;
  bindings[0].kind = BindingKind::UniformBuffer;
  bindings[0].buffer = uniforms;
  bindings[1].binding = shared->binding;
  bindings[1].kind = BindingKind::UniformBuffer;
  bindings[1].buffer = sharedBuffer;
  dev->setBindings(bindings);
  dev->setVertexBuffer(0, vertices);
  dev->draw(3);
  dev->endPass();

  const std::vector<uint8_t> rgba = dev->readTexture(color);
  ASSERT_EQ(rgba.size(), size_t(kSize) * kSize * 4);
  ReadbackRegion depthAspect;
  depthAspect.aspect = TextureAspect::Depth;
  const std::vector<uint8_t> depthBytes = dev->readTexture(depth, depthAspect);
  ASSERT_EQ(depthBytes.size(), size_t(kSize) * kSize * 4);
  // The driver: (0.5 * 1, 0.25, 3 / 4, 1 * 1); the port: blue.
  const int want[4] = {driverCompiles ? 128 : 0, driverCompiles ? 64 : 0, driverCompiles ? 191 : 255, 255};

  for (size_t i = 0; i < rgba.size(); i += 4) {
    for (int c = 0; c < 4; ++c) ASSERT_NEAR(rgba[i + c], want[c], 1) << "pixel " << i / 4 << " channel " << c;
    float z = 0;
    std::memcpy(&z, depthBytes.data() + i, 4);
    ASSERT_NEAR(z, 0.25f, 1e-6) << "pixel " << i / 4;
  }
}

// Atomic counters (an array of arrays among them): OpenGL keeps them in atomic counter buffers at the bindings the source gives,
// the port (glslang's relaxed rules) in a storage block with members of the same names. The
// port counts differently on purpose, so the buffer says which of the two ran.
const char* kOpenGlCounters = R"(#version 430
layout(local_size_x = 4) in;
layout(binding = 2) uniform atomic_uint first;
layout(binding = 2, offset = 8) uniform atomic_uint third;
layout(binding = 3) uniform atomic_uint grid[2][2];
void main() {
  atomicCounterIncrement(first);
  atomicCounterIncrement(third);
  atomicCounterIncrement(third);
  atomicCounterIncrement(grid[1][0]);
  atomicCounterIncrement(grid[0][1]);
}
)";
const char* kPortCounters = R"(#version 430
layout(local_size_x = 4) in;
layout(binding = 2) uniform atomic_uint first;
layout(binding = 2, offset = 8) uniform atomic_uint third;
layout(binding = 3) uniform atomic_uint grid[2][2];
void main() { atomicCounterIncrement(first); }
)";

TEST_P(RhiOpenGlGlslTest, AtomicCountersAreTheBufferBoundAtThePortsBlock) {
  std::vector<uint32_t> spirv = port(ShaderStage::Compute, kPortCounters);
  ASSERT_FALSE(spirv.empty());
  // glslang's relaxed rules: one storage block per OpenGL binding, gl_AtomicCounterBlock_N, each
  // at binding 0 (a runner moves them apart, as here).
  std::map<std::string, uint32_t> blockBinding;
  for (const harness::script::UniformBlockVariable& b : harness::script::storageBlocks(spirv)) {
    ASSERT_NE(b.bindingWord, 0u);
    spirv[b.bindingWord] = static_cast<uint32_t>(blockBinding.size());
    blockBinding[b.typeName] = spirv[b.bindingWord];
  }
  ASSERT_EQ(blockBinding.size(), 2u);

  const uint32_t zeros[4] = {0, 0, 0, 0};
  BufferDesc bd;
  bd.size = sizeof zeros;
  bd.usage = BufferUsage_Storage;
  bd.initialData = zeros;
  BufferHandle counters[2] = {dev->createBuffer(bd), dev->createBuffer(bd)};
  ComputePipelineDesc cd;
  cd.computeShader = shader(ShaderStage::Compute, kOpenGlCounters, spirv);
  ComputePipelineHandle pipeline = dev->createComputePipeline(cd);
  ASSERT_TRUE(pipeline);
  ResourceBinding b[2];
  for (int i = 0; i < 2; ++i) {
    b[i].binding = blockBinding.at(i == 0 ? "gl_AtomicCounterBlock_2" : "gl_AtomicCounterBlock_3");
    b[i].kind = BindingKind::StorageBuffer;
    b[i].buffer = counters[i];
  }
  dev->setComputePipeline(pipeline);
  dev->setBindings(b);
  dev->dispatch(3, 1, 1);

  // 12 invocations: the driver's program counts 12 at offset 0 and 24 at offset 8 of binding 2,
  // and 12 in grid[0][1] and grid[1][0] (offsets 4 and 8 of binding 3); the port 12 at 0 of binding 2.
  const uint32_t want[2][4] = {{12, 0, driverCompiles ? 24u : 0u, 0}, {0, driverCompiles ? 12u : 0u, driverCompiles ? 12u : 0u, 0}};
  for (int i = 0; i < 2; ++i) {
    std::vector<uint8_t> bytes = dev->readBuffer(counters[i], 0, sizeof zeros);
    ASSERT_EQ(bytes.size(), sizeof zeros);
    uint32_t got[4];
    std::memcpy(got, bytes.data(), sizeof got);
    for (int w = 0; w < 4; ++w) EXPECT_EQ(got[w], want[i][w]) << "binding " << (i + 2) << " word " << w;
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, RhiOpenGlGlslTest, ::testing::ValuesIn(allBackends()), BackendName());

}  // namespace
}  // namespace parity::rhi
