// Tests of the RHI validation layer (rhi/validation.h): every rule is provoked on every backend,
// and the test checks that exactly that rule's id was reported and that the call never reached
// the backend. A pass-through Device between the validation layer and the real backend counts
// the calls that get through; the driver's own debug output (GL debug context, Vulkan
// validation layer) must stay silent, which shows that nothing invalid was forwarded.
//
// Tests are named after the rule they provoke; RhiValidationRules.EveryRuleHasATest checks that
// no rule is left without one.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "rhi/shader_compiler.h"
#include "rhi/validation.h"
#include "tests/test_support.h"

namespace parity::rhi {
namespace {

using parity::test::allBackends;
using parity::test::BackendName;

// Forwards every call and counts those that change state or read data (info() and describe()
// are not counted: the validation layer may use them freely).
class CountingDevice final : public Device {
 public:
  explicit CountingDevice(std::unique_ptr<Device> inner) : inner_(std::move(inner)) {}
  size_t calls = 0;

  const DeviceInfo& info() const override { return shown_ ? *shown_ : inner_->info(); }
  // Hides a feature from the validation layer, to provoke the rules on what a device lacks.
  void withholdFeature(const std::string& feature) {
    if (!shown_) shown_ = inner_->info();
    std::erase(shown_->features, feature);
  }
  // Shows compute subgroup size control with subgroups of min..max invocations (or none: 0, 0).
  void showSubgroupSizes(uint32_t min, uint32_t max) {
    if (!shown_) shown_ = inner_->info();
    shown_->caps.subgroupSizeControl = max > 0;
    shown_->caps.minSubgroupSize = min, shown_->caps.maxSubgroupSize = max;
  }
  // Hides the 64-bit vertex formats (Capabilities::doubleVertexFormats).
  void withholdDoubleVertexFormats() {
    if (!shown_) shown_ = inner_->info();
    shown_->caps.doubleVertexFormats = false;
  }
  BufferHandle createBuffer(const BufferDesc& d) override { return ++calls, inner_->createBuffer(d); }
  TextureHandle createTexture(const TextureDesc& d) override { return ++calls, inner_->createTexture(d); }
  TextureHandle createTextureView(const TextureViewDesc& d) override { return ++calls, inner_->createTextureView(d); }
  SamplerHandle createSampler(const SamplerDesc& d) override { return ++calls, inner_->createSampler(d); }
  ShaderHandle createShader(const ShaderDesc& d) override { return ++calls, inner_->createShader(d); }
  PipelineHandle createPipeline(const PipelineDesc& d) override { return ++calls, inner_->createPipeline(d); }
  ComputePipelineHandle createComputePipeline(const ComputePipelineDesc& d) override {
    return ++calls, inner_->createComputePipeline(d);
  }
  void destroy(BufferHandle h) override { ++calls, inner_->destroy(h); }
  void destroy(TextureHandle h) override { ++calls, inner_->destroy(h); }
  void destroy(SamplerHandle h) override { ++calls, inner_->destroy(h); }
  void destroy(ShaderHandle h) override { ++calls, inner_->destroy(h); }
  void destroy(PipelineHandle h) override { ++calls, inner_->destroy(h); }
  void destroy(ComputePipelineHandle h) override { ++calls, inner_->destroy(h); }
  const BufferDesc* describe(BufferHandle h) const override { return inner_->describe(h); }
  const TextureDesc* describe(TextureHandle h) const override { return inner_->describe(h); }
  void writeBuffer(BufferHandle h, size_t o, const void* d, size_t s) override {
    ++calls, inner_->writeBuffer(h, o, d, s);
  }
  void writeTexture(TextureHandle h, uint32_t l, uint32_t m, const void* d) override {
    ++calls, inner_->writeTexture(h, l, m, d);
  }
  std::vector<uint8_t> readBuffer(BufferHandle h, size_t o, size_t s) override {
    return ++calls, inner_->readBuffer(h, o, s);
  }
  std::vector<uint8_t> readTexture(TextureHandle h, const ReadbackRegion& r) override {
    return ++calls, inner_->readTexture(h, r);
  }
  void copyTexture(TextureHandle s, TextureHandle d, const ReadbackRegion& sr, const ReadbackRegion& dr) override {
    ++calls, inner_->copyTexture(s, d, sr, dr);
  }
  void copyBuffer(BufferHandle s, size_t so, BufferHandle d, size_t dO, size_t n) override {
    ++calls, inner_->copyBuffer(s, so, d, dO, n);
  }
  void beginPass(const PassDesc& d) override { ++calls, inner_->beginPass(d); }
  void endPass() override { ++calls, inner_->endPass(); }
  void setPipeline(PipelineHandle h) override { ++calls, inner_->setPipeline(h); }
  void setViewport(const Viewport& v) override { ++calls, inner_->setViewport(v); }
  void setScissor(const Rect& r) override { ++calls, inner_->setScissor(r); }
  void setStencilReference(uint8_t r) override { ++calls, inner_->setStencilReference(r); }
  void setBlendConstant(const std::array<float, 4>& c) override { ++calls, inner_->setBlendConstant(c); }
  void setVertexBuffer(uint32_t s, BufferHandle h, size_t o) override { ++calls, inner_->setVertexBuffer(s, h, o); }
  void setIndexBuffer(BufferHandle h, IndexType t, size_t o) override { ++calls, inner_->setIndexBuffer(h, t, o); }
  void draw(uint32_t a, uint32_t b, uint32_t c, uint32_t d) override { ++calls, inner_->draw(a, b, c, d); }
  void drawIndexed(uint32_t a, uint32_t b, uint32_t c, int32_t d, uint32_t e) override {
    ++calls, inner_->drawIndexed(a, b, c, d, e);
  }
  void setComputePipeline(ComputePipelineHandle h) override { ++calls, inner_->setComputePipeline(h); }
  void dispatch(uint32_t x, uint32_t y, uint32_t z) override { ++calls, inner_->dispatch(x, y, z); }
  void setBindings(std::span<const ResourceBinding> b) override { ++calls, inner_->setBindings(b); }
  void pushConstants(const void* d, uint32_t s) override { ++calls, inner_->pushConstants(d, s); }
  TimestampId writeTimestamp() override { return ++calls, inner_->writeTimestamp(); }
  std::optional<uint64_t> timestampNs(TimestampId id) override { return ++calls, inner_->timestampNs(id); }
  void resetTimestamps() override { ++calls, inner_->resetTimestamps(); }
  void submit() override { ++calls, inner_->submit(); }

 private:
  std::unique_ptr<Device> inner_;
  std::optional<DeviceInfo> shown_;
};

const char* kFullscreenVs = R"(#version 450
void main() {
  vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
  gl_Position = vec4(p * 2.0 - 1.0, 0.5, 1.0);
})";

const char* kRedFs = R"(#version 450
layout(location = 0) out vec4 o;
void main() { o = vec4(1.0, 0.0, 0.0, 1.0); })";

const char* kUniformFs = R"(#version 450
layout(set = 0, binding = 0) uniform U { vec4 color; } u;
layout(location = 0) out vec4 o;
void main() { o = u.color; })";

const char* kSamplerFs = R"(#version 450
layout(set = 0, binding = 1) uniform sampler2D tex;
layout(location = 0) out vec4 o;
void main() { o = texelFetch(tex, ivec2(0), 0); })";

const char* kUintSamplerFs = R"(#version 450
layout(set = 0, binding = 1) uniform usampler2D tex;
layout(location = 0) out vec4 o;
void main() { o = vec4(texelFetch(tex, ivec2(0), 0)); })";

const char* kPushFs = R"(#version 450
layout(push_constant) uniform PC { vec4 color; } pc;
layout(location = 0) out vec4 o;
void main() { o = pc.color; })";

const char* kAttributeVs = R"(#version 450
layout(location = 0) in vec2 pos;
void main() { gl_Position = vec4(pos, 0.5, 1.0); })";

const char* kUniformVs = R"(#version 450
layout(set = 0, binding = 0) uniform U { vec4 offset; } u;
void main() {
  vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
  gl_Position = vec4(p * 2.0 - 1.0, 0.5, 1.0) + u.offset;
})";

const char* kStorageCs = R"(#version 450
layout(local_size_x = 1) in;
layout(set = 0, binding = 0) buffer B { uint v[]; } b;
void main() { b.v[gl_GlobalInvocationID.x] = 7u; })";

std::vector<uint32_t> spirv(ShaderStage stage, const char* glsl) {
  CompiledShader c = compileGlslSource(glsl, "validation_test", stage);
  EXPECT_TRUE(c.ok()) << c.error;
  return c.spirv;
}

class RhiValidationTest : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    DeviceDesc desc;
    desc.backend = GetParam();
    desc.validation = false;  // wrapped below, around the counting device
    desc.debug = true;
    desc.log = [this](const std::string& m) { driverMessages_.push_back(m); };
    std::unique_ptr<Device> backend = parity::test::makeDeviceWith(desc);
    if (!backend) GTEST_SKIP() << "backend " << GetParam() << " unavailable";
    auto counting = std::make_unique<CountingDevice>(std::move(backend));
    counter_ = counting.get();
    dev_ = wrapWithValidation(std::move(counting), [this](const std::string& id, const std::string& message) {
      reported_.push_back({id, message});
    });
  }

  void TearDown() override {
    if (!dev_) return;
    // Leave the device idle: end a pass a test left open, run what was recorded.
    dev_->submit();
    dev_.reset();
    EXPECT_TRUE(driverMessages_.empty()) << "driver debug output (an invalid call reached the driver?): "
                                         << driverMessages_.front();
  }

  // Runs `f`, expecting exactly `rule` to be reported and no call to reach the backend.
  template <class F>
  void expectDropped(const char* rule, F&& f) {
    size_t first = reported_.size();
    size_t before = counter_->calls;
    f();
    std::vector<std::string> ids;
    std::string messages;
    for (size_t i = first; i < reported_.size(); ++i) {
      ids.push_back(reported_[i].first);
      messages += reported_[i].first + ": " + reported_[i].second + "\n";
    }
    EXPECT_EQ(ids, std::vector<std::string>{rule}) << messages;
    EXPECT_EQ(counter_->calls, before) << "the invalid call reached the backend";
  }
  // Runs `f`, expecting no report.
  template <class F>
  void expectValid(F&& f) {
    size_t first = reported_.size();
    f();
    for (size_t i = first; i < reported_.size(); ++i)
      ADD_FAILURE() << "unexpected report " << reported_[i].first << ": " << reported_[i].second;
  }
  std::string lastMessage() const { return reported_.empty() ? std::string() : reported_.back().second; }

  // --- object helpers (created validly; a report fails the test) ---
  ShaderHandle shader(ShaderStage stage, const char* glsl) {
    ShaderHandle h;
    expectValid([&] {
      ShaderDesc d;
      d.stage = stage;
      d.spirv = spirv(stage, glsl);
      d.label = "test shader";
      h = dev_->createShader(d);
    });
    EXPECT_TRUE(h);
    return h;
  }
  TextureHandle texture(Format f, uint32_t w = 4, uint32_t h = 4, uint32_t usage = TextureUsage_Default,
                        uint32_t samples = 1, const char* label = "tex") {
    TextureDesc d;
    d.format = f;
    d.width = w;
    d.height = h;
    d.usage = usage;
    d.samples = samples;
    d.label = label;
    TextureHandle t;
    expectValid([&] { t = dev_->createTexture(d); });
    EXPECT_TRUE(t);
    return t;
  }
  BufferHandle buffer(size_t size, uint32_t usage = BufferUsage_All, const char* label = "buf") {
    BufferDesc d;
    d.size = size;
    d.usage = usage;
    d.label = label;
    BufferHandle b;
    expectValid([&] { b = dev_->createBuffer(d); });
    EXPECT_TRUE(b);
    return b;
  }
  PipelineDesc pipelineDesc(ShaderHandle vs, ShaderHandle fs, Format color = Format::RGBA8) {
    PipelineDesc d;
    d.vertexShader = vs;
    d.fragmentShader = fs;
    d.colorTargetCount = 1;
    d.colorTargets[0].format = color;
    d.label = "test pipeline";
    return d;
  }
  PipelineHandle pipeline(const PipelineDesc& d) {
    PipelineHandle p;
    expectValid([&] { p = dev_->createPipeline(d); });
    EXPECT_TRUE(p);
    return p;
  }
  PipelineHandle simplePipeline(const char* fs = kRedFs, Format color = Format::RGBA8) {
    return pipeline(pipelineDesc(shader(ShaderStage::Vertex, kFullscreenVs), shader(ShaderStage::Fragment, fs), color));
  }
  static PassDesc passOn(TextureHandle color, TextureHandle depth = {}) {
    PassDesc p;
    p.colors[0].texture = color;
    p.depthStencil.texture = depth;
    p.label = "test pass";
    return p;
  }
  void begin(TextureHandle color, TextureHandle depth = {}) {
    expectValid([&] { dev_->beginPass(passOn(color, depth)); });
  }
  void end() {
    expectValid([&] { dev_->endPass(); });
  }
  ComputePipelineHandle computePipeline(const char* cs = kStorageCs) {
    ComputePipelineDesc d;
    d.computeShader = shader(ShaderStage::Compute, cs);
    d.label = "test compute";
    ComputePipelineHandle p;
    expectValid([&] { p = dev_->createComputePipeline(d); });
    EXPECT_TRUE(p);
    return p;
  }

  std::unique_ptr<Device> dev_;
  CountingDevice* counter_ = nullptr;
  std::vector<std::pair<std::string, std::string>> reported_;
  std::vector<std::string> driverMessages_;
};

// ---------------------------------------------------------------------------------------------
// A valid sequence reports nothing and works.
// ---------------------------------------------------------------------------------------------
TEST_P(RhiValidationTest, ValidSequenceReportsNothing) {
  expectValid([&] {
    TextureHandle target = texture(Format::RGBA8, 4, 4);
    TextureHandle depth = texture(Format::D24S8, 4, 4);
    uint8_t texel[4] = {10, 20, 30, 40};
    TextureDesc sd;
    sd.width = sd.height = 1;
    sd.usage = TextureUsage_Sampled;
    sd.initialData = texel;
    sd.label = "sampled";
    TextureHandle sampled = dev_->createTexture(sd);
    float color[4] = {0, 1, 0, 1};
    BufferHandle ubo = buffer(256, BufferUsage_Uniform, "ubo");
    dev_->writeBuffer(ubo, 0, color, sizeof(color));

    PipelineDesc pd =
        pipelineDesc(shader(ShaderStage::Vertex, kFullscreenVs), shader(ShaderStage::Fragment, kUniformFs));
    pd.depthStencilFormat = Format::D24S8;
    pd.depthStencil.depthCompare = CompareOp::LessEqual;
    pd.depthStencil.depthWrite = true;
    PipelineHandle p = pipeline(pd);
    PipelineHandle ps = simplePipeline(kSamplerFs);

    TextureHandle scratch = texture(Format::RGBA8, 4, 4, TextureUsage_Default, 1, "scratch");
    ResourceBinding b[2];
    b[0].binding = 0;
    b[0].kind = BindingKind::UniformBuffer;
    b[0].buffer = ubo;
    b[1].binding = 1;
    b[1].kind = BindingKind::SampledTexture;
    b[1].texture = sampled;
    dev_->setBindings(b);
    TimestampId t0 = dev_->writeTimestamp();
    dev_->beginPass(passOn(target, depth));
    dev_->setPipeline(p);
    dev_->setViewport({});
    dev_->draw(3);
    dev_->endPass();
    dev_->beginPass(passOn(scratch));
    dev_->setPipeline(ps);
    dev_->draw(3);
    dev_->endPass();
    TimestampId t1 = dev_->writeTimestamp();

    BufferHandle ssbo = buffer(16, BufferUsage_Storage, "ssbo");
    ResourceBinding sb;
    sb.binding = 0;
    sb.kind = BindingKind::StorageBuffer;
    sb.buffer = ssbo;
    dev_->setComputePipeline(computePipeline());
    dev_->setBindings({&sb, 1});
    dev_->dispatch(4);
    dev_->submit();

    EXPECT_TRUE(dev_->timestampNs(t0).has_value());
    EXPECT_TRUE(dev_->timestampNs(t1).has_value());
    std::vector<uint8_t> px = dev_->readTexture(target);
    ASSERT_EQ(px.size(), 64u);
    EXPECT_EQ(px[0], 0);
    EXPECT_EQ(px[1], 255);
    std::vector<uint8_t> s = dev_->readTexture(scratch);
    ASSERT_EQ(s.size(), 64u);
    EXPECT_EQ(std::vector<uint8_t>(s.begin(), s.begin() + 4), std::vector<uint8_t>({10, 20, 30, 40}));
    std::vector<uint8_t> words = dev_->readBuffer(ssbo, 0, 16);
    ASSERT_EQ(words.size(), 16u);
    uint32_t w3;
    std::memcpy(&w3, words.data() + 12, 4);
    EXPECT_EQ(w3, 7u);
    std::vector<uint8_t> d = dev_->readTexture(depth, {0, 0, TextureAspect::Depth});
    EXPECT_EQ(d.size(), 64u);
    dev_->destroy(BufferHandle{});  // null: no-op
  });
}

TEST_P(RhiValidationTest, DroppedPassReportsOnce) {
  PipelineHandle p = simplePipeline();
  expectDropped("E_PASS_NO_ATTACHMENTS", [&] {
    dev_->beginPass(PassDesc{});
    dev_->setPipeline(p);
    dev_->setViewport({});
    dev_->draw(3);
    dev_->endPass();
  });
  expectValid([&] { dev_->submit(); });
}

// ---------------------------------------------------------------------------------------------
// One test per rule.
// ---------------------------------------------------------------------------------------------
TEST_P(RhiValidationTest, E_HANDLE_INVALID) {
  BufferHandle b = buffer(16);
  expectValid([&] { dev_->destroy(b); });
  uint32_t v = 1;
  expectDropped("E_HANDLE_INVALID", [&] { dev_->writeBuffer(b, 0, &v, 4); });
  expectDropped("E_HANDLE_INVALID", [&] { dev_->destroy(b); });
  expectDropped("E_HANDLE_INVALID", [&] { EXPECT_TRUE(dev_->readTexture(TextureHandle{}).empty()); });
}

TEST_P(RhiValidationTest, E_BUFFER_SIZE_ZERO) {
  expectDropped("E_BUFFER_SIZE_ZERO", [&] {
    BufferDesc d;
    d.label = "empty one";
    EXPECT_FALSE(dev_->createBuffer(d));
  });
  EXPECT_NE(lastMessage().find("'empty one'"), std::string::npos) << lastMessage();
}

TEST_P(RhiValidationTest, E_BUFFER_USAGE) {
  BufferDesc d;
  d.size = 16;
  d.usage = 0;
  expectDropped("E_BUFFER_USAGE", [&] { EXPECT_FALSE(dev_->createBuffer(d)); });
  BufferHandle vb = buffer(256, BufferUsage_Vertex, "vertices only");
  ResourceBinding b;
  b.kind = BindingKind::UniformBuffer;
  b.buffer = vb;
  expectDropped("E_BUFFER_USAGE", [&] { dev_->setBindings({&b, 1}); });
  EXPECT_NE(lastMessage().find("'vertices only'"), std::string::npos) << lastMessage();
  BufferHandle ub = buffer(256, BufferUsage_Uniform);
  expectDropped("E_BUFFER_USAGE", [&] { dev_->setIndexBuffer(ub, IndexType::UInt16); });
}

TEST_P(RhiValidationTest, E_BUFFER_OFFSET) {
  BufferHandle b = buffer(64);
  expectDropped("E_BUFFER_OFFSET", [&] { dev_->setVertexBuffer(0, b, 64); });
  expectDropped("E_BUFFER_OFFSET", [&] { dev_->setIndexBuffer(b, IndexType::UInt32, 2); });
}

TEST_P(RhiValidationTest, E_TEXTURE_SIZE_ZERO) {
  TextureDesc d;
  d.width = 0;
  d.label = "flat";
  expectDropped("E_TEXTURE_SIZE_ZERO", [&] { EXPECT_FALSE(dev_->createTexture(d)); });
  EXPECT_NE(lastMessage().find("'flat'"), std::string::npos);
  d.width = 4;
  d.mipLevels = 0;
  expectDropped("E_TEXTURE_SIZE_ZERO", [&] { EXPECT_FALSE(dev_->createTexture(d)); });
}

TEST_P(RhiValidationTest, E_TEXTURE_SIZE_TOO_LARGE) {
  TextureDesc d;
  d.width = 16385;
  expectDropped("E_TEXTURE_SIZE_TOO_LARGE", [&] { EXPECT_FALSE(dev_->createTexture(d)); });
}

TEST_P(RhiValidationTest, E_TEXTURE_FORMAT_UNDEFINED) {
  TextureDesc d;
  d.format = Format::Undefined;
  expectDropped("E_TEXTURE_FORMAT_UNDEFINED", [&] { EXPECT_FALSE(dev_->createTexture(d)); });
}

TEST_P(RhiValidationTest, E_TEXTURE_LAYERS) {
  TextureDesc d;
  d.layers = 2;  // type stays Tex2D
  expectDropped("E_TEXTURE_LAYERS", [&] { EXPECT_FALSE(dev_->createTexture(d)); });
}

TEST_P(RhiValidationTest, E_TEXTURE_DIMENSION) {
  TextureDesc d;
  d.type = TextureType::Tex1D;
  d.width = 8;
  d.height = 2;
  expectDropped("E_TEXTURE_DIMENSION", [&] { EXPECT_FALSE(dev_->createTexture(d)); });
  d.height = 1;
  expectValid([&] { EXPECT_TRUE(dev_->createTexture(d)); });
  d.layers = 2;  // a 1D array texture
  expectValid([&] { EXPECT_TRUE(dev_->createTexture(d)); });
  d = {};
  d.type = TextureType::Tex3D;
  d.width = d.height = 4;
  d.depth = 3;
  expectValid([&] { EXPECT_TRUE(dev_->createTexture(d)); });
  d.layers = 2;
  expectDropped("E_TEXTURE_DIMENSION", [&] { EXPECT_FALSE(dev_->createTexture(d)); });
  d.layers = 1;
  d.depth = 4096;
  expectDropped("E_TEXTURE_DIMENSION", [&] { EXPECT_FALSE(dev_->createTexture(d)); });
  d = {};
  d.depth = 2;  // Tex2D
  expectDropped("E_TEXTURE_DIMENSION", [&] { EXPECT_FALSE(dev_->createTexture(d)); });
  d.depth = 0;
  expectDropped("E_TEXTURE_SIZE_ZERO", [&] { EXPECT_FALSE(dev_->createTexture(d)); });
  // The mip chain of a 3D texture counts its depth: 1x1x8 has 4 levels.
  d = {};
  d.type = TextureType::Tex3D;
  d.depth = 8;
  d.mipLevels = 4;
  expectValid([&] { EXPECT_TRUE(dev_->createTexture(d)); });
  d.mipLevels = 5;
  expectDropped("E_TEXTURE_MIP_COUNT", [&] { EXPECT_FALSE(dev_->createTexture(d)); });
}

TEST_P(RhiValidationTest, E_TEXTURE_CUBE_LAYERS) {
  TextureDesc d;
  d.type = TextureType::Cube;
  d.width = d.height = 4;
  d.layers = 4;
  expectDropped("E_TEXTURE_CUBE_LAYERS", [&] { EXPECT_FALSE(dev_->createTexture(d)); });
  d.layers = 6;
  d.height = 2;
  expectDropped("E_TEXTURE_CUBE_LAYERS", [&] { EXPECT_FALSE(dev_->createTexture(d)); });
}

TEST_P(RhiValidationTest, E_TEXTURE_MIP_COUNT) {
  TextureDesc d;
  d.width = 4;
  d.height = 2;
  d.mipLevels = 4;  // 4x2, 2x1, 1x1
  expectDropped("E_TEXTURE_MIP_COUNT", [&] { EXPECT_FALSE(dev_->createTexture(d)); });
}

TEST_P(RhiValidationTest, E_TEXTURE_MSAA_SAMPLES) {
  TextureDesc d;
  d.samples = 2;
  expectDropped("E_TEXTURE_MSAA_SAMPLES", [&] { EXPECT_FALSE(dev_->createTexture(d)); });
}

TEST_P(RhiValidationTest, E_TEXTURE_MSAA_INVALID) {
  TextureDesc d;
  d.width = d.height = 4;
  d.samples = 4;
  d.mipLevels = 2;
  expectDropped("E_TEXTURE_MSAA_INVALID", [&] { EXPECT_FALSE(dev_->createTexture(d)); });
  d.mipLevels = 1;
  uint32_t texel[16] = {};
  d.initialData = texel;
  expectDropped("E_TEXTURE_MSAA_INVALID", [&] { EXPECT_FALSE(dev_->createTexture(d)); });
  d.initialData = nullptr;
  // Storage usage only where the device can store to multisampled images.
  d.usage = TextureUsage_RenderTarget | TextureUsage_Storage;
  if (dev_->info().caps.storageMultisample)
    expectValid([&] { EXPECT_TRUE(dev_->createTexture(d)); });
  else
    expectDropped("E_TEXTURE_MSAA_INVALID", [&] { EXPECT_FALSE(dev_->createTexture(d)); });
}

TEST_P(RhiValidationTest, E_TEXTURE_USAGE) {
  TextureDesc d;
  d.format = Format::D32F;
  d.usage = TextureUsage_Sampled | TextureUsage_Storage;
  expectDropped("E_TEXTURE_USAGE", [&] { EXPECT_FALSE(dev_->createTexture(d)); });
  TextureHandle rtOnly = texture(Format::RGBA8, 4, 4, TextureUsage_RenderTarget, 1, "render only");
  ResourceBinding b;
  b.binding = 1;
  b.kind = BindingKind::SampledTexture;
  b.texture = rtOnly;
  expectDropped("E_TEXTURE_USAGE", [&] { dev_->setBindings({&b, 1}); });
  b.kind = BindingKind::StorageTexture;
  expectDropped("E_TEXTURE_USAGE", [&] { dev_->setBindings({&b, 1}); });
}

TEST_P(RhiValidationTest, E_TEXTURE_DESTROY_WITH_VIEWS) {
  TextureHandle parent = texture(Format::RGBA8);
  TextureViewDesc vd;
  vd.parent = parent;
  vd.format = Format::R32_UINT;
  TextureHandle view;
  expectValid([&] { view = dev_->createTextureView(vd); });
  ASSERT_TRUE(view);
  expectDropped("E_TEXTURE_DESTROY_WITH_VIEWS", [&] { dev_->destroy(parent); });
  expectValid([&] {
    dev_->destroy(view);
    dev_->destroy(parent);
  });
}

TEST_P(RhiValidationTest, E_VIEW_PARENT_INVALID) {
  TextureViewDesc vd;
  expectDropped("E_VIEW_PARENT_INVALID", [&] { EXPECT_FALSE(dev_->createTextureView(vd)); });
  vd.parent = texture(Format::RGBA8);
  TextureHandle view;
  expectValid([&] { view = dev_->createTextureView(vd); });
  vd.parent = view;
  expectDropped("E_VIEW_PARENT_INVALID", [&] { EXPECT_FALSE(dev_->createTextureView(vd)); });
}

TEST_P(RhiValidationTest, E_VIEW_SIZE_CLASS) {
  TextureViewDesc vd;
  vd.parent = texture(Format::RGBA8, 4, 4, TextureUsage_Default, 1, "rgba8 storage");
  vd.format = Format::RGBA16F;
  expectDropped("E_VIEW_SIZE_CLASS", [&] { EXPECT_FALSE(dev_->createTextureView(vd)); });
  EXPECT_NE(lastMessage().find("'rgba8 storage'"), std::string::npos);
  vd.format = Format::R8;
  expectDropped("E_VIEW_SIZE_CLASS", [&] { EXPECT_FALSE(dev_->createTextureView(vd)); });
}

TEST_P(RhiValidationTest, E_VIEW_DEPTH) {
  TextureViewDesc vd;
  vd.parent = texture(Format::D32F);
  vd.format = Format::R32F;
  expectDropped("E_VIEW_DEPTH", [&] { EXPECT_FALSE(dev_->createTextureView(vd)); });
  vd.parent = texture(Format::R32F);
  vd.format = Format::D32F;
  expectDropped("E_VIEW_DEPTH", [&] { EXPECT_FALSE(dev_->createTextureView(vd)); });
}

TEST_P(RhiValidationTest, E_VIEW_RANGE) {
  TextureViewDesc vd;
  vd.parent = texture(Format::RGBA8);
  vd.baseLayer = 1;
  expectDropped("E_VIEW_RANGE", [&] { EXPECT_FALSE(dev_->createTextureView(vd)); });
  vd.baseLayer = 0;
  vd.mipCount = 2;
  expectDropped("E_VIEW_RANGE", [&] { EXPECT_FALSE(dev_->createTextureView(vd)); });
}

TEST_P(RhiValidationTest, E_VIEW_SWIZZLE) {
  // A swizzle is for sampling: Vulkan wants the identity on attachments and storage images.
  TextureHandle parent = texture(Format::RGBA8, 4, 4, TextureUsage_Default | TextureUsage_Storage);
  TextureViewDesc vd;
  vd.parent = parent;
  vd.swizzle.r = static_cast<Swizzle>(99);
  expectDropped("E_VIEW_SWIZZLE", [&] { EXPECT_FALSE(dev_->createTextureView(vd)); });
  vd.swizzle = {Swizzle::Blue, Swizzle::Green, Swizzle::Red, Swizzle::One};
  vd.label = "bgr1";
  TextureHandle swizzled;
  expectValid([&] { swizzled = dev_->createTextureView(vd); });
  ASSERT_TRUE(swizzled);
  ResourceBinding b;
  b.binding = 1;
  b.kind = BindingKind::SampledTexture;
  b.texture = swizzled;
  expectValid([&] { dev_->setBindings({&b, 1}); });
  b.kind = BindingKind::StorageTexture;
  expectDropped("E_VIEW_SWIZZLE", [&] { dev_->setBindings({&b, 1}); });
  expectDropped("E_VIEW_SWIZZLE", [&] { dev_->beginPass(passOn(swizzled)); });
  EXPECT_NE(lastMessage().find("'bgr1'"), std::string::npos);
  expectValid([&] { dev_->endPass(); });
  // Naming each component's own source is the identity: usable everywhere.
  vd.swizzle = {Swizzle::Red, Swizzle::Green, Swizzle::Blue, Swizzle::Alpha};
  TextureHandle same;
  expectValid([&] { same = dev_->createTextureView(vd); });
  expectValid([&] {
    dev_->beginPass(passOn(same));
    dev_->endPass();
  });
  expectValid([&] {
    dev_->destroy(same);
    dev_->destroy(swizzled);
  });
}

TEST_P(RhiValidationTest, E_SHADER_SPIRV_EMPTY) {
  ShaderDesc d;
  d.label = "nothing.frag";
  expectDropped("E_SHADER_SPIRV_EMPTY", [&] { EXPECT_FALSE(dev_->createShader(d)); });
  EXPECT_NE(lastMessage().find("'nothing.frag'"), std::string::npos);
}

TEST_P(RhiValidationTest, E_SHADER_REFLECTION) {
  ShaderDesc d;
  d.spirv = {1, 2, 3, 4, 5, 6};
  expectDropped("E_SHADER_REFLECTION", [&] { EXPECT_FALSE(dev_->createShader(d)); });
  // Binding 20 breaks the binding model (bindings below 16).
  d.stage = ShaderStage::Fragment;
  d.spirv = spirv(ShaderStage::Fragment, R"(#version 450
layout(set = 0, binding = 20) uniform U { vec4 c; } u;
layout(location = 0) out vec4 o;
void main() { o = u.c; })");
  expectDropped("E_SHADER_REFLECTION", [&] { EXPECT_FALSE(dev_->createShader(d)); });
  // Blocks of one kind may alias a binding; a uniform and a storage block may not.
  d.spirv = spirv(ShaderStage::Fragment, R"(#version 450
layout(set = 0, binding = 3) uniform U { vec4 c; } u;
layout(set = 0, binding = 3) readonly buffer S { vec4 c; } s;
layout(location = 0) out vec4 o;
void main() { o = u.c + s.c; })");
  expectDropped("E_SHADER_REFLECTION", [&] { EXPECT_FALSE(dev_->createShader(d)); });
}

TEST_P(RhiValidationTest, E_SHADER_ENTRY_POINT) {
  ShaderDesc d;
  d.stage = ShaderStage::Vertex;  // the module is a fragment shader
  d.spirv = spirv(ShaderStage::Fragment, kRedFs);
  expectDropped("E_SHADER_ENTRY_POINT", [&] { EXPECT_FALSE(dev_->createShader(d)); });
  d.stage = ShaderStage::Fragment;
  d.entryPoint = "notMain";
  expectDropped("E_SHADER_ENTRY_POINT", [&] { EXPECT_FALSE(dev_->createShader(d)); });
}

TEST_P(RhiValidationTest, E_PIPELINE_SHADER_MISSING) {
  PipelineDesc d = pipelineDesc(shader(ShaderStage::Vertex, kFullscreenVs), {});
  expectDropped("E_PIPELINE_SHADER_MISSING", [&] { EXPECT_FALSE(dev_->createPipeline(d)); });
  expectDropped("E_PIPELINE_SHADER_MISSING", [&] { EXPECT_FALSE(dev_->createComputePipeline({})); });
}

TEST_P(RhiValidationTest, E_PIPELINE_SHADER_STAGE) {
  ShaderHandle fs = shader(ShaderStage::Fragment, kRedFs);
  PipelineDesc d = pipelineDesc(fs, fs);
  expectDropped("E_PIPELINE_SHADER_STAGE", [&] { EXPECT_FALSE(dev_->createPipeline(d)); });
  ComputePipelineDesc cd;
  cd.computeShader = fs;
  expectDropped("E_PIPELINE_SHADER_STAGE", [&] { EXPECT_FALSE(dev_->createComputePipeline(cd)); });
}

TEST_P(RhiValidationTest, E_PIPELINE_SUBGROUP_SIZE) {
  ComputePipelineDesc d;
  d.computeShader = shader(ShaderStage::Compute, R"(#version 450
layout(local_size_x = 12) in;
layout(std430, binding = 0) buffer B { uint v[]; } b;
void main() { b.v[gl_LocalInvocationIndex] = 1u; })");
  // Shown subgroups of 4 to 16 invocations, the layer judges the sizes before the backend sees them.
  counter_->showSubgroupSizes(4, 16);
  for (uint32_t size : {6u, 2u, 32u}) {
    d.requiredSubgroupSize = size;
    expectDropped("E_PIPELINE_SUBGROUP_SIZE", [&] { EXPECT_FALSE(dev_->createComputePipeline(d)) << size; });
    EXPECT_NE(lastMessage().find("requiredSubgroupSize " + std::to_string(size)), std::string::npos) << lastMessage();
  }
  d.requiredSubgroupSize = 8;  // a local size x of 12 is not whole subgroups of 8
  d.fullSubgroups = true;
  expectDropped("E_PIPELINE_SUBGROUP_SIZE", [&] { EXPECT_FALSE(dev_->createComputePipeline(d)); });
  EXPECT_NE(lastMessage().find("local size x 12"), std::string::npos) << lastMessage();
  d.requiredSubgroupSize = 0;  // nor of the largest size, 16
  expectDropped("E_PIPELINE_SUBGROUP_SIZE", [&] { EXPECT_FALSE(dev_->createComputePipeline(d)); });
  counter_->showSubgroupSizes(0, 0);
  d.fullSubgroups = false;
  d.varyingSubgroupSize = true;
  expectDropped("E_PIPELINE_SUBGROUP_SIZE", [&] { EXPECT_FALSE(dev_->createComputePipeline(d)); });
  EXPECT_NE(lastMessage().find("lacks"), std::string::npos) << lastMessage();
}

TEST_P(RhiValidationTest, E_PIPELINE_BINDING_CONFLICT) {
  // Binding 0 is a uniform buffer in the vertex shader and a sampled texture in the fragment shader.
  PipelineDesc d = pipelineDesc(shader(ShaderStage::Vertex, kUniformVs), shader(ShaderStage::Fragment, R"(#version 450
layout(set = 0, binding = 0) uniform sampler2D tex;
layout(location = 0) out vec4 o;
void main() { o = texelFetch(tex, ivec2(0), 0); })"));
  expectDropped("E_PIPELINE_BINDING_CONFLICT", [&] { EXPECT_FALSE(dev_->createPipeline(d)); });
}

TEST_P(RhiValidationTest, E_PIPELINE_COLOR_TARGET_COUNT) {
  PipelineDesc d = pipelineDesc(shader(ShaderStage::Vertex, kFullscreenVs), shader(ShaderStage::Fragment, kRedFs));
  d.colorTargetCount = 5;
  expectDropped("E_PIPELINE_COLOR_TARGET_COUNT", [&] { EXPECT_FALSE(dev_->createPipeline(d)); });
  d.colorTargetCount = 0;
  expectDropped("E_PIPELINE_COLOR_TARGET_COUNT", [&] { EXPECT_FALSE(dev_->createPipeline(d)); });
}

TEST_P(RhiValidationTest, E_PIPELINE_FORMAT) {
  PipelineDesc d = pipelineDesc(shader(ShaderStage::Vertex, kFullscreenVs), shader(ShaderStage::Fragment, kRedFs));
  d.colorTargets[0].format = Format::D32F;
  expectDropped("E_PIPELINE_FORMAT", [&] { EXPECT_FALSE(dev_->createPipeline(d)); });
  d.colorTargets[0].format = Format::RGBA8;
  d.depthStencilFormat = Format::R32F;
  expectDropped("E_PIPELINE_FORMAT", [&] { EXPECT_FALSE(dev_->createPipeline(d)); });
}

TEST_P(RhiValidationTest, E_PIPELINE_BLEND) {
  PipelineDesc d =
      pipelineDesc(shader(ShaderStage::Vertex, kFullscreenVs), shader(ShaderStage::Fragment, R"(#version 450
layout(location = 0) out uvec4 o;
void main() { o = uvec4(1); })"),
                   Format::RGBA8_UINT);
  d.colorTargets[0].blend.enabled = true;
  expectDropped("E_PIPELINE_BLEND", [&] { EXPECT_FALSE(dev_->createPipeline(d)); });
}

TEST_P(RhiValidationTest, E_PIPELINE_ATTRIBUTE) {
  PipelineDesc d = pipelineDesc(shader(ShaderStage::Vertex, kAttributeVs), shader(ShaderStage::Fragment, kRedFs));
  // The shader reads location 0; no attribute supplies it.
  expectDropped("E_PIPELINE_ATTRIBUTE", [&] { EXPECT_FALSE(dev_->createPipeline(d)); });
  d.attributeCount = 1;
  d.attributes[0].format = VertexFormat::Float2;
  d.vertexBuffers[0].stride = 8;
  d.attributeCount = 2;
  d.attributes[1] = d.attributes[0];  // location 0 twice
  expectDropped("E_PIPELINE_ATTRIBUTE", [&] { EXPECT_FALSE(dev_->createPipeline(d)); });
  // A dvec4 takes locations 0 and 1: an attribute at location 1 overlaps it.
  d.vertexBuffers[0].stride = 40;
  d.attributes[0].format = VertexFormat::Double4;
  d.attributes[1] = {1, VertexFormat::Float, 32, 0};
  expectDropped("E_PIPELINE_ATTRIBUTE", [&] { EXPECT_FALSE(dev_->createPipeline(d)); });
}

TEST_P(RhiValidationTest, E_PIPELINE_SAMPLES) {
  PipelineDesc d = pipelineDesc(shader(ShaderStage::Vertex, kFullscreenVs), shader(ShaderStage::Fragment, kRedFs));
  d.samples = 2;
  expectDropped("E_PIPELINE_SAMPLES", [&] { EXPECT_FALSE(dev_->createPipeline(d)); });
}

TEST_P(RhiValidationTest, E_PIPELINE_DEPTH_STATE) {
  PipelineDesc d = pipelineDesc(shader(ShaderStage::Vertex, kFullscreenVs), shader(ShaderStage::Fragment, kRedFs));
  d.depthStencil.depthWrite = true;
  expectDropped("E_PIPELINE_DEPTH_STATE", [&] { EXPECT_FALSE(dev_->createPipeline(d)); });
  d.depthStencil.depthWrite = false;
  d.depthStencil.stencilEnabled = true;
  d.depthStencilFormat = Format::D32F;
  expectDropped("E_PIPELINE_DEPTH_STATE", [&] { EXPECT_FALSE(dev_->createPipeline(d)); });
}

TEST_P(RhiValidationTest, E_PIPELINE_RASTER_STATE) {
  PipelineDesc d = pipelineDesc(shader(ShaderStage::Vertex, kFullscreenVs), shader(ShaderStage::Fragment, kRedFs));
  d.raster.polygonMode = static_cast<PolygonMode>(3);
  expectDropped("E_PIPELINE_RASTER_STATE", [&] { EXPECT_FALSE(dev_->createPipeline(d)); });
  d.raster.polygonMode = PolygonMode::Fill;
  d.topology = static_cast<PrimitiveTopology>(10);
  expectDropped("E_PIPELINE_RASTER_STATE", [&] { EXPECT_FALSE(dev_->createPipeline(d)); });
  d.topology = PrimitiveTopology::Triangles;
  d.raster.depthBias.slopeFactor = std::numeric_limits<float>::infinity();
  expectDropped("E_PIPELINE_RASTER_STATE", [&] { EXPECT_FALSE(dev_->createPipeline(d)); });
  d.raster.depthBias.slopeFactor = 1;
  d.raster.depthBias.clamp = std::numeric_limits<float>::quiet_NaN();
  expectDropped("E_PIPELINE_RASTER_STATE", [&] { EXPECT_FALSE(dev_->createPipeline(d)); });
  d.raster.depthBias.clamp = 0.5f;
  expectValid([&] { EXPECT_TRUE(dev_->createPipeline(d)); });
}

TEST_P(RhiValidationTest, E_PIPELINE_DEVICE_FEATURE) {
  const ShaderHandle vs = shader(ShaderStage::Vertex, kFullscreenVs), fs = shader(ShaderStage::Fragment, kRedFs);
  const ShaderHandle gs = shader(ShaderStage::Geometry, R"(#version 450
layout(lines_adjacency) in;
layout(points, max_vertices = 1) out;
void main() { gl_Position = gl_in[1].gl_Position; gl_PointSize = 1.0; EmitVertex(); })");
  PipelineDesc line = pipelineDesc(vs, fs), clamp = line, biasClamp = line, adjacency = line;
  line.raster.polygonMode = PolygonMode::Line;
  clamp.raster.depthClampEnabled = true;
  biasClamp.raster.depthBias = {1, 0, 0.5f};
  adjacency.geometryShader = gs;
  adjacency.topology = PrimitiveTopology::LinesWithAdjacency;
  // With every feature offered, each is valid; without its feature, each is dropped.
  const std::pair<const PipelineDesc*, const char*> cases[] = {
      {&line, "fillModeNonSolid"}, {&clamp, "depthClamp"}, {&biasClamp, "depthBiasClamp"}, {&adjacency, "geometryShader"}};
  for (const auto& c : cases) {
    const PipelineDesc& desc = *c.first;
    expectValid([&] { EXPECT_TRUE(dev_->createPipeline(desc)) << c.second; });
  }
  for (const auto& c : cases) {
    const PipelineDesc& desc = *c.first;
    counter_->withholdFeature(c.second);
    expectDropped("E_PIPELINE_DEVICE_FEATURE", [&] { EXPECT_FALSE(dev_->createPipeline(desc)) << c.second; });
    EXPECT_NE(lastMessage().find(c.second), std::string::npos) << lastMessage();
  }
  // A 64-bit attribute on a device without 64-bit vertex formats (lavapipe 22.3 has none).
  PipelineDesc doubles = pipelineDesc(shader(ShaderStage::Vertex, R"(#version 450
layout(location = 0) in dvec2 pos;
void main() { gl_Position = vec4(vec2(pos), 0.5, 1.0); })"), fs);
  doubles.attributeCount = 1;
  doubles.attributes[0] = {0, VertexFormat::Double2, 0, 0};
  doubles.vertexBuffers[0].stride = 16;
  counter_->withholdDoubleVertexFormats();
  expectDropped("E_PIPELINE_DEVICE_FEATURE", [&] { EXPECT_FALSE(dev_->createPipeline(doubles)); });
  EXPECT_NE(lastMessage().find("64-bit vertex formats"), std::string::npos) << lastMessage();
}

TEST_P(RhiValidationTest, E_PASS_NESTED) {
  TextureHandle a = texture(Format::RGBA8), b = texture(Format::RGBA8);
  begin(a);
  expectDropped("E_PASS_NESTED", [&] { dev_->beginPass(passOn(b)); });
  end();
}

TEST_P(RhiValidationTest, E_PASS_NOT_BEGUN) {
  PipelineHandle p = simplePipeline();
  expectDropped("E_PASS_NOT_BEGUN", [&] { dev_->draw(3); });
  expectDropped("E_PASS_NOT_BEGUN", [&] { dev_->setPipeline(p); });
  expectDropped("E_PASS_NOT_BEGUN", [&] { dev_->setViewport({}); });
  expectDropped("E_PASS_NOT_BEGUN", [&] { dev_->endPass(); });
}

TEST_P(RhiValidationTest, E_PASS_NO_ATTACHMENTS) {
  expectDropped("E_PASS_NO_ATTACHMENTS", [&] { dev_->beginPass(PassDesc{}); });
  expectValid([&] { dev_->endPass(); });  // closes the dropped pass silently
}

TEST_P(RhiValidationTest, E_PASS_ATTACHMENT_FORMAT) {
  TextureHandle depth = texture(Format::D32F);
  expectDropped("E_PASS_ATTACHMENT_FORMAT", [&] { dev_->beginPass(passOn(depth)); });
  expectValid([&] { dev_->endPass(); });
  TextureHandle color = texture(Format::RGBA8), color2 = texture(Format::RGBA8);
  expectDropped("E_PASS_ATTACHMENT_FORMAT", [&] { dev_->beginPass(passOn(color, color2)); });
  expectValid([&] { dev_->endPass(); });
}

TEST_P(RhiValidationTest, E_PASS_ATTACHMENT_USAGE) {
  TextureHandle t = texture(Format::RGBA8, 4, 4, TextureUsage_Sampled, 1, "sample only");
  expectDropped("E_PASS_ATTACHMENT_USAGE", [&] { dev_->beginPass(passOn(t)); });
  EXPECT_NE(lastMessage().find("'sample only'"), std::string::npos);
  expectValid([&] { dev_->endPass(); });
}

TEST_P(RhiValidationTest, E_PASS_ATTACHMENT_RANGE) {
  TextureHandle t = texture(Format::RGBA8);
  PassDesc p = passOn(t);
  p.colors[0].layer = 1;
  expectDropped("E_PASS_ATTACHMENT_RANGE", [&] { dev_->beginPass(p); });
  expectValid([&] { dev_->endPass(); });
  p.colors[0].layer = 0;
  p.colors[0].mip = 1;
  expectDropped("E_PASS_ATTACHMENT_RANGE", [&] { dev_->beginPass(p); });
  expectValid([&] { dev_->endPass(); });
}

TEST_P(RhiValidationTest, E_PASS_ATTACHMENT_SIZE_MISMATCH) {
  TextureHandle c = texture(Format::RGBA8, 4, 4), d = texture(Format::D32F, 8, 8);
  expectDropped("E_PASS_ATTACHMENT_SIZE_MISMATCH", [&] { dev_->beginPass(passOn(c, d)); });
  expectValid([&] { dev_->endPass(); });
}

TEST_P(RhiValidationTest, E_PASS_ATTACHMENT_SAMPLES) {
  TextureHandle c = texture(Format::RGBA8, 4, 4, TextureUsage_Default, 4), d = texture(Format::D32F, 4, 4);
  expectDropped("E_PASS_ATTACHMENT_SAMPLES", [&] { dev_->beginPass(passOn(c, d)); });
  expectValid([&] { dev_->endPass(); });
}

TEST_P(RhiValidationTest, E_PASS_ATTACHMENT_DUPLICATE) {
  TextureHandle c = texture(Format::RGBA8);
  PassDesc p = passOn(c);
  p.colors[1].texture = c;
  expectDropped("E_PASS_ATTACHMENT_DUPLICATE", [&] { dev_->beginPass(p); });
  expectValid([&] { dev_->endPass(); });
}

TEST_P(RhiValidationTest, E_PASS_RESOLVE) {
  TextureHandle single = texture(Format::RGBA8), other = texture(Format::RGBA8);
  PassDesc p = passOn(single);
  p.colors[0].resolveTarget = other;  // the attachment is not multisampled
  expectDropped("E_PASS_RESOLVE", [&] { dev_->beginPass(p); });
  expectValid([&] { dev_->endPass(); });
  TextureHandle msaa = texture(Format::RGBA8, 4, 4, TextureUsage_Default, 4);
  TextureHandle wrongSize = texture(Format::RGBA8, 8, 8);
  p = passOn(msaa);
  p.colors[0].resolveTarget = wrongSize;
  expectDropped("E_PASS_RESOLVE", [&] { dev_->beginPass(p); });
  expectValid([&] { dev_->endPass(); });
}

TEST_P(RhiValidationTest, E_VIEWPORT_INVALID) {
  TextureHandle t = texture(Format::RGBA8);
  PipelineHandle p = simplePipeline();
  begin(t);
  expectValid([&] { dev_->setPipeline(p); });
  Viewport vp;
  vp.maxDepth = 2.0f;
  expectDropped("E_VIEWPORT_INVALID", [&] { dev_->setViewport(vp); });
  vp.maxDepth = 1.0f;
  vp.width = -4.0f;
  expectDropped("E_VIEWPORT_INVALID", [&] { dev_->setViewport(vp); });
  end();
}

TEST_P(RhiValidationTest, E_SCISSOR_INVALID) {
  TextureHandle t = texture(Format::RGBA8);
  begin(t);
  expectDropped("E_SCISSOR_INVALID", [&] { dev_->setScissor({-1, 0, 2, 2}); });
  end();
}

TEST_P(RhiValidationTest, E_DRAW_NO_PIPELINE) {
  TextureHandle t = texture(Format::RGBA8);
  PipelineHandle p = simplePipeline();
  begin(t);
  expectValid([&] { dev_->setPipeline(p); });
  end();
  // Every pass starts without a pipeline.
  begin(t);
  expectDropped("E_DRAW_NO_PIPELINE", [&] { dev_->draw(3); });
  end();
  std::vector<uint8_t> px = dev_->readTexture(t);
  ASSERT_EQ(px.size(), 64u);
  EXPECT_EQ(px[0], 0) << "the dropped draw wrote pixels";
}

TEST_P(RhiValidationTest, E_DRAW_PIPELINE_MISMATCH) {
  TextureHandle t = texture(Format::RGBA16F);
  PipelineHandle p = simplePipeline(kRedFs, Format::RGBA8);
  begin(t);
  expectValid([&] { dev_->setPipeline(p); });
  expectDropped("E_DRAW_PIPELINE_MISMATCH", [&] { dev_->draw(3); });
  end();
  TextureHandle c = texture(Format::RGBA8), d = texture(Format::D32F);
  begin(c, d);  // the pipeline has no depth-stencil format
  expectValid([&] { dev_->setPipeline(p); });
  expectDropped("E_DRAW_PIPELINE_MISMATCH", [&] { dev_->draw(3); });
  end();
}

TEST_P(RhiValidationTest, E_VERTEX_BUFFER_SLOT) {
  BufferHandle b = buffer(64);
  expectDropped("E_VERTEX_BUFFER_SLOT", [&] { dev_->setVertexBuffer(kMaxVertexBuffers, b); });
}

PipelineDesc attributePipeline(PipelineDesc d) {
  d.attributeCount = 1;
  d.attributes[0].format = VertexFormat::Float2;
  d.vertexBuffers[0].stride = 8;
  return d;
}

TEST_P(RhiValidationTest, E_VERTEX_BUFFER_MISSING) {
  TextureHandle t = texture(Format::RGBA8);
  PipelineHandle p = pipeline(attributePipeline(
      pipelineDesc(shader(ShaderStage::Vertex, kAttributeVs), shader(ShaderStage::Fragment, kRedFs))));
  begin(t);
  expectValid([&] { dev_->setPipeline(p); });
  expectDropped("E_VERTEX_BUFFER_MISSING", [&] { dev_->draw(3); });
  end();
}

TEST_P(RhiValidationTest, E_INDEX_BUFFER_MISSING) {
  TextureHandle t = texture(Format::RGBA8);
  PipelineHandle p = simplePipeline();
  begin(t);
  expectValid([&] { dev_->setPipeline(p); });
  expectDropped("E_INDEX_BUFFER_MISSING", [&] { dev_->drawIndexed(3); });
  end();
}

TEST_P(RhiValidationTest, E_DRAW_VERTEX_RANGE) {
  TextureHandle t = texture(Format::RGBA8);
  PipelineHandle p = pipeline(attributePipeline(
      pipelineDesc(shader(ShaderStage::Vertex, kAttributeVs), shader(ShaderStage::Fragment, kRedFs))));
  BufferHandle vb = buffer(3 * 8, BufferUsage_Vertex, "three vertices");
  begin(t);
  expectValid([&] {
    dev_->setPipeline(p);
    dev_->setVertexBuffer(0, vb);
    dev_->draw(3);
  });
  expectDropped("E_DRAW_VERTEX_RANGE", [&] { dev_->draw(3, 1, 1); });
  end();
}

TEST_P(RhiValidationTest, E_DRAW_INDEX_RANGE) {
  TextureHandle t = texture(Format::RGBA8);
  PipelineHandle p = simplePipeline();
  uint16_t idx[4] = {0, 1, 2, 0};
  BufferDesc bd;
  bd.size = sizeof(idx);
  bd.usage = BufferUsage_Index;
  bd.initialData = idx;
  BufferHandle ib;
  expectValid([&] { ib = dev_->createBuffer(bd); });
  begin(t);
  expectValid([&] {
    dev_->setPipeline(p);
    dev_->setIndexBuffer(ib, IndexType::UInt16);
    dev_->drawIndexed(3, 1, 1);
  });
  expectDropped("E_DRAW_INDEX_RANGE", [&] { dev_->drawIndexed(3, 1, 2); });
  end();
}

TEST_P(RhiValidationTest, E_BINDING_INDEX) {
  BufferHandle b = buffer(256, BufferUsage_Uniform);
  ResourceBinding r[2];
  r[0].binding = kMaxBindings;
  r[0].buffer = b;
  expectDropped("E_BINDING_INDEX", [&] { dev_->setBindings({r, 1}); });
  r[0].binding = 3;
  r[1] = r[0];
  expectDropped("E_BINDING_INDEX", [&] { dev_->setBindings({r, 2}); });
}

TEST_P(RhiValidationTest, E_BINDING_MISSING) {
  TextureHandle t = texture(Format::RGBA8);
  PipelineHandle p = simplePipeline(kSamplerFs);
  begin(t);
  expectValid([&] { dev_->setPipeline(p); });
  expectDropped("E_BINDING_MISSING", [&] { dev_->draw(3); });
  end();
  ComputePipelineHandle cp = computePipeline();
  expectValid([&] { dev_->setComputePipeline(cp); });
  expectDropped("E_BINDING_MISSING", [&] { dev_->dispatch(1); });
}

TEST_P(RhiValidationTest, E_BINDING_KIND) {
  TextureHandle t = texture(Format::RGBA8);
  PipelineHandle p = simplePipeline(kUniformFs);
  BufferHandle b = buffer(256);
  ResourceBinding r;
  r.kind = BindingKind::StorageBuffer;  // the shader declares a uniform buffer
  r.buffer = b;
  expectValid([&] { dev_->setBindings({&r, 1}); });
  begin(t);
  expectValid([&] { dev_->setPipeline(p); });
  expectDropped("E_BINDING_KIND", [&] { dev_->draw(3); });
  end();
}

TEST_P(RhiValidationTest, E_BINDING_RANGE) {
  BufferHandle b = buffer(512, BufferUsage_Uniform);
  ResourceBinding r;
  r.buffer = b;
  r.offset = 256;
  r.size = 512;
  expectDropped("E_BINDING_RANGE", [&] { dev_->setBindings({&r, 1}); });
  r.offset = 16;  // not a multiple of 256
  r.size = 16;
  expectDropped("E_BINDING_RANGE", [&] { dev_->setBindings({&r, 1}); });
  BufferHandle big = buffer(70000, BufferUsage_Uniform, "big");
  r.buffer = big;
  r.offset = 0;
  r.size = 0;  // to the end: 70000 bytes, above the uniform range limit
  expectDropped("E_BINDING_RANGE", [&] { dev_->setBindings({&r, 1}); });
  ResourceBinding s;
  s.kind = BindingKind::StorageTexture;
  s.texture = texture(Format::RGBA8, 4, 4, TextureUsage_Storage);
  s.mip = 1;
  expectDropped("E_BINDING_RANGE", [&] { dev_->setBindings({&s, 1}); });
}

TEST_P(RhiValidationTest, E_BINDING_TEXTURE_MISMATCH) {
  TextureHandle t = texture(Format::RGBA8);
  PipelineHandle p = simplePipeline(kUintSamplerFs);
  ResourceBinding r;
  r.binding = 1;
  r.kind = BindingKind::SampledTexture;
  r.texture =
      texture(Format::RGBA8, 1, 1, TextureUsage_Sampled, 1, "unorm texture");  // usampler2D needs an integer format
  expectValid([&] { dev_->setBindings({&r, 1}); });
  begin(t);
  expectValid([&] { dev_->setPipeline(p); });
  expectDropped("E_BINDING_TEXTURE_MISMATCH", [&] { dev_->draw(3); });
  EXPECT_NE(lastMessage().find("'unorm texture'"), std::string::npos);
  end();
  // A shadow sampler needs a depth texture, and an explicit sampler must have compareEnabled
  // (the null default compares with LessEqual).
  PipelineHandle shadow = simplePipeline(R"(#version 450
layout(set = 0, binding = 1) uniform sampler2DShadow tex;
layout(location = 0) out vec4 o;
void main() { o = vec4(texture(tex, vec3(0.5, 0.5, 0.5))); })");
  r.texture = texture(Format::D32F, 4, 4, TextureUsage_Sampled, 1, "depth");
  expectValid([&] { dev_->setBindings({&r, 1}); });
  begin(t);
  expectValid([&] {
    dev_->setPipeline(shadow);
    dev_->draw(3);
  });
  SamplerHandle plain;
  expectValid([&] { plain = dev_->createSampler({}); });
  r.sampler = plain;
  expectValid([&] { dev_->setBindings({&r, 1}); });
  expectDropped("E_BINDING_TEXTURE_MISMATCH", [&] { dev_->draw(3); });
  r.sampler = {};
  r.texture = texture(Format::RGBA8, 4, 4, TextureUsage_Sampled, 1, "colour");
  expectValid([&] { dev_->setBindings({&r, 1}); });
  expectDropped("E_BINDING_TEXTURE_MISMATCH", [&] { dev_->draw(3); });
  end();
  // A sampler3D needs a Tex3D texture, a sampler2D anything but Tex1D and Tex3D.
  PipelineHandle volume = simplePipeline(R"(#version 450
layout(set = 0, binding = 1) uniform sampler3D tex;
layout(location = 0) out vec4 o;
void main() { o = texelFetch(tex, ivec3(0), 0); })");
  TextureDesc d3;
  d3.type = TextureType::Tex3D;
  d3.width = d3.height = 2;
  d3.depth = 2;
  d3.usage = TextureUsage_Sampled;
  d3.label = "volume";
  TextureHandle vol;
  expectValid([&] { vol = dev_->createTexture(d3); });
  r.texture = texture(Format::RGBA8, 4, 4, TextureUsage_Sampled, 1, "flat");
  expectValid([&] { dev_->setBindings({&r, 1}); });
  begin(t);
  expectValid([&] { dev_->setPipeline(volume); });
  expectDropped("E_BINDING_TEXTURE_MISMATCH", [&] { dev_->draw(3); });
  EXPECT_NE(lastMessage().find("3D"), std::string::npos) << lastMessage();
  r.texture = vol;
  expectValid([&] {
    dev_->setBindings({&r, 1});
    dev_->draw(3);
  });
  PipelineHandle flat = simplePipeline(kSamplerFs);
  expectValid([&] { dev_->setPipeline(flat); });
  expectDropped("E_BINDING_TEXTURE_MISMATCH", [&] { dev_->draw(3); });
  end();
}

TEST_P(RhiValidationTest, E_PIPELINE_SEPARATE_PAIRS) {
  // Each stage combines 9 separate texture/sampler pairs (textures at bindings 0 and 1, samplers
  // at 2..10): each shader is valid, the pipeline's 18 pairs are more than 16.
  auto pairsShader = [](const char* stageMain, uint32_t texture) {
    std::string glsl = "#version 450\nlayout(set = 0, binding = " + std::to_string(texture) + ") uniform texture2D t;\n";
    std::string sum = "vec4(0.0)";
    for (uint32_t s = 2; s <= 10; ++s) {
      glsl += "layout(set = 0, binding = " + std::to_string(s) + ") uniform sampler s" + std::to_string(s) + ";\n";
      sum += " + textureLod(sampler2D(t, s" + std::to_string(s) + "), vec2(0.5), 0.0)";
    }
    return glsl + stageMain + sum + "; }\n";
  };
  std::string vs = pairsShader("layout(location = 0) out vec4 v;\nvoid main() { gl_Position = vec4(0.0, 0.0, 0.5, 1.0); v = ", 0);
  std::string fs = pairsShader("layout(location = 0) in vec4 v;\nlayout(location = 0) out vec4 o;\nvoid main() { o = v + ", 1);
  PipelineDesc d = pipelineDesc(shader(ShaderStage::Vertex, vs.c_str()), shader(ShaderStage::Fragment, fs.c_str()));
  expectDropped("E_PIPELINE_SEPARATE_PAIRS", [&] { EXPECT_FALSE(dev_->createPipeline(d)); });
  // 9 pairs in one pipeline are fine.
  d.fragmentShader = shader(ShaderStage::Fragment, R"(#version 450
layout(location = 0) in vec4 v;
layout(location = 0) out vec4 o;
void main() { o = v; })");
  pipeline(d);
}

TEST_P(RhiValidationTest, E_BINDING_BORDER_COLOR) {
  TextureHandle t = texture(Format::RGBA8);
  SamplerDesc sd;
  sd.addressV = AddressMode::ClampToBorder;
  sd.borderColor = BorderColor::IntOpaqueWhite;  // an Int colour on a unorm texture
  SamplerHandle intWhite, floatWhite;
  expectValid([&] { intWhite = dev_->createSampler(sd); });
  sd.borderColor = BorderColor::FloatOpaqueWhite;
  expectValid([&] { floatWhite = dev_->createSampler(sd); });
  PipelineHandle p = simplePipeline(kSamplerFs);
  ResourceBinding r;
  r.binding = 1;
  r.kind = BindingKind::SampledTexture;
  r.texture = texture(Format::RGBA8, 4, 4, TextureUsage_Sampled, 1, "unorm texture");
  r.sampler = intWhite;
  expectValid([&] { dev_->setBindings({&r, 1}); });
  begin(t);
  expectValid([&] { dev_->setPipeline(p); });
  expectDropped("E_BINDING_BORDER_COLOR", [&] { dev_->draw(3); });
  EXPECT_NE(lastMessage().find("'unorm texture'"), std::string::npos);
  r.sampler = floatWhite;
  expectValid([&] {
    dev_->setBindings({&r, 1});
    dev_->draw(3);
  });
  end();
  // The same check for a separate texture/sampler pair: a Float colour on an integer texture.
  PipelineHandle separate = simplePipeline(R"(#version 450
layout(set = 0, binding = 1) uniform utexture2D tex;
layout(set = 0, binding = 2) uniform sampler smp;
layout(location = 0) out vec4 o;
void main() { o = vec4(texture(usampler2D(tex, smp), vec2(1.5, 0.5))); })");
  std::array<ResourceBinding, 2> pair{};
  pair[0].binding = 1, pair[0].kind = BindingKind::SeparateTexture;
  pair[0].texture = texture(Format::RGBA8_UINT, 4, 4, TextureUsage_Sampled, 1, "uint texture");
  pair[1].binding = 2, pair[1].kind = BindingKind::SeparateSampler, pair[1].sampler = floatWhite;
  expectValid([&] { dev_->setBindings(pair); });
  begin(t);
  expectValid([&] { dev_->setPipeline(separate); });
  expectDropped("E_BINDING_BORDER_COLOR", [&] { dev_->draw(3); });
  EXPECT_NE(lastMessage().find("'uint texture'"), std::string::npos);
  pair[1].sampler = intWhite;
  expectValid([&] {
    dev_->setBindings(pair);
    dev_->draw(3);
  });
  end();
}

// A sampler's level-of-detail clamp must hold (minLod <= maxLod, finite) and its bias stay within
// the device's maxSamplerLodBias; OpenGL's defaults, a clamp to one level and the largest bias
// are fine.
TEST_P(RhiValidationTest, E_SAMPLER_LOD) {
  SamplerDesc sd;
  expectValid([&] { dev_->destroy(dev_->createSampler(sd)); });
  sd.minLod = sd.maxLod = 1.0f;
  sd.mipLodBias = -dev_->info().caps.maxSamplerLodBias;
  expectValid([&] { dev_->destroy(dev_->createSampler(sd)); });
  sd.minLod = 2.0f;
  expectDropped("E_SAMPLER_LOD", [&] { EXPECT_FALSE(dev_->createSampler(sd)); });
  EXPECT_NE(lastMessage().find("minLod 2.000000 above maxLod 1.000000"), std::string::npos) << lastMessage();
  sd = SamplerDesc{};
  sd.mipLodBias = dev_->info().caps.maxSamplerLodBias + 1.0f;
  expectDropped("E_SAMPLER_LOD", [&] { EXPECT_FALSE(dev_->createSampler(sd)); });
  sd = SamplerDesc{};
  sd.maxLod = std::numeric_limits<float>::quiet_NaN();
  expectDropped("E_SAMPLER_LOD", [&] { EXPECT_FALSE(dev_->createSampler(sd)); });
}

// A Linear sampler on an integer texture (a platform's depth read through R32_UINT, say): Vulkan
// forbids it and GL reads 0; on a depth texture read without comparison: an optional format
// feature (lavapipe filters no D32F). A Nearest one is fine, and so is Linear on a unorm texture
// or with comparison (PCF).
TEST_P(RhiValidationTest, E_BINDING_FILTER_FORMAT) {
  TextureHandle t = texture(Format::RGBA8);
  SamplerDesc sd;
  SamplerHandle nearest, linear;
  expectValid([&] { nearest = dev_->createSampler(sd); });
  sd.minFilter = sd.magFilter = Filter::Linear;
  expectValid([&] { linear = dev_->createSampler(sd); });
  PipelineHandle p = simplePipeline(R"(#version 450
layout(set = 0, binding = 1) uniform usampler2D depthBits;
layout(location = 0) out vec4 o;
void main() { o = vec4(texelFetch(depthBits, ivec2(0), 0)); })");
  ResourceBinding r;
  r.binding = 1;
  r.kind = BindingKind::SampledTexture;
  r.texture = texture(Format::R32_UINT, 4, 4, TextureUsage_Sampled, 1, "depth bits");
  r.sampler = linear;
  expectValid([&] { dev_->setBindings({&r, 1}); });
  begin(t);
  expectValid([&] { dev_->setPipeline(p); });
  expectDropped("E_BINDING_FILTER_FORMAT", [&] { dev_->draw(3); });
  EXPECT_NE(lastMessage().find("'depth bits'"), std::string::npos) << lastMessage();
  r.sampler = nearest;
  expectValid([&] {
    dev_->setBindings({&r, 1});
    dev_->draw(3);
  });
  end();
  // The pair a shader combines: a separate integer texture with a Linear separate sampler.
  PipelineHandle separate = simplePipeline(R"(#version 450
layout(set = 0, binding = 1) uniform utexture2D tex;
layout(set = 0, binding = 2) uniform sampler smp;
layout(location = 0) out vec4 o;
void main() { o = vec4(texture(usampler2D(tex, smp), vec2(0.5))); })");
  std::array<ResourceBinding, 2> pair{};
  pair[0].binding = 1, pair[0].kind = BindingKind::SeparateTexture;
  pair[0].texture = texture(Format::RGBA8_UINT, 4, 4, TextureUsage_Sampled, 1, "uint texture");
  pair[1].binding = 2, pair[1].kind = BindingKind::SeparateSampler, pair[1].sampler = linear;
  expectValid([&] { dev_->setBindings(pair); });
  begin(t);
  expectValid([&] { dev_->setPipeline(separate); });
  expectDropped("E_BINDING_FILTER_FORMAT", [&] { dev_->draw(3); });
  pair[1].sampler = nearest;
  expectValid([&] {
    dev_->setBindings(pair);
    dev_->draw(3);
  });
  end();
  // Linear on a unorm texture is what it is for.
  PipelineHandle unorm = simplePipeline(kSamplerFs);
  r.texture = texture(Format::RGBA8, 4, 4, TextureUsage_Sampled, 1, "unorm texture");
  r.sampler = linear;
  begin(t);
  expectValid([&] {
    dev_->setPipeline(unorm);
    dev_->setBindings({&r, 1});
    dev_->draw(3);
  });
  // A depth texture read as a value through a Linear sampler; with comparison it is PCF.
  r.texture = texture(Format::D32F, 4, 4, TextureUsage_Sampled, 1, "depth");
  expectValid([&] { dev_->setBindings({&r, 1}); });
  expectDropped("E_BINDING_FILTER_FORMAT", [&] { dev_->draw(3); });
  EXPECT_NE(lastMessage().find("as depth"), std::string::npos) << lastMessage();
  end();
  PipelineHandle shadow = simplePipeline(R"(#version 450
layout(set = 0, binding = 1) uniform sampler2DShadow depth;
layout(location = 0) out vec4 o;
void main() { o = vec4(texture(depth, vec3(0.5, 0.5, 0.5))); })");
  sd.compareEnabled = true;
  SamplerHandle pcf;
  expectValid([&] { pcf = dev_->createSampler(sd); });
  r.sampler = pcf;
  begin(t);
  expectValid([&] {
    dev_->setPipeline(shadow);
    dev_->setBindings({&r, 1});
    dev_->draw(3);
  });
  end();
}

TEST_P(RhiValidationTest, E_BINDING_TEXEL_FORMAT) {
  BufferHandle b = buffer(512);
  ResourceBinding r;
  r.kind = BindingKind::UniformTexelBuffer;
  r.buffer = b;
  r.texelFormat = Format::D24S8;  // not a texel buffer format
  expectDropped("E_BINDING_TEXEL_FORMAT", [&] { dev_->setBindings({&r, 1}); });
  r.texelFormat = Format::RGBA32F;
  r.size = 40;  // two and a half texels
  expectDropped("E_BINDING_TEXEL_FORMAT", [&] { dev_->setBindings({&r, 1}); });
  r.size = 48;
  expectValid([&] { dev_->setBindings({&r, 1}); });
}

TEST_P(RhiValidationTest, E_BINDING_FEEDBACK) {
  TextureHandle t = texture(Format::RGBA8, 4, 4);
  PipelineHandle p = simplePipeline(kSamplerFs);
  ResourceBinding r;
  r.binding = 1;
  r.kind = BindingKind::SampledTexture;
  r.texture = t;
  expectValid([&] { dev_->setBindings({&r, 1}); });
  begin(t);
  expectValid([&] { dev_->setPipeline(p); });
  expectDropped("E_BINDING_FEEDBACK", [&] { dev_->draw(3); });
  end();
}

TEST_P(RhiValidationTest, E_PUSH_CONSTANT_SIZE) {
  uint8_t data[kMaxPushConstantBytes + 4] = {};
  expectDropped("E_PUSH_CONSTANT_SIZE", [&] { dev_->pushConstants(data, kMaxPushConstantBytes + 4); });
  expectDropped("E_PUSH_CONSTANT_SIZE", [&] { dev_->pushConstants(data, 6); });
  expectDropped("E_PUSH_CONSTANT_SIZE", [&] { dev_->pushConstants(nullptr, 16); });
}

TEST_P(RhiValidationTest, E_PUSH_CONSTANT_MISSING) {
  TextureHandle t = texture(Format::RGBA8);
  PipelineHandle p = simplePipeline(kPushFs);
  float half[2] = {1, 1};
  begin(t);
  expectValid([&] {
    dev_->setPipeline(p);
    dev_->pushConstants(half, sizeof(half));  // 8 of the 16 bytes the shader declares
  });
  expectDropped("E_PUSH_CONSTANT_MISSING", [&] { dev_->draw(3); });
  end();
}

TEST_P(RhiValidationTest, E_DISPATCH_IN_PASS) {
  TextureHandle t = texture(Format::RGBA8);
  ComputePipelineHandle cp = computePipeline();
  expectValid([&] { dev_->setComputePipeline(cp); });
  begin(t);
  expectDropped("E_DISPATCH_IN_PASS", [&] { dev_->dispatch(1); });
  expectDropped("E_DISPATCH_IN_PASS", [&] { dev_->setComputePipeline(cp); });
  end();
}

TEST_P(RhiValidationTest, E_DISPATCH_NO_PIPELINE) {
  expectDropped("E_DISPATCH_NO_PIPELINE", [&] { dev_->dispatch(1); });
}

TEST_P(RhiValidationTest, E_DISPATCH_SIZE) {
  ComputePipelineHandle cp = computePipeline();
  expectValid([&] { dev_->setComputePipeline(cp); });
  expectDropped("E_DISPATCH_SIZE", [&] { dev_->dispatch(70000); });
}

TEST_P(RhiValidationTest, E_TRANSFER_IN_PASS) {
  TextureHandle t = texture(Format::RGBA8), other = texture(Format::RGBA8);
  BufferHandle b = buffer(16);
  uint32_t v = 1;
  begin(t);
  expectDropped("E_TRANSFER_IN_PASS", [&] { dev_->writeBuffer(b, 0, &v, 4); });
  expectDropped("E_TRANSFER_IN_PASS", [&] { EXPECT_TRUE(dev_->readBuffer(b, 0, 4).empty()); });
  expectDropped("E_TRANSFER_IN_PASS", [&] { EXPECT_TRUE(dev_->readTexture(other).empty()); });
  expectDropped("E_TRANSFER_IN_PASS", [&] { dev_->copyTexture(other, t); });
  end();
}

TEST_P(RhiValidationTest, E_TRANSFER_EMPTY) {
  BufferHandle b = buffer(16);
  uint32_t v = 1;
  expectDropped("E_TRANSFER_EMPTY", [&] { dev_->writeBuffer(b, 0, &v, 0); });
  expectDropped("E_TRANSFER_EMPTY", [&] { dev_->writeBuffer(b, 0, nullptr, 4); });
  TextureHandle t = texture(Format::RGBA8);
  expectDropped("E_TRANSFER_EMPTY", [&] { dev_->writeTexture(t, 0, 0, nullptr); });
}

TEST_P(RhiValidationTest, E_WRITE_OUT_OF_RANGE) {
  uint32_t init[4] = {1, 2, 3, 4};
  BufferDesc bd;
  bd.size = sizeof(init);
  bd.initialData = init;
  bd.label = "sixteen bytes";
  BufferHandle b;
  expectValid([&] { b = dev_->createBuffer(bd); });
  uint32_t v[2] = {9, 9};
  expectDropped("E_WRITE_OUT_OF_RANGE", [&] { dev_->writeBuffer(b, 12, v, 8); });
  EXPECT_NE(lastMessage().find("'sixteen bytes'"), std::string::npos);
  std::vector<uint8_t> back = dev_->readBuffer(b, 0, 16);
  ASSERT_EQ(back.size(), 16u);
  EXPECT_EQ(std::memcmp(back.data(), init, 16), 0) << "the dropped write changed the buffer";
}

TEST_P(RhiValidationTest, E_READ_OUT_OF_RANGE) {
  BufferHandle b = buffer(16);
  expectDropped("E_READ_OUT_OF_RANGE", [&] { EXPECT_TRUE(dev_->readBuffer(b, 8, 16).empty()); });
}

TEST_P(RhiValidationTest, E_COPY_OUT_OF_RANGE) {
  BufferHandle a = buffer(16), b = buffer(8);
  expectDropped("E_COPY_OUT_OF_RANGE", [&] { dev_->copyBuffer(a, 0, b, 0, 16); });
  expectDropped("E_COPY_OUT_OF_RANGE", [&] { dev_->copyBuffer(a, 12, b, 0, 8); });
}

TEST_P(RhiValidationTest, E_SUBRESOURCE_RANGE) {
  TextureHandle t = texture(Format::RGBA8);
  expectDropped("E_SUBRESOURCE_RANGE", [&] {
    EXPECT_TRUE(dev_->readTexture(t, {1, 0, TextureAspect::Color}).empty());
  });
  std::vector<uint8_t> data(64);
  expectDropped("E_SUBRESOURCE_RANGE", [&] { dev_->writeTexture(t, 0, 1, data.data()); });
  // A Tex3D's layers are its slices, fewer at each mip: 4x4x4 has 2 slices at mip 1.
  TextureDesc d;
  d.type = TextureType::Tex3D;
  d.width = d.height = d.depth = 4;
  d.mipLevels = 2;
  TextureHandle vol;
  expectValid([&] { vol = dev_->createTexture(d); });
  expectValid([&] {
    EXPECT_EQ(dev_->readTexture(vol, {3, 0, TextureAspect::Color}).size(), 64u);
    EXPECT_EQ(dev_->readTexture(vol, {1, 1, TextureAspect::Color}).size(), 16u);
  });
  expectDropped("E_SUBRESOURCE_RANGE", [&] {
    EXPECT_TRUE(dev_->readTexture(vol, {4, 0, TextureAspect::Color}).empty());
  });
  expectDropped("E_SUBRESOURCE_RANGE", [&] { dev_->writeTexture(vol, 2, 1, data.data()); });
}

TEST_P(RhiValidationTest, E_TRANSFER_MSAA) {
  TextureHandle m = texture(Format::RGBA8, 4, 4, TextureUsage_Default, 4), s = texture(Format::RGBA8);
  std::vector<uint8_t> data(64);
  expectDropped("E_TRANSFER_MSAA", [&] { dev_->writeTexture(m, 0, 0, data.data()); });
  expectDropped("E_TRANSFER_MSAA", [&] { dev_->copyTexture(m, s); });
}

TEST_P(RhiValidationTest, E_READBACK_MSAA) {
  TextureHandle m = texture(Format::RGBA8, 4, 4, TextureUsage_Default, 4);
  expectDropped("E_READBACK_MSAA", [&] { EXPECT_TRUE(dev_->readTexture(m).empty()); });
}

TEST_P(RhiValidationTest, E_READBACK_ASPECT) {
  TextureHandle c = texture(Format::RGBA8), d = texture(Format::D32F);
  expectDropped("E_READBACK_ASPECT", [&] { EXPECT_TRUE(dev_->readTexture(c, {0, 0, TextureAspect::Depth}).empty()); });
  expectDropped("E_READBACK_ASPECT", [&] {
    EXPECT_TRUE(dev_->readTexture(d, {0, 0, TextureAspect::Stencil}).empty());
  });
  expectDropped("E_READBACK_ASPECT", [&] { EXPECT_TRUE(dev_->readTexture(d, {0, 0, TextureAspect::Color}).empty()); });
}

TEST_P(RhiValidationTest, E_COPY_SIZE_CLASS) {
  TextureHandle a = texture(Format::RGBA8), b = texture(Format::RGBA16F);
  expectDropped("E_COPY_SIZE_CLASS", [&] { dev_->copyTexture(a, b); });
}

TEST_P(RhiValidationTest, E_COPY_SIZE_MISMATCH) {
  TextureHandle a = texture(Format::RGBA8, 4, 4), b = texture(Format::R32_UINT, 8, 4);
  expectDropped("E_COPY_SIZE_MISMATCH", [&] { dev_->copyTexture(a, b); });
}

TEST_P(RhiValidationTest, E_COPY_DEPTH) {
  TextureHandle a = texture(Format::D32F), b = texture(Format::R32F);
  expectDropped("E_COPY_DEPTH", [&] { dev_->copyTexture(a, b); });
  TextureHandle c = texture(Format::D24S8);
  expectDropped("E_COPY_DEPTH", [&] { dev_->copyTexture(a, c); });
}

TEST_P(RhiValidationTest, E_COPY_OVERLAP) {
  TextureHandle a = texture(Format::RGBA8);
  expectDropped("E_COPY_OVERLAP", [&] { dev_->copyTexture(a, a); });
  BufferHandle b = buffer(64);
  expectDropped("E_COPY_OVERLAP", [&] { dev_->copyBuffer(b, 0, b, 8, 16); });
}

TEST_P(RhiValidationTest, E_TIMESTAMP_IN_PASS) {
  TextureHandle t = texture(Format::RGBA8);
  begin(t);
  expectDropped("E_TIMESTAMP_IN_PASS", [&] { EXPECT_EQ(dev_->writeTimestamp(), kInvalidTimestamp); });
  expectDropped("E_TIMESTAMP_IN_PASS", [&] { dev_->resetTimestamps(); });
  end();
  expectValid([&] { EXPECT_FALSE(dev_->timestampNs(kInvalidTimestamp).has_value()); });
}

TEST_P(RhiValidationTest, E_TIMESTAMP_PENDING) {
  TimestampId id = 0;
  expectValid([&] { id = dev_->writeTimestamp(); });
  expectDropped("E_TIMESTAMP_PENDING", [&] { EXPECT_FALSE(dev_->timestampNs(id).has_value()); });
  expectValid([&] {
    dev_->submit();
    EXPECT_TRUE(dev_->timestampNs(id).has_value());
  });
}

TEST_P(RhiValidationTest, E_SUBMIT_IN_PASS) {
  TextureHandle t = texture(Format::RGBA8);
  begin(t);
  expectDropped("E_SUBMIT_IN_PASS", [&] { dev_->submit(); });
  end();
}

// ---------------------------------------------------------------------------------------------
// Descriptor arrays
// ---------------------------------------------------------------------------------------------
const char* kUniformArrayFs = R"(#version 450
layout(set = 0, binding = 0) uniform U { vec4 color; } u[3];
layout(location = 0) out vec4 o;
void main() { o = u[0].color + u[1].color + u[2].color; })";

TEST_P(RhiValidationTest, E_BINDING_ARRAY_ELEMENT) {
  BufferHandle b = buffer(256, BufferUsage_Uniform);
  ResourceBinding r[2];
  r[0].buffer = b;
  r[0].arrayElement = kMaxArrayElements;
  expectDropped("E_BINDING_ARRAY_ELEMENT", [&] { dev_->setBindings({r, 1}); });
  // Two elements of one binding in one call are two bindings; the same element twice is not.
  r[0].arrayElement = 2;
  r[1] = r[0];
  r[1].arrayElement = 1;
  expectValid([&] { dev_->setBindings({r, 2}); });
  r[1].arrayElement = 2;
  expectDropped("E_BINDING_INDEX", [&] { dev_->setBindings({r, 2}); });
}

TEST_P(RhiValidationTest, E_BINDING_MISSING_ArrayElement) {
  TextureHandle t = texture(Format::RGBA8);
  PipelineHandle p = simplePipeline(kUniformArrayFs);
  BufferHandle b = buffer(256, BufferUsage_Uniform);
  ResourceBinding r[3];
  for (uint32_t e = 0; e < 3; ++e) {
    r[e].buffer = b;
    r[e].arrayElement = e;
  }
  expectValid([&] { dev_->setBindings({r, 2}); });  // elements 0 and 1 of 3
  begin(t);
  expectValid([&] { dev_->setPipeline(p); });
  expectDropped("E_BINDING_MISSING", [&] { dev_->draw(3); });
  EXPECT_NE(lastMessage().find("binding 0[2]"), std::string::npos) << lastMessage();
  expectValid([&] {
    dev_->setBindings({&r[2], 1});  // merges: elements 0 and 1 stay bound
    dev_->draw(3);
  });
  end();
}

TEST_P(RhiValidationTest, E_PIPELINE_ARRAY_SIZE) {
  ShaderHandle vs = shader(ShaderStage::Vertex, R"(#version 450
layout(set = 0, binding = 0) uniform U { vec4 offset; } u[2];
void main() { gl_Position = u[0].offset + u[1].offset; })");
  ShaderHandle fs = shader(ShaderStage::Fragment, kUniformArrayFs);
  PipelineDesc d = pipelineDesc(vs, fs);
  expectDropped("E_PIPELINE_ARRAY_SIZE", [&] { EXPECT_FALSE(dev_->createPipeline(d)); });
}

TEST_P(RhiValidationTest, E_SHADER_REFLECTION_DescriptorArrays) {
  ShaderDesc d;
  d.stage = ShaderStage::Fragment;
  const char* broken[] = {
      // more than kMaxArrayElements
      R"(#version 450
layout(set = 0, binding = 0) uniform sampler2D s[17];
layout(location = 0) out vec4 o;
void main() { o = texelFetch(s[16], ivec2(0), 0); })",
      // sized by a specialization constant
      R"(#version 450
layout(constant_id = 0) const int kCount = 2;
layout(set = 0, binding = 0) uniform sampler2D s[kCount];
layout(location = 0) out vec4 o;
void main() { o = texelFetch(s[1], ivec2(0), 0); })",
  };
  for (const char* glsl : broken) {
    d.spirv = spirv(ShaderStage::Fragment, glsl);
    expectDropped("E_SHADER_REFLECTION", [&] { EXPECT_FALSE(dev_->createShader(d)); });
  }
  d.spirv = spirv(ShaderStage::Fragment, R"(#version 450
layout(set = 0, binding = 0) uniform sampler2D s[16];
layout(location = 0) out vec4 o;
void main() { o = texelFetch(s[15], ivec2(0), 0); })");
  expectValid([&] { EXPECT_TRUE(dev_->createShader(d)); });
}

TEST_P(RhiValidationTest, E_SHADER_SAMPLER_ARRAY) {
  ShaderDesc d;
  d.stage = ShaderStage::Fragment;
  d.spirv = spirv(ShaderStage::Fragment, R"(#version 450
layout(set = 0, binding = 0) uniform texture2D t;
layout(set = 0, binding = 1) uniform sampler s[2];
layout(location = 0) out vec4 o;
void main() { o = texture(sampler2D(t, s[0]), vec2(0.5)) + texture(sampler2D(t, s[1]), vec2(0.5)); })");
  if (dev_->info().caps.separateSamplerArrays)
    expectValid([&] { EXPECT_TRUE(dev_->createShader(d)); });
  else
    expectDropped("E_SHADER_SAMPLER_ARRAY", [&] { EXPECT_FALSE(dev_->createShader(d)); });
}

INSTANTIATE_TEST_SUITE_P(Rhi, RhiValidationTest, ::testing::ValuesIn(allBackends()), BackendName());

// ---------------------------------------------------------------------------------------------
// The rule table itself.
// ---------------------------------------------------------------------------------------------
TEST(RhiValidationRules, TableIsWellFormed) {
  const auto& rules = validationRules();
  ASSERT_EQ(rules.size(), static_cast<size_t>(ValidationRuleId::Count));
  std::set<std::string> seen;
  for (size_t i = 0; i < rules.size(); ++i) {
    const ValidationRule& r = rules[i];
    EXPECT_EQ(r.id.rfind("E_", 0), 0u) << r.id;
    EXPECT_TRUE(seen.insert(r.id).second) << "duplicate id " << r.id;
    EXPECT_FALSE(r.description.empty()) << r.id;
    EXPECT_EQ(r.description.find('\n'), std::string::npos) << r.id;
    EXPECT_EQ(validationRuleName(static_cast<ValidationRuleId>(i)), r.id);
    const ValidationRule* found = findValidationRule(r.id);
    ASSERT_NE(found, nullptr);
    EXPECT_EQ(found->description, r.description);
  }
  EXPECT_EQ(findValidationRule("E_NO_SUCH_RULE"), nullptr);
}

TEST(RhiValidationRules, EveryRuleHasATest) {
  std::set<std::string> tested;
  const ::testing::UnitTest& unit = *::testing::UnitTest::GetInstance();
  for (int i = 0; i < unit.total_test_suite_count(); ++i) {
    const ::testing::TestSuite& suite = *unit.GetTestSuite(i);
    if (std::string(suite.name()).find("RhiValidationTest") == std::string::npos) continue;
    for (int j = 0; j < suite.total_test_count(); ++j) {
      std::string name = suite.GetTestInfo(j)->name();
      tested.insert(name.substr(0, name.find('/')));
    }
  }
  for (const ValidationRule& r : validationRules()) EXPECT_TRUE(tested.count(r.id)) << "no test for " << r.id;
}

}  // namespace
}  // namespace parity::rhi
