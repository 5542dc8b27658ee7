// The platform layers' real GPU path on every backend, compared with the CPU models.
//
// Each test renders known values through the platform's write path (platform.glsl's
// parityWriteRg16Bits into GpuTargets::writeTarget(), or the depth test), runs the platform's resolve / copy pass (GpuTargets), reads
// them through the read path (parityReadRg16 / parityReadDepth) into an RG32F / R32F target and
// compares with the CPU model of platforms/<platform>/.
//
// Tolerances:
//  * Integer words (x360 EDRAM int16 and resolved words, PS3 packed bytes, D24 words) are compared
//    bit for bit: the shaders evaluate the model's fp32 expressions in the same order with
//    `precise` (no contraction) and store the integers through integer views, so no driver
//    float -> unorm/snorm conversion decides them.
//  * Final floats (what a technique's shader reads) may differ by 1 ULP: they come from the texture
//    unit's unorm/snorm-to-float conversion or a shader division by 65535, 32767 or 16777215,
//    neither of which GLSL/SPIR-V requires to be correctly rounded (the model's are), and the
//    pack itself allows 1 ULP for texDepth2D_precise (P4).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "platforms/dx10/depth_read.h"
#include "platforms/platform_device.h"
#include "platforms/platform_layer.h"
#include "platforms/ps3/depth_read.h"
#include "platforms/ps3/packed16.h"
#include "platforms/x360/fixed16.h"
#include "platforms/x360/float7e3.h"
#include "platforms/x360/pixel_center.h"
#include "platforms/x360/resolve.h"
#include "rhi/shader_compiler.h"
#include "tests/test_support.h"

namespace parity::platforms {
namespace {

using Param = std::tuple<std::string, PlatformId>;

const char* kFullscreenVs = R"(#version 450
void main() {
  vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
})";

// Writes the source RG32F texel through the platform's exact write path (integer view).
const char* kWriteRg16BitsFs = R"(#version 450
#include "platform.glsl"
layout(binding = 0) uniform sampler2D uSource;
layout(location = 0) out PARITY_RG16_BITS_TYPE o;
void main() { o = parityWriteRg16Bits(texelFetch(uSource, ivec2(gl_FragCoord.xy), 0).xy); })";

// The same through the blendable float path into the attachment.
const char* kWriteRg16Fs = R"(#version 450
#include "platform.glsl"
layout(binding = 0) uniform sampler2D uSource;
layout(location = 0) out vec4 o;
void main() { o = parityWriteRg16(texelFetch(uSource, ivec2(gl_FragCoord.xy), 0).xy); })";

const char* kWriteHdrFs = R"(#version 450
#include "platform.glsl"
layout(binding = 0) uniform sampler2D uSource;
layout(location = 0) out vec4 o;
void main() { o = parityWriteRgba16Hdr(texelFetch(uSource, ivec2(gl_FragCoord.xy), 0)); })";

const char* kReadHdrFs = R"(#version 450
#include "platform.glsl"
layout(binding = 0) uniform sampler2D uRead;
layout(location = 0) out vec4 o;
void main() { o = parityReadRgba16Hdr(texelFetch(uRead, ivec2(gl_FragCoord.xy), 0)); })";

// Reads the platform's read texture back to RG32F.
const char* kReadRg16Fs = R"(#version 450
#include "platform.glsl"
layout(binding = 0) uniform PARITY_RG16_SAMPLER uRead;
layout(location = 0) out vec2 o;
void main() { o = parityReadRg16(texelFetch(uRead, ivec2(gl_FragCoord.xy), 0)); })";

const char* kWriteDepthFs = R"(#version 450
layout(binding = 0) uniform sampler2D uSource;
void main() { gl_FragDepth = texelFetch(uSource, ivec2(gl_FragCoord.xy), 0).x; })";

const char* kReadDepthFs = R"(#version 450
#include "platform.glsl"
layout(binding = 0) uniform PARITY_DEPTH_SAMPLER uDepth;
layout(location = 0) out float o;
void main() { o = parityReadDepth(texelFetch(uDepth, ivec2(gl_FragCoord.xy), 0)); })";

int ulpDistance(float a, float b) {
  if (a == b) return 0;
  if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<int>::max();
  int32_t ia, ib;
  std::memcpy(&ia, &a, 4);
  std::memcpy(&ib, &b, 4);
  if ((ia < 0) != (ib < 0)) return std::numeric_limits<int>::max();
  return std::abs(ia - ib);
}

std::vector<float> asFloats(const std::vector<uint8_t>& b) {
  std::vector<float> f(b.size() / 4);
  std::memcpy(f.data(), b.data(), f.size() * 4);
  return f;
}

class PlatformGpuTest : public ::testing::TestWithParam<Param> {
 protected:
  void SetUp() override {
    dev = parity::test::makeDevice(std::get<0>(GetParam()));
    if (!dev) GTEST_SKIP() << "backend unavailable";
    platform = std::get<1>(GetParam());
  }
  void TearDown() override {
    for (auto p : pipelines) dev->destroy(p);
    for (auto s : shaders) dev->destroy(s);
    dev.reset();
  }

  rhi::ShaderHandle shader(rhi::ShaderStage stage, const std::string& glsl, const TargetPlan& plan) {
    rhi::CompiledShader c = rhi::compileGlslSource(glsl, "platform_gpu_test", stage, platformShaderOptions(plan));
    EXPECT_TRUE(c.ok()) << c.error;
    rhi::ShaderDesc d;
    d.stage = stage;
    d.spirv = c.spirv;
    rhi::ShaderHandle h = dev->createShader(d);
    shaders.push_back(h);
    return h;
  }

  rhi::PipelineHandle fullscreen(const std::string& fs, const TargetPlan& plan, rhi::Format color, rhi::Format depth,
                                 const rhi::BlendState& blend = {}, uint8_t writeMask = rhi::ColorMask_All,
                                 const std::string& vs = kFullscreenVs) {
    rhi::PipelineDesc p;
    p.vertexShader = shader(rhi::ShaderStage::Vertex, vs, plan);
    p.fragmentShader = shader(rhi::ShaderStage::Fragment, fs, plan);
    if (color != rhi::Format::Undefined) {
      p.colorTargets[0].format = color;
      p.colorTargets[0].blend = blend;
      p.colorTargets[0].writeMask = writeMask;
      p.colorTargetCount = 1;
    }
    p.depthStencilFormat = depth;
    if (depth != rhi::Format::Undefined) p.depthStencil.depthWrite = true;
    rhi::PipelineHandle h = dev->createPipeline(p);
    pipelines.push_back(h);
    return h;
  }

  rhi::TextureHandle source(rhi::Format f, uint32_t w, uint32_t h, const void* data) {
    rhi::TextureDesc d;
    d.format = f;
    d.width = w;
    d.height = h;
    d.usage = rhi::TextureUsage_Sampled;
    d.initialData = data;
    return dev->createTexture(d);
  }

  // One draw of `vertices` (the full-screen triangle by default). `load` keeps the target's
  // contents (for blending onto them); `viewport` shifts the guest's window positions (X5).
  void pass(rhi::TextureHandle color, rhi::TextureHandle depth, rhi::PipelineHandle p, rhi::TextureHandle input,
            bool load = false, rhi::SamplerHandle sampler = {}, uint32_t vertices = 3,
            const rhi::Viewport* viewport = nullptr) {
    rhi::PassDesc pd;
    pd.colors[0].texture = color;
    if (load) pd.colors[0].load = rhi::LoadOp::Load;
    pd.depthStencil.texture = depth;
    dev->beginPass(pd);
    dev->setPipeline(p);
    if (viewport) dev->setViewport(*viewport);
    rhi::ResourceBinding b;
    b.binding = 0;
    b.kind = rhi::BindingKind::SampledTexture;
    b.texture = input;
    b.sampler = sampler;
    if (input) dev->setBindings({&b, 1});
    dev->draw(vertices);
    dev->endPass();
  }

  rhi::TextureHandle target(rhi::Format f, uint32_t w, uint32_t h) {
    rhi::TextureDesc d;
    d.format = f;
    d.width = w;
    d.height = h;
    return dev->createTexture(d);
  }

  // Writes (x, y) pairs through the platform's Rg16Unorm path, resolves, reads back to floats.
  // `edramWords` gets the write path's console bytes, `resolvedWords` the resolved ones.
  std::vector<float> roundTripRg16(const std::vector<float>& xy, uint32_t w, uint32_t h, const PlatformParams& params,
                                   std::vector<uint8_t>* written = nullptr, std::vector<uint8_t>* resolved = nullptr) {
    LogicalTarget t{"dsf", LogicalFormat::Rg16Unorm, true, TargetRole::GBuffer, "geometry"};
    TargetPlan plan = planTargets(platform, {&t, 1}, w, h, params);
    GpuTargets gpu(*dev, plan);
    rhi::TextureHandle src = source(rhi::Format::RG32F, w, h, xy.data());
    const PhysicalTarget& pt = plan.targets[0];
    pass(gpu.writeTarget("dsf"), {}, fullscreen(kWriteRg16BitsFs, plan, pt.writeFormat, rhi::Format::Undefined), src);
    EXPECT_TRUE(gpu.resolve("dsf")) << gpu.error();
    rhi::TextureDesc od;
    od.format = rhi::Format::RG32F;
    od.width = w;
    od.height = h;
    rhi::TextureHandle out = dev->createTexture(od);
    pass(out, {}, fullscreen(kReadRg16Fs, plan, rhi::Format::RG32F, rhi::Format::Undefined), gpu.readTexture("dsf"));
    std::vector<float> result = asFloats(dev->readTexture(out));
    if (written) *written = gpu.consoleBytes("dsf");
    if (resolved) *resolved = gpu.consoleBytes("dsf", true);
    dev->destroy(out);
    dev->destroy(src);
    return result;
  }

  std::vector<float> roundTripDepth(const std::vector<float>& d, uint32_t w, uint32_t h,
                                    std::vector<uint8_t>* stored = nullptr) {
    LogicalTarget t{"depth", LogicalFormat::Depth24Stencil8, true, TargetRole::GBuffer, "geometry"};
    TargetPlan plan = planTargets(platform, {&t, 1}, w, h, {});
    GpuTargets gpu(*dev, plan);
    rhi::TextureHandle src = source(rhi::Format::R32F, w, h, d.data());
    const PhysicalTarget& pt = plan.targets[0];
    pass({}, gpu.attachment("depth"), fullscreen(kWriteDepthFs, plan, rhi::Format::Undefined, pt.attachmentFormat), src);
    EXPECT_TRUE(gpu.resolve("depth")) << gpu.error();
    rhi::TextureDesc od;
    od.format = rhi::Format::R32F;
    od.width = w;
    od.height = h;
    rhi::TextureHandle out = dev->createTexture(od);
    pass(out, {}, fullscreen(kReadDepthFs, plan, rhi::Format::R32F, rhi::Format::Undefined), gpu.readTexture("depth"));
    std::vector<float> result = asFloats(dev->readTexture(out));
    if (stored) *stored = gpu.consoleBytes("depth");
    dev->destroy(out);
    dev->destroy(src);
    return result;
  }

  std::unique_ptr<rhi::Device> dev;
  PlatformId platform = PlatformId::Reference;
  std::vector<rhi::PipelineHandle> pipelines;
  std::vector<rhi::ShaderHandle> shaders;
};

// Platform-specific GPU tests: the same fixture, instantiated for one platform only.
class X360GpuTest : public PlatformGpuTest {};
class Ps3GpuTest : public PlatformGpuTest {};
class Dx10GpuTest : public PlatformGpuTest {};
class ConsoleGpuTest : public PlatformGpuTest {};  // the platforms whose Rg16Unorm path stores integers

// The CPU model's value for a logical Rg16Unorm component v, and its stored 16-bit word.
struct Rg16Model {
  float value;
  uint16_t word;  // ps3/dx10: X16; x360: EDRAM int16 bits; reference: unused
};
Rg16Model modelRg16(PlatformId p, float v, const PlatformParams& params) {
  switch (p) {
    case PlatformId::Reference: return {v, 0};
    case PlatformId::Dx10: {
      uint16_t q = ps3::quantizeUnorm16(v);
      return {float(q) / 65535.0f, q};
    }
    case PlatformId::Ps3: {
      ps3::Argb8Bytes b = ps3::packTwo16InArgb8(v, 0.0f);
      return {ps3::sampleY16X16(b)->r, uint16_t(b[0] << 8 | b[1])};
    }
    case PlatformId::X360: {
      x360::DsfPathResult r = x360::runDsfPath(x360::dsfPath(params.dsfResolvePath), v, params);
      return {r.reconstructed, uint16_t(r.edram)};
    }
  }
  return {v, 0};
}

// 1 ULP of the value read, or, for x360 path C, 1 ULP of the fetched t in (-1, 1) carried
// through v' = (t + 1) / 2: the cancellation near t = -1 turns it into 2^-25 absolute.
bool rg16Close(float got, float model) {
  return ulpDistance(got, model) <= 1 || std::fabs(double(got) - double(model)) <= std::ldexp(1.0, -25);
}

// P2 / X3 / D1 vectors, both channels, against the CPU model.
TEST_P(PlatformGpuTest, Rg16VectorsMatchTheModel) {
  const std::vector<float> xs = {0.123456f, 0.987654f, 0.5f, 0.25f, 1.0f, 0.0f, 0.75f, 0.001f};
  std::vector<float> xy;
  for (size_t i = 0; i < xs.size(); ++i) {
    xy.push_back(xs[i]);
    xy.push_back(xs[xs.size() - 1 - i]);
  }
  const uint32_t w = uint32_t(xs.size()), h = 1;
  PlatformParams params;
  std::vector<uint8_t> written;
  std::vector<float> got = roundTripRg16(xy, w, h, params, &written);
  ASSERT_EQ(got.size(), xy.size());
  for (size_t i = 0; i < xy.size(); ++i) {
    Rg16Model m = modelRg16(platform, xy[i], params);
    EXPECT_TRUE(rg16Close(got[i], m.value)) << "v = " << xy[i] << ": got " << got[i] << ", model " << m.value;
    if (platform == PlatformId::Ps3) {
      // Console memory [A, R, G, B] = [hiX, loX, hiY, loY], bit-exact.
      ps3::Argb8Bytes b = ps3::packTwo16InArgb8(xy[i & ~size_t(1)], xy[i | 1]);
      for (int k = 0; k < 4; ++k) EXPECT_EQ(written[(i / 2) * 4 + k], b[k]) << "pixel " << i / 2 << " byte " << k;
    } else if (platform == PlatformId::X360) {
      uint16_t word = uint16_t(written[i * 2] | written[i * 2 + 1] << 8);
      EXPECT_EQ(word, m.word) << "EDRAM int16 for v = " << xy[i];
    } else if (platform == PlatformId::Dx10) {
      uint16_t word = uint16_t(written[i * 2] | written[i * 2 + 1] << 8);
      EXPECT_EQ(word, m.word) << "R16G16_UNORM word for v = " << xy[i];
    }
  }
  if (platform == PlatformId::Ps3) {
    // Pack vector: (0.123456, 0.987654) -> bytes 1F 9B FC D6.
    std::vector<float> v = {0.123456f, 0.987654f};
    std::vector<uint8_t> bytes;
    roundTripRg16(v, 1, 1, params, &bytes);
    EXPECT_EQ(bytes, (std::vector<uint8_t>{0x1F, 0x9B, 0xFC, 0xD6}));
  }
}

// X3 (3): paths A, B, C for v = 0.123456 (EDRAM int16, resolved word, sampled value).
TEST_P(X360GpuTest, ResolvePathsABC) {
  struct Case {
    DsfResolvePath path;
    uint16_t edram, resolved;
  } cases[] = {{DsfResolvePath::NaiveA, 0x007E, 0x1F80},
               {DsfResolvePath::XdkBiasB, 0x0FCD, 0x1F9A},
               {DsfResolvePath::PaperSignedC, 0x9F9C, 0x9F9C}};
  for (const Case& c : cases) {
    PlatformParams params;
    params.dsfResolvePath = c.path;
    std::vector<uint8_t> written, resolved;
    std::vector<float> got = roundTripRg16({0.123456f, 0.123456f}, 1, 1, params, &written, &resolved);
    x360::DsfPathResult m = x360::runDsfPath(x360::dsfPath(c.path), 0.123456f, params);
    SCOPED_TRACE(std::string("path ") + std::string(x360::dsfPath(c.path).name));
    ASSERT_EQ(written.size(), 4u);
    ASSERT_EQ(resolved.size(), 4u);
    EXPECT_EQ(uint16_t(written[0] | written[1] << 8), c.edram);
    EXPECT_EQ(uint16_t(resolved[0] | resolved[1] << 8), c.resolved);
    EXPECT_EQ(uint16_t(resolved[0] | resolved[1] << 8), m.resolved.word);
    EXPECT_LE(ulpDistance(got[0], m.reconstructed), 1) << got[0] << " vs " << m.reconstructed;
  }
}

// X2 (3): encode vectors through the write path (path A writes c = v directly).
TEST_P(X360GpuTest, Fixed16EncodeVectors) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<float> cs = {0.0f, 1.0f, -1.0f, 32.0f, -32.0f, 40.0f, -40.0f, nan, 0.5f * 32.0f / 32767.0f, 0.123456f};
  PlatformParams params;
  params.dsfResolvePath = DsfResolvePath::NaiveA;
  std::vector<float> xy;
  for (float c : cs) xy.insert(xy.end(), {c, -c});
  std::vector<uint8_t> written;
  roundTripRg16(xy, uint32_t(cs.size()), 1, params, &written);
  ASSERT_EQ(written.size(), xy.size() * 2);
  for (size_t i = 0; i < xy.size(); ++i) {
    uint16_t word = uint16_t(written[i * 2] | written[i * 2 + 1] << 8);
    EXPECT_EQ(word, uint16_t(x360::encodeFixed16(xy[i], 0).value)) << "c = " << xy[i];
  }
  auto word = [&](size_t element) { return uint16_t(written[element * 2] | written[element * 2 + 1] << 8); };
  EXPECT_EQ(word(2), 0x0400);   // +1
  EXPECT_EQ(word(3), 0xFC00);   // -1
  EXPECT_EQ(word(6), 0x7FFF);   // +32
  EXPECT_EQ(word(10), 0x7FFF);  // +40 clamps
  EXPECT_EQ(word(11), 0x8001);  // -40 clamps
  EXPECT_EQ(word(14), 0x0000);  // NaN -> 0
  EXPECT_EQ(word(16), 0x0001);  // half a step rounds away from zero
}

// X2 (3) aliasing round trip on the GPU path: raw k_16_16 words (0x8000 among them) stored in the
// EDRAM surface and read back through its aliased bit views (the readback and the GPU pass that
// lays out the EDRAM image both read the RG16_UINT view of the RG16_SNORM attachment) keep every
// bit; a SNORM float round trip would turn 0x8000 into 0x8001.
TEST_P(X360GpuTest, RawFixed16WordsSurviveTheAliasedViews) {
  LogicalTarget t{"dsf", LogicalFormat::Rg16Unorm, true, TargetRole::GBuffer, "geometry"};
  TargetPlan plan = planTargets(platform, {&t, 1}, 2, 1, {});
  GpuTargets gpu(*dev, plan);
  const uint16_t words[4] = {0x8000, 0x8000, 0x7FFF, 0x8001};  // pixel (0, 0) R, G; pixel (1, 0) R, G
  dev->writeTexture(gpu.attachment("dsf"), 0, 0, words);
  const std::vector<uint8_t> stored = gpu.consoleBytes("dsf");
  ASSERT_EQ(stored.size(), 8u);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(uint16_t(stored[i * 2] | stored[i * 2 + 1] << 8), words[i]) << "word " << i;
  const std::vector<uint8_t> edram = gpu.edramBytes("dsf");
  ASSERT_GE(edram.size(), 8u);
  auto dword = [&](size_t at) { return uint32_t(edram[at] | edram[at + 1] << 8 | edram[at + 2] << 16 | uint32_t(edram[at + 3]) << 24); };
  EXPECT_EQ(dword(0), 0x80008000u) << "pixel (0, 0), R low";
  EXPECT_EQ(dword(4), 0x80017FFFu) << "pixel (1, 0)";
  EXPECT_EQ(x360::transferThroughSnorm16(0x8000), 0x8001) << "the lossy path this guards against";
}

// X3 (3): the MSAA averaging vector, 2x samples 0x0800 / 0xF800 resolved with k01 into unsigned
// k_16_16 (path A's destination): the model gives 0, mainline Xenia's -1 unpack clamp 0.50003.
TEST_P(X360GpuTest, MsaaAveragingVector) {
  for (K16UnpackClamp clamp : {K16UnpackClamp::Minus32, K16UnpackClamp::Minus1}) {
    PlatformParams params;
    params.dsfResolvePath = DsfResolvePath::NaiveA;
    params.k16UnpackClamp = clamp;
    LogicalTarget t{"dsf", LogicalFormat::Rg16Unorm, true, TargetRole::GBuffer, "geometry"};
    TargetPlan plan = planTargets(platform, {&t, 1}, 1, 2, params);  // 1 pixel, 2 sample rows
    GpuTargets gpu(*dev, plan);
    const uint16_t samples[4] = {0x0800, 0x0800, 0xF800, 0xF800};  // row 0 = sample 0, row 1 = sample 1
    dev->writeTexture(gpu.attachment("dsf"), 0, 0, samples);
    ASSERT_TRUE(gpu.resolve("dsf", 2)) << gpu.error();
    std::vector<uint8_t> resolved = gpu.consoleBytes("dsf", true);
    const int16_t s[] = {int16_t(0x0800), int16_t(0xF800)};
    x360::ResolvedComponent m =
        x360::resolveFixed16Component(s, 0, x360::SurfaceNumberFormat::kUnsignedRepeatingFraction, params);
    ASSERT_GE(resolved.size(), 4u);
    EXPECT_EQ(uint16_t(resolved[0] | resolved[1] << 8), m.word);
    EXPECT_EQ(m.word, clamp == K16UnpackClamp::Minus32 ? 0u : x360::packUnorm16(0.50003052f));
  }
}

// --- x360 4x MSAA and 64-bpp surfaces through the GPU path --------------------------------------
//
// Known values are written sample by sample through the platform's write path (one draw per
// guest sample, gl_SampleMask selecting the host sample that holds it), resolved with the
// platform's k0123 averaging and exported as EDRAM bytes by the platform's GPU pass; the CPU
// model writes the same words into EdramMemory and runs resolveSurface. Tolerance: none. Every
// compared quantity is an integer word the shaders compute with the model's fp32 expressions in
// the model's order (`precise`, sums in guest sample order, ldexp for the powers of two), and
// the words reach the GPU through integer views or as exact fp32 multiples of 2^-15.

// A fragment shader writing sample `host` of a 4x target: `write` of the source texel `t` of the
// guest sample, column 4x + guest of a (4w) x h texture, as a value of type `outType`.
std::string writePerSampleFs(const std::string& outType, const std::string& write) {
  return R"(#version 450
#include "platform.glsl"
layout(binding = 0) uniform sampler2D uSource;
layout(push_constant) uniform Sample { int guest; int host; } uSample;
layout(location = 0) out )" + outType + R"( o;
void main() {
  gl_SampleMask[0] = 1 << uSample.host;
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec4 t = texelFetch(uSource, ivec2(p.x * 4 + uSample.guest, p.y), 0);
  o = )" + write + R"(;
})";
}
const std::string kWriteRg16BitsPerSampleFs = writePerSampleFs("PARITY_RG16_BITS_TYPE", "parityWriteRg16Bits(t.xy)");
const std::string kWriteHdrPerSampleFs = writePerSampleFs("vec4", "parityWriteRgba16Hdr(t)");
const std::string kWriteColorPerSampleFs = writePerSampleFs("vec4", "t");

class X360MsaaGpuTest : public PlatformGpuTest {
 protected:
  // Writes every sample of the 4x target `name` from `perSample` ((4w) x h texels of `sourceFormat`).
  void writeSamples(GpuTargets& gpu, const std::string& name, const std::string& fs, rhi::Format sourceFormat,
                    const std::vector<float>& perSample) {
    const TargetPlan& plan = gpu.plan();
    const PhysicalTarget& pt = *plan.find(name);
    ASSERT_EQ(pt.samples, 4u);
    rhi::PipelineDesc p;
    p.vertexShader = shader(rhi::ShaderStage::Vertex, kFullscreenVs, plan);
    p.fragmentShader = shader(rhi::ShaderStage::Fragment, fs, plan);
    p.colorTargets[0].format = pt.writeFormat;
    p.colorTargetCount = 1;
    p.samples = 4;
    rhi::PipelineHandle pipeline = dev->createPipeline(p);
    pipelines.push_back(pipeline);
    ASSERT_TRUE(pipeline);
    rhi::TextureHandle src = source(sourceFormat, plan.width * 4, plan.height, perSample.data());
    for (uint32_t guest = 0; guest < 4; ++guest) {
      rhi::PassDesc pd;
      pd.colors[0].texture = gpu.writeTarget(name);
      pd.colors[0].load = guest == 0 ? rhi::LoadOp::Clear : rhi::LoadOp::Load;
      dev->beginPass(pd);
      dev->setPipeline(pipeline);
      const int32_t pc[2] = {int32_t(guest), int32_t(x360::hostSampleIndex(x360::MsaaSamples::k4X, guest))};
      dev->pushConstants(pc, sizeof pc);
      rhi::ResourceBinding b;
      b.binding = 0;
      b.kind = rhi::BindingKind::SampledTexture;
      b.texture = src;
      dev->setBindings({&b, 1});
      dev->draw(3);
      dev->endPass();
    }
    dev->submit();
    dev->destroy(src);
  }
};

x360::EdramSurface modelSurface(const PhysicalTarget& t, const TargetPlan& plan) {
  x360::EdramSurface s;
  s.name = t.logical.name;
  s.colorFormat = t.logical.format == LogicalFormat::Rgba16Hdr ? x360::ColorRenderTargetFormat::k_16_16_16_16
                                                               : x360::ColorRenderTargetFormat::k_16_16;
  s.isDepth = t.logical.format == LogicalFormat::Depth24Stencil8;
  s.baseTile = t.edramBase;
  s.pitchPx = plan.width;
  s.heightPx = plan.height;
  s.msaa = t.samples == 4 ? x360::MsaaSamples::k4X : x360::MsaaSamples::k1X;
  return s;
}

// The model's bytes of a surface's tile span, tile `base` first.
std::vector<uint8_t> modelEdramSpan(const x360::EdramMemory& edram, const x360::EdramSurface& s) {
  std::vector<uint8_t> out;
  for (uint32_t i = 0; i < s.sizeTiles(); ++i) {
    const uint32_t tile = (s.baseTile + i) % x360::kEdramTileCount;
    auto first = edram.bytes().begin() + std::ptrdiff_t(tile) * x360::kEdramTileSizeBytes;
    out.insert(out.end(), first, first + x360::kEdramTileSizeBytes);
  }
  return out;
}

size_t firstDifference(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  for (size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    if (a[i] != b[i]) return i;
  return a.size() == b.size() ? a.size() : std::min(a.size(), b.size());
}

// Logical DSF value that path `spec` encodes to the int16 `s` (undoes c = (v * scale + offset)
// * 2^color_exp_bias; the test asserts that the model's encode gives `s` back).
float dsfValueFor(const x360::DsfPathSpec& spec, int16_t s) {
  return (std::ldexp(x360::decodeFixed16(s), -spec.colorExpBias) - spec.shaderOffset) / spec.shaderScale;
}

// X3 on a 4x k_16_16 surface: per-sample words through parityWriteRg16Bits, the k0123 resolve
// (unpack clamp, average, exponent bias, pack per the path's destination), the EDRAM image
// (X1 4x sample placement under both sample orders). Pixel 0 holds the pack's averaging vector
// (+2.000061, -2.000061, ...): 0 under the -32 unpack clamp, 0.50003 under mainline's -1.
TEST_P(X360MsaaGpuTest, K16Msaa4xResolveAndEdramMatchTheModel) {
  struct Case {
    DsfResolvePath path;
    K16UnpackClamp clamp;
    Msaa4xSampleOrder order;
  } cases[] = {{DsfResolvePath::NaiveA, K16UnpackClamp::Minus32, Msaa4xSampleOrder::XeniaMainline},
               {DsfResolvePath::NaiveA, K16UnpackClamp::Minus1, Msaa4xSampleOrder::XeniaMainline},
               {DsfResolvePath::PaperSignedC, K16UnpackClamp::Minus32, Msaa4xSampleOrder::XeniaMainline},
               {DsfResolvePath::PaperSignedC, K16UnpackClamp::Minus32, Msaa4xSampleOrder::CanaryCanonical},
               {DsfResolvePath::XdkBiasB, K16UnpackClamp::Minus32, Msaa4xSampleOrder::XeniaMainline}};
  const uint32_t w = 8, h = 8;
  std::vector<uint8_t> edramByOrder[2];
  for (const Case& c : cases) {
    PlatformParams params;
    params.dsfResolvePath = c.path;
    params.k16UnpackClamp = c.clamp;
    params.msaa4xSampleOrder = c.order;
    const x360::DsfPathSpec spec = x360::dsfPath(c.path);
    SCOPED_TRACE("path " + std::string(spec.name) + ", unpack clamp " + std::to_string(int(c.clamp)) +
                 ", sample order " + std::to_string(int(c.order)));
    LogicalTarget t{"dsf", LogicalFormat::Rg16Unorm, true, TargetRole::GBuffer, "geometry", 4};
    TargetPlan plan = planTargets(platform, {&t, 1}, w, h, params);
    const PhysicalTarget& pt = plan.targets[0];
    x360::EdramSurface surface = modelSurface(pt, plan);
    EXPECT_EQ(pt.edramTiles, surface.sizeTiles());
    // Words per sample: the pack vector at pixel 0, then a spread over the whole int16 range
    // (both clamp ends included) that makes the fp32 sums round.
    std::vector<float> perSample(size_t(w) * h * 4 * 2);
    x360::EdramMemory edram;
    for (uint32_t y = 0; y < h; ++y) {
      for (uint32_t x = 0; x < w; ++x) {
        for (uint32_t s = 0; s < 4; ++s) {
          int16_t words[2];
          const uint32_t i = (y * w + x) * 4 + s;
          for (uint32_t ch = 0; ch < 2; ++ch) {
            int32_t v = int32_t((i * 2 + ch) * 40503u % 65535u) - 32767;
            if (x == 0 && y == 0) v = (s % 2 == 0) ? 0x0800 : -0x0800;  // X3 averaging vector
            if (i == 5) v = ch == 0 ? 32767 : -32767;
            words[ch] = int16_t(v);
            perSample[(size_t(y) * w * 4 + x * 4 + s) * 2 + ch] = dsfValueFor(spec, words[ch]);
          }
          // The model's EDRAM word is what the path's encode stores for that value.
          const int16_t r = x360::runDsfPath(spec, perSample[(size_t(y) * w * 4 + x * 4 + s) * 2], params).edram;
          const int16_t g = x360::runDsfPath(spec, perSample[(size_t(y) * w * 4 + x * 4 + s) * 2 + 1], params).edram;
          ASSERT_EQ(r, words[0]);
          ASSERT_EQ(g, words[1]);
          edram.writeSample(surface, x, y, s, x360::packFixed16x2(r, g), params);
        }
      }
    }
    GpuTargets gpu(*dev, plan);
    writeSamples(gpu, "dsf", kWriteRg16BitsPerSampleFs, rhi::Format::RG32F, perSample);
    ASSERT_TRUE(gpu.resolve("dsf")) << gpu.error();
    const std::vector<uint8_t> resolved = gpu.consoleBytes("dsf", true);
    const std::vector<uint8_t> gpuEdram = gpu.edramBytes("dsf");

    x360::ResolveRequest request;
    request.rect = {0, 0, w, h};
    request.destFormat = x360::ColorFormat::k_16_16;
    request.destNumber = spec.destNumber;
    request.destExpBias = spec.destExpBias;
    request.sampleSelect = x360::CopySampleSelect::k0123;
    DiagnosticList diagnostics;
    const x360::ResolvedTexture model = x360::resolveSurface(edram, surface, request, diagnostics, params);
    ASSERT_EQ(resolved.size(), size_t(w) * h * 4);
    ASSERT_EQ(model.texels.size(), size_t(w) * h);
    int mismatches = 0;
    for (size_t i = 0; i < model.texels.size(); ++i) {
      const uint32_t got = uint32_t(resolved[i * 4]) | uint32_t(resolved[i * 4 + 1]) << 8 |
                           uint32_t(resolved[i * 4 + 2]) << 16 | uint32_t(resolved[i * 4 + 3]) << 24;
      if (got != uint32_t(model.texels[i]) && mismatches++ < 5)
        ADD_FAILURE() << "pixel " << i << ": GPU 0x" << std::hex << got << ", model 0x" << model.texels[i];
    }
    EXPECT_EQ(mismatches, 0);
    if (c.path == DsfResolvePath::NaiveA) {
      // Pixel 0, R: the pack's averaging vector into the unsigned destination.
      const uint16_t r0 = uint16_t(resolved[0] | resolved[1] << 8);
      EXPECT_EQ(r0, c.clamp == K16UnpackClamp::Minus32 ? 0u : x360::packUnorm16(0.50003052f));
    }
    const std::vector<uint8_t> modelEdram = modelEdramSpan(edram, surface);
    ASSERT_EQ(gpuEdram.size(), size_t(pt.edramTiles) * x360::kEdramTileSizeBytes);
    EXPECT_EQ(firstDifference(gpuEdram, modelEdram), gpuEdram.size()) << "first differing EDRAM byte";
    if (c.path == DsfResolvePath::PaperSignedC) edramByOrder[int(c.order)] = gpuEdram;
  }
  // X1 byte offsets of the 4x samples of pixel (0, 0) under mainline: s0 / s1 / s2 / s3 at
  // 0 / pitch row (80 samples = 320 bytes) / 4 / 324; the two orders place samples 1 and 2
  // differently, so their images differ.
  ASSERT_FALSE(edramByOrder[0].empty());
  EXPECT_NE(edramByOrder[0], edramByOrder[1]);
}

// X3 on a 4x k_16_16_16_16 surface (64 bpp): per-sample values through parityWriteRgba16Hdr,
// the k0123 resolve into the signed destination (average, re-encode), and the EDRAM image in
// the 64-bpp layout (40x16 samples per tile, two dwords per sample).
TEST_P(X360MsaaGpuTest, K16x4Msaa4xResolveAndEdramMatchTheModel) {
  const uint32_t w = 8, h = 8;
  for (K16UnpackClamp clamp : {K16UnpackClamp::Minus32, K16UnpackClamp::Minus1}) {
    PlatformParams params;
    params.k16UnpackClamp = clamp;
    SCOPED_TRACE("unpack clamp " + std::to_string(int(clamp)));
    LogicalTarget t{"light", LogicalFormat::Rgba16Hdr, true, TargetRole::LBuffer, "lights", 4};
    TargetPlan plan = planTargets(platform, {&t, 1}, w, h, params);
    const PhysicalTarget& pt = plan.targets[0];
    x360::EdramSurface surface = modelSurface(pt, plan);
    ASSERT_TRUE(surface.is64bpp());
    EXPECT_EQ(pt.edramTiles, surface.sizeTiles());
    EXPECT_EQ(pt.edramTiles, 2u);  // 16x16 samples: one row of 40-sample tiles, doubled for 64 bpp
    std::vector<float> perSample(size_t(w) * h * 4 * 4);
    x360::EdramMemory edram;
    for (uint32_t y = 0; y < h; ++y) {
      for (uint32_t x = 0; x < w; ++x) {
        for (uint32_t s = 0; s < 4; ++s) {
          const uint32_t i = (y * w + x) * 4 + s;
          int16_t words[4];
          for (uint32_t ch = 0; ch < 4; ++ch) {
            float v = float(int32_t((i * 4 + ch) * 7919u % 80001u) - 40000) / 1000.0f;  // [-40, 40]: clamps too
            if (x == 0 && y == 0) v = (s % 2 == 0) ? 2.000061f : -2.000061f;            // X3 averaging vector
            perSample[(size_t(y) * w * 4 + x * 4 + s) * 4 + ch] = v;
            words[ch] = x360::encodeFixed16(v, 0).value;
          }
          edram.writeSample(surface, x, y, s, x360::packFixed16x4(words[0], words[1], words[2], words[3]), params);
        }
      }
    }
    GpuTargets gpu(*dev, plan);
    writeSamples(gpu, "light", kWriteHdrPerSampleFs, rhi::Format::RGBA32F, perSample);
    ASSERT_TRUE(gpu.resolve("light")) << gpu.error();
    const std::vector<uint8_t> resolved = gpu.consoleBytes("light", true);
    const std::vector<uint8_t> gpuEdram = gpu.edramBytes("light");

    x360::ResolveRequest request;
    request.rect = {0, 0, w, h};
    request.destFormat = x360::ColorFormat::k_16_16_16_16;
    request.destNumber = x360::SurfaceNumberFormat::kSignedRepeatingFraction;
    request.sampleSelect = x360::CopySampleSelect::k0123;
    DiagnosticList diagnostics;
    const x360::ResolvedTexture model = x360::resolveSurface(edram, surface, request, diagnostics, params);
    ASSERT_EQ(resolved.size(), size_t(w) * h * 8);
    ASSERT_EQ(model.texels.size(), size_t(w) * h);
    int mismatches = 0;
    for (size_t i = 0; i < model.texels.size(); ++i) {
      uint64_t got = 0;
      for (int b = 0; b < 8; ++b) got |= uint64_t(resolved[i * 8 + b]) << (8 * b);
      if (got != model.texels[i] && mismatches++ < 5)
        ADD_FAILURE() << "pixel " << i << ": GPU 0x" << std::hex << got << ", model 0x" << model.texels[i];
    }
    EXPECT_EQ(mismatches, 0);
    // Pixel 0, R: +-2.000061 average to 0 (-32 clamp); mainline's -1 clamp gives 0.50003 -> 512.
    const int16_t r0 = int16_t(resolved[0] | resolved[1] << 8);
    EXPECT_EQ(r0, clamp == K16UnpackClamp::Minus32 ? 0 : x360::encodeFixed16(0.50003052f, 0).value);
    const std::vector<uint8_t> modelEdram = modelEdramSpan(edram, surface);
    ASSERT_EQ(gpuEdram.size(), size_t(pt.edramTiles) * x360::kEdramTileSizeBytes);
    EXPECT_EQ(firstDifference(gpuEdram, modelEdram), gpuEdram.size()) << "first differing EDRAM byte";
  }
}

// X3 on 4x k_8_8_8_8 surfaces: the averaging resolve (k0123: the bytes averaged, ties rounded up
// as the model's float path and Xenia's pack do) of a colour a later pass reads as one image,
// and the four point resolves (k0..k3) of one read sample by sample (LogicalTarget::readSamples)
// into the layers of its array, against the model; a 4x k_32_FLOAT read per sample keeps every
// sample's float bit for bit.
TEST_P(X360MsaaGpuTest, K8AndK32Msaa4xResolvesMatchTheModel) {
  const uint32_t w = 8, h = 4;
  std::vector<LogicalTarget> targets = {{"averaged", LogicalFormat::Rgba8Unorm, true, TargetRole::Plain, "draw", 4},
                                        {"each", LogicalFormat::Rgba8Unorm, true, TargetRole::Plain, "draw", 4},
                                        {"floats", LogicalFormat::R32Float, true, TargetRole::Plain, "draw", 4}};
  targets[1].readSamples = targets[2].readSamples = true;
  // The frame's colour asked for in float: its average stays float (the console's 8-bit display
  // surface is what the harness reads only when it asks for 8 bits).
  LogicalTarget output{"output", LogicalFormat::Output, true, TargetRole::Plain, "draw", 4};
  output.outputFormat = rhi::Format::RGBA32F;
  targets.push_back(output);
  TargetPlan plan = planTargets(platform, targets, w, h);
  std::vector<float> perSample(size_t(w) * h * 4 * 4), floats(size_t(w) * h * 4 * 4, 0.0f);
  x360::EdramSurface surface = modelSurface(*plan.find("averaged"), plan);
  surface.colorFormat = x360::ColorRenderTargetFormat::k_8_8_8_8;
  surface.baseTile = 0;
  x360::EdramMemory edram;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x)
      for (uint32_t s = 0; s < 4; ++s) {
        uint64_t word = 0;
        for (uint32_t ch = 0; ch < 4; ++ch) {
          // Bytes whose sums hit every remainder mod 4, ties (remainder 2) among them.
          const uint32_t byte = (((y * w + x) * 16 + s * 4 + ch) * 2654435761u >> 13) & 255u;
          perSample[((size_t(y) * w + x) * 4 + s) * 4 + ch] = float(byte) / 255.0f;
          word |= uint64_t(byte) << (8 * ch);
        }
        floats[((size_t(y) * w + x) * 4 + s) * 4] = 1.0f / 3.0f + float(s) + float(y * w + x) * 0.001f;
        edram.writeSample(surface, x, y, s, word);
      }
  GpuTargets gpu(*dev, plan);
  writeSamples(gpu, "averaged", kWriteColorPerSampleFs, rhi::Format::RGBA32F, perSample);
  writeSamples(gpu, "each", kWriteColorPerSampleFs, rhi::Format::RGBA32F, perSample);
  writeSamples(gpu, "floats", kWriteColorPerSampleFs, rhi::Format::RGBA32F, floats);
  std::vector<float> outputs(floats.size());
  for (size_t i = 0; i < outputs.size(); ++i) outputs[i] = float(i % 1000) / 3000.0f;  // not bytes
  writeSamples(gpu, "output", kWriteColorPerSampleFs, rhi::Format::RGBA32F, outputs);
  for (const char* name : {"averaged", "each", "floats", "output"}) ASSERT_TRUE(gpu.resolve(name)) << gpu.error();
  dev->submit();

  auto modelResolve = [&](x360::CopySampleSelect select) {
    x360::ResolveRequest request;
    request.rect = {0, 0, w, h};
    request.sampleSelect = select;
    DiagnosticList diagnostics;
    std::vector<uint8_t> bytes;
    for (uint64_t texel : x360::resolveSurface(edram, surface, request, diagnostics).texels)
      for (int b = 0; b < 4; ++b) bytes.push_back(uint8_t(texel >> (8 * b)));
    return bytes;
  };
  std::vector<uint8_t> sums(size_t(w) * h * 4);
  for (size_t i = 0; i < sums.size(); ++i)
    for (uint32_t s = 0; s < 4; ++s) sums[i] += uint8_t(std::lround(perSample[(i / 4 * 4 + s) * 4 + i % 4] * 255.0f) & 3);
  EXPECT_GT(std::count_if(sums.begin(), sums.end(), [](uint8_t r) { return r % 4 == 2; }), 0) << "no tie to round";
  EXPECT_EQ(dev->readTexture(gpu.readTexture("averaged")), modelResolve(x360::CopySampleSelect::k0123));
  const std::vector<float> averaged = asFloats(dev->readTexture(gpu.readTexture("output")));
  ASSERT_EQ(averaged.size(), size_t(w) * h * 4);
  for (size_t i = 0; i < averaged.size(); ++i) {
    const size_t p = i / 4, c = i % 4;
    auto at = [&](uint32_t guest) { return outputs[(p * 4 + guest) * 4 + c]; };
    const float want = (((at(0) + at(1)) + at(2)) + at(3)) * 0.25f;
    EXPECT_EQ(averaged[i], want) << "texel " << p << " channel " << c;
    if (averaged[i] != want) break;
  }
  const x360::CopySampleSelect single[4] = {x360::CopySampleSelect::k0, x360::CopySampleSelect::k1,
                                            x360::CopySampleSelect::k2, x360::CopySampleSelect::k3};
  for (uint32_t s = 0; s < 4; ++s) {
    SCOPED_TRACE("sample " + std::to_string(s));
    rhi::ReadbackRegion layer;
    layer.layer = s;
    EXPECT_EQ(dev->readTexture(gpu.readTexture("each"), layer), modelResolve(single[s]));
    std::vector<uint8_t> got = dev->readTexture(gpu.readTexture("floats"), layer);
    ASSERT_EQ(got.size(), size_t(w) * h * 4);
    for (size_t p = 0; p < size_t(w) * h; ++p) {
      float v;
      std::memcpy(&v, got.data() + p * 4, 4);
      EXPECT_EQ(v, floats[(p * 4 + s) * 4]) << "pixel " << p;
    }
  }
}

// X2 under x360.hdr_format = k_2_10_10_10_float: values written as floats, rounded to 7e3 after
// the pass (GpuTargets::quantiseFloat7e3), an additive blend onto them rounded again, the bit
// copy resolve: every stored word is the CPU model's, the ties and the denormals included; the
// surface takes 32 bpp of EDRAM, half of k_16_16_16_16.
TEST_P(X360GpuTest, Float7e3WritesBlendsAndResolvesMatchTheModel) {
  const uint32_t w = 16, h = 8;
  PlatformParams params;
  params.hdrFormat = X360HdrFormat::Float7e3;
  LogicalTarget t{"light", LogicalFormat::Rgba16Hdr, true, TargetRole::LBuffer, "lights"};
  TargetPlan plan = planTargets(platform, {&t, 1}, w, h, params);
  const PhysicalTarget& pt = plan.targets[0];
  EXPECT_EQ(pt.mapping.consoleBytesPerPixel, 4u);
  EXPECT_EQ(pt.edramTiles, planTargets(platform, {&t, 1}, w, h).targets[0].edramTiles / 2);
  // Values: every 7e3 code and the midpoint above it (ties to even), below zero, beyond 31.875.
  std::vector<float> first(size_t(w) * h * 4), second(first.size());
  for (size_t i = 0; i < first.size(); ++i) {
    const uint32_t code = uint32_t(i / 2) % 1024u;
    const float lo = x360::decodeFloat7e3(code), hi = code < 1023 ? x360::decodeFloat7e3(code + 1) : 40.0f;
    first[i] = i % 2 == 0 ? lo : (lo + hi) * 0.5f;
    if (i % 97 == 0) first[i] = -1.5f;
    second[i] = float(i % 13) * 0.0625f;
  }
  for (size_t i = 3; i < first.size(); i += 4) first[i] = float(i % 7) / 6.0f;  // alpha: 2 bits
  GpuTargets gpu(*dev, plan);
  rhi::TextureHandle a = source(rhi::Format::RGBA32F, w, h, first.data());
  rhi::TextureHandle b = source(rhi::Format::RGBA32F, w, h, second.data());
  rhi::BlendState add;
  add.enabled = true;
  add.srcColor = add.dstColor = add.srcAlpha = add.dstAlpha = rhi::BlendFactor::One;
  const std::string fs = R"(#version 450
#include "platform.glsl"
layout(binding = 0) uniform sampler2D uSource;
layout(location = 0) out vec4 o;
void main() { o = parityWriteRgba16Hdr(texelFetch(uSource, ivec2(gl_FragCoord.xy), 0)); })";
  pass(gpu.attachment("light"), {}, fullscreen(fs, plan, pt.attachmentFormat, rhi::Format::Undefined), a);
  gpu.quantiseFloat7e3("light");
  dev->submit();
  std::vector<uint8_t> written = gpu.consoleBytes("light", false);
  const std::vector<float> storedFloats = asFloats(dev->readTexture(gpu.attachment("light")));
  pass(gpu.attachment("light"), {}, fullscreen(fs, plan, pt.attachmentFormat, rhi::Format::Undefined, add), b, true);
  gpu.quantiseFloat7e3("light");
  ASSERT_TRUE(gpu.resolve("light")) << gpu.error();
  dev->submit();
  std::vector<uint8_t> resolved = gpu.consoleBytes("light", true);
  ASSERT_EQ(written.size(), size_t(w) * h * 4);
  ASSERT_EQ(resolved.size(), written.size());
  int mismatches = 0;
  for (size_t p = 0; p < size_t(w) * h; ++p) {
    std::array<float, 4> v{}, blended{};
    for (int c = 0; c < 4; ++c) v[c] = first[p * 4 + c];
    const uint32_t want = x360::packFloat7e3x3Unorm2(v);
    const std::array<float, 4> stored = x360::unpackFloat7e3x3Unorm2(want);
    for (int c = 0; c < 4; ++c)  // the surface holds the 7e3 values themselves, not the written floats
      if (storedFloats[p * 4 + c] != stored[c] && mismatches++ < 5)
        ADD_FAILURE() << "pixel " << p << " channel " << c << ": stored " << storedFloats[p * 4 + c] << ", model "
                      << stored[c];
    for (int c = 0; c < 4; ++c) blended[c] = stored[c] + second[p * 4 + c];
    const uint32_t wantBlended = x360::packFloat7e3x3Unorm2(blended);
    uint32_t got = 0, gotBlended = 0;
    for (int k = 0; k < 4; ++k) {
      got |= uint32_t(written[p * 4 + k]) << (8 * k);
      gotBlended |= uint32_t(resolved[p * 4 + k]) << (8 * k);
    }
    if ((got != want || gotBlended != wantBlended) && mismatches++ < 5)
      ADD_FAILURE() << "pixel " << p << ": written 0x" << std::hex << got << " (model 0x" << want << "), blended 0x"
                    << gotBlended << " (model 0x" << wantBlended << ")";
  }
  EXPECT_EQ(mismatches, 0);
  dev->destroy(a);
  dev->destroy(b);
}

// X1/X2 64 bpp, single-sampled, with the pack's address vectors: a 1280-pixel pitch is 32 tiles;
// pixel (1, 0) starts at byte 8 and pixel (40, 0) at byte 5120 (tile 1); each sample is R, G in
// the low dword and B, A in the high one, int16 little-endian. The whole image matches the model.
TEST_P(X360GpuTest, Edram64bppBytesMatchTheModel) {
  const uint32_t w = 1280, h = 16;
  LogicalTarget t{"light", LogicalFormat::Rgba16Hdr, true, TargetRole::LBuffer, "lights"};
  PlatformParams params;
  EXPECT_EQ(params.edram64bppTileLayout, Edram64bppTileLayout::Xenia40x16);  // the pack's default
  TargetPlan plan = planTargets(platform, {&t, 1}, w, h, params);
  const PhysicalTarget& pt = plan.targets[0];
  x360::EdramSurface surface = modelSurface(pt, plan);
  EXPECT_EQ(surface.pitchTiles(), 32u);
  EXPECT_EQ(pt.edramTiles, 32u);
  std::vector<float> values(size_t(w) * h * 4);
  x360::EdramMemory edram;
  for (uint32_t y = 0; y < h; ++y) {
    for (uint32_t x = 0; x < w; ++x) {
      int16_t words[4];
      for (uint32_t ch = 0; ch < 4; ++ch) {
        const int16_t s = int16_t(int32_t(((y * w + x) * 4 + ch) * 2654435761u % 65535u) - 32767);
        values[(size_t(y) * w + x) * 4 + ch] = x360::decodeFixed16(s);
        words[ch] = x360::encodeFixed16(values[(size_t(y) * w + x) * 4 + ch], 0).value;
        ASSERT_EQ(words[ch], s);
      }
      if (x == 0 && y == 0) {
        const float v[4] = {1.0f, -1.0f, 32.0f, -32.0f};
        for (uint32_t ch = 0; ch < 4; ++ch) {
          values[ch] = v[ch];
          words[ch] = x360::encodeFixed16(v[ch], 0).value;
        }
      }
      edram.writeSample(surface, x, y, 0, x360::packFixed16x4(words[0], words[1], words[2], words[3]), params);
    }
  }
  GpuTargets gpu(*dev, plan);
  rhi::TextureHandle src = source(rhi::Format::RGBA32F, w, h, values.data());
  pass(gpu.attachment("light"), {}, fullscreen(kWriteHdrFs, plan, pt.attachmentFormat, rhi::Format::Undefined), src);
  const std::vector<uint8_t> gpuEdram = gpu.edramBytes("light");
  const std::vector<uint8_t> linear = gpu.consoleBytes("light");
  ASSERT_EQ(gpuEdram.size(), size_t(32) * x360::kEdramTileSizeBytes);
  EXPECT_EQ(firstDifference(gpuEdram, modelEdramSpan(edram, surface)), gpuEdram.size()) << "first differing byte";
  // Pixel (0, 0) = (+1, -1, +32, -32) -> 0x0400, 0xFC00, 0x7FFF, 0x8001.
  EXPECT_EQ(std::vector<uint8_t>(gpuEdram.begin(), gpuEdram.begin() + 8),
            (std::vector<uint8_t>{0x00, 0x04, 0x00, 0xFC, 0xFF, 0x7F, 0x01, 0x80}));
  EXPECT_EQ(x360::edramByteOffset(surface, 1, 0, 0, params), 8u);
  EXPECT_EQ(x360::edramByteOffset(surface, 40, 0, 0, params), 5120u);
  // The linear export and the EDRAM image hold the same 8 bytes for pixels (1, 0) and (40, 0).
  ASSERT_EQ(linear.size(), size_t(w) * h * 8);
  for (uint32_t x : {1u, 40u}) {
    const size_t at = x == 1 ? 8 : 5120;
    EXPECT_EQ(std::vector<uint8_t>(gpuEdram.begin() + at, gpuEdram.begin() + at + 8),
              std::vector<uint8_t>(linear.begin() + x * 8, linear.begin() + x * 8 + 8))
        << "pixel (" << x << ", 0)";
  }
  dev->destroy(src);
}

// X1 depth tiles: the D24S8 surface as it lies in EDRAM, each sample the stored word
// (D24 << 8) | stencil, with the two 40-column halves of every tile swapped relative to colour.
// The pack's vectors at a 160-pixel pitch (2 tiles): pixel (0, 0) at byte 160, (40, 0) at byte 0,
// (80, 0) at 5120 + 160; the whole image matches the CPU model (EdramMemory with isDepth).
TEST_P(X360GpuTest, EdramDepthBytesMatchTheModel) {
  const uint32_t w = 160, h = 20;  // two tiles wide, two tile rows (the second partly padding)
  LogicalTarget t{"depth", LogicalFormat::Depth24Stencil8, true, TargetRole::GBuffer, "geometry"};
  TargetPlan plan = planTargets(platform, {&t, 1}, w, h, {});
  const PhysicalTarget& pt = plan.targets[0];
  x360::EdramSurface surface = modelSurface(pt, plan);
  ASSERT_TRUE(surface.isDepth);
  EXPECT_EQ(pt.edramTiles, 4u);
  std::vector<uint32_t> words(size_t(w) * h);
  x360::EdramMemory edram;
  for (uint32_t y = 0; y < h; ++y) {
    for (uint32_t x = 0; x < w; ++x) {
      const uint32_t i = y * w + x;
      // D24 below 2^20: the sampled D24 / 16777215 converts back exactly on every driver (the
      // layout is under test here, not the depth read; DepthVectorsMatchTheModel covers that).
      const uint32_t d24 = i * 311u + 7u, stencil = (i * 40503u >> 3) & 255u;
      words[i] = d24 << 8 | stencil;
      edram.writeSample(surface, x, y, 0, words[i]);
    }
  }
  GpuTargets gpu(*dev, plan);
  dev->writeTexture(gpu.attachment("depth"), 0, 0, words.data());
  const std::vector<uint8_t> gpuEdram = gpu.edramBytes("depth");
  ASSERT_EQ(gpuEdram.size(), size_t(4) * x360::kEdramTileSizeBytes);
  EXPECT_EQ(firstDifference(gpuEdram, modelEdramSpan(edram, surface)), gpuEdram.size()) << "first differing byte";
  auto dwordAt = [&](size_t byte) {
    return uint32_t(gpuEdram[byte] | gpuEdram[byte + 1] << 8 | gpuEdram[byte + 2] << 16 | uint32_t(gpuEdram[byte + 3]) << 24);
  };
  EXPECT_EQ(x360::edramByteOffset(surface, 0, 0, 0), 160u);
  EXPECT_EQ(x360::edramByteOffset(surface, 40, 0, 0), 0u);
  EXPECT_EQ(dwordAt(160), words[0]) << "pixel (0, 0) in the second half of tile 0";
  EXPECT_EQ(dwordAt(0), words[40]) << "pixel (40, 0) in the first half";
  EXPECT_EQ(dwordAt(5120 + 160), words[80]) << "pixel (80, 0) in tile 1";
}

float modelDepth(PlatformId p, float d) {
  switch (p) {
    case PlatformId::Reference: return d;
    case PlatformId::Dx10:
    case PlatformId::X360: return dx10::decodeR24X8(dx10::quantizeD24(d));
    case PlatformId::Ps3: return ps3::texDepth2DPrecise(ps3::sampleDepthAsArgb8(dx10::quantizeD24(d), 0));
  }
  return d;
}

float modelDepthFromD24(PlatformId p, uint32_t d24) {
  if (p == PlatformId::Ps3) return ps3::texDepth2DPrecise(ps3::sampleDepthAsArgb8(d24, 0));
  return dx10::decodeR24X8(d24);
}

uint32_t storedWordOf(PlatformId p, const std::vector<uint8_t>& stored, size_t i) {
  return p == PlatformId::Ps3
             ? uint32_t(stored[i * 4] << 24 | stored[i * 4 + 1] << 16 | stored[i * 4 + 2] << 8 | stored[i * 4 + 3])
             : uint32_t(stored[i * 4] | stored[i * 4 + 1] << 8 | stored[i * 4 + 2] << 16 | stored[i * 4 + 3] << 24);
}

// P4 / D1 vectors: D24 = 0xABCDEF, 0x000001, 0xFFFFFF, 0.
TEST_P(PlatformGpuTest, DepthVectorsMatchTheModel) {
  const std::vector<float> d = {float(0xABCDEF / 16777215.0), float(1 / 16777215.0), 1.0f, 0.0f, 0.5f, 0.25f};
  std::vector<uint8_t> stored;
  std::vector<float> got = roundTripDepth(d, uint32_t(d.size()), 1, &stored);
  ASSERT_EQ(got.size(), d.size());
  for (size_t i = 0; i < d.size(); ++i) {
    EXPECT_LE(ulpDistance(got[i], modelDepth(platform, d[i])), 1)
        << "d = " << d[i] << ": got " << got[i] << ", model " << modelDepth(platform, d[i]);
    if (platform != PlatformId::Reference) {
      uint32_t word = storedWordOf(platform, stored, i);
      EXPECT_EQ(word >> 8, dx10::quantizeD24(d[i])) << "stored D24 for d = " << d[i];
    }
  }
  if (platform == PlatformId::Ps3) {
    EXPECT_LE(ulpDistance(got[0], 0.67111108727f), 1) << "0xABCDEF via BARG + texDepth2D_precise";
  }
}

// A gradient through every platform: every pixel matches the model, and the effective precision
// measured as log2(distinct values read back) matches the model's (A = 10, B = 15, C = 16 bits).
TEST_P(PlatformGpuTest, GradientPrecisionMatchesTheModel) {
  const uint32_t w = 256, h = 256;
  std::vector<DsfResolvePath> paths = {DsfResolvePath::PaperSignedC};
  if (platform == PlatformId::X360) paths = {DsfResolvePath::NaiveA, DsfResolvePath::XdkBiasB, DsfResolvePath::PaperSignedC};
  for (DsfResolvePath path : paths) {
    PlatformParams params;
    params.dsfResolvePath = path;
    std::vector<float> xy(size_t(w) * h * 2);
    for (uint32_t i = 0; i < w * h; ++i) {
      xy[i * 2] = float(i) / 65535.0f;
      xy[i * 2 + 1] = 1.0f - float(i) / 65535.0f;
    }
    std::vector<float> got = roundTripRg16(xy, w, h, params);
    ASSERT_EQ(got.size(), xy.size());
    std::set<float> distinct;
    int mismatches = 0;
    for (size_t i = 0; i < xy.size(); ++i) {
      if (i % 2 == 0) distinct.insert(got[i]);
      float m = modelRg16(platform, xy[i], params).value;
      if (!rg16Close(got[i], m) && mismatches++ < 5) ADD_FAILURE() << "v = " << xy[i] << ": " << got[i] << " vs " << m;
    }
    EXPECT_EQ(mismatches, 0);
    double bits = std::log2(double(distinct.size()));
    double expected = rg16EffectiveBits(platform, params);
    if (platform == PlatformId::Reference)
      EXPECT_EQ(distinct.size(), size_t(w) * h);  // every value survives (fp32)
    else
      EXPECT_NEAR(bits, expected, 0.05) << "path " << int(path) << ": " << distinct.size() << " levels";
    RecordProperty("bits_" + std::to_string(int(path)), std::to_string(bits));
  }
}

// A depth ramp with steps of 2^-28 from 0.125: D24 platforms resolve 2^24 levels per unit
// (4096 levels over the 2^-12 span), fp32 depth (reference) 2^26.
TEST_P(PlatformGpuTest, DepthRampPrecisionMatchesTheModel) {
  const uint32_t w = 256, h = 256;
  std::vector<float> d(size_t(w) * h);
  for (uint32_t i = 0; i < w * h; ++i) d[i] = 0.125f + float(i) * std::ldexp(1.0f, -28);
  std::vector<uint8_t> stored;
  std::vector<float> got = roundTripDepth(d, w, h, &stored);
  ASSERT_EQ(got.size(), d.size());
  ASSERT_EQ(stored.size(), d.size() * 4);
  std::set<float> distinct(got.begin(), got.end());
  int mismatches = 0, notNearest = 0;
  for (size_t i = 0; i < d.size(); ++i) {
    float model = modelDepth(platform, d[i]);
    if (platform != PlatformId::Reference) {
      // The rasteriser's float -> D24 conversion is the driver's (GL and Vulkan allow either
      // neighbour); from the stored word on, the platform path must follow the model exactly.
      uint32_t word = storedWordOf(platform, stored, i);
      uint32_t d24 = word >> 8;
      int64_t delta = int64_t(d24) - int64_t(dx10::quantizeD24(d[i]));
      if (delta != 0) ++notNearest;
      EXPECT_LE(std::abs(delta), 1) << "d = " << d[i];
      model = modelDepthFromD24(platform, d24);
    }
    if (ulpDistance(got[i], model) > 1 && mismatches++ < 5)
      ADD_FAILURE() << "d = " << d[i] << ": " << got[i] << " vs " << model;
  }
  EXPECT_EQ(mismatches, 0);
  RecordProperty("d24_not_round_to_nearest", notNearest);
  const double span = double(w) * h * std::ldexp(1.0, -28);
  const double bits = std::log2(double(distinct.size()) / span);
  if (platform == PlatformId::Reference)
    EXPECT_NEAR(bits, 26.0, 0.05);
  else
    EXPECT_NEAR(bits, depthEffectiveBits(platform), 0.05) << distinct.size() << " levels";
}


// The blendable float path (parityWriteRg16 into the attachment) stores the same words as the
// exact path: the quarter-step offset leaves no tie for the driver's conversion to decide.
TEST_P(ConsoleGpuTest, BlendablePathStoresTheModelWords) {
  const std::vector<float> xy = {0.001f, 0.5f, 0.123456f, 0.987654f, 1.0f, 0.0f, 0.25f, 0.75f};
  const uint32_t w = uint32_t(xy.size() / 2);
  LogicalTarget t{"dsf", LogicalFormat::Rg16Unorm, true, TargetRole::GBuffer, "geometry"};
  TargetPlan plan = planTargets(platform, {&t, 1}, w, 1, {});
  rhi::TextureHandle src = source(rhi::Format::RG32F, w, 1, xy.data());
  GpuTargets exact(*dev, plan), blendable(*dev, plan);
  const PhysicalTarget& pt = plan.targets[0];
  pass(exact.writeTarget("dsf"), {}, fullscreen(kWriteRg16BitsFs, plan, pt.writeFormat, rhi::Format::Undefined), src);
  pass(blendable.attachment("dsf"), {}, fullscreen(kWriteRg16Fs, plan, pt.attachmentFormat, rhi::Format::Undefined),
       src);
  EXPECT_EQ(blendable.consoleBytes("dsf"), exact.consoleBytes("dsf"));
  if (platform == PlatformId::Dx10) {
    std::vector<uint8_t> b = blendable.consoleBytes("dsf");
    ASSERT_EQ(b.size(), 16u);
    EXPECT_EQ(b[0] | b[1] << 8, 66) << "0.001 -> round(65.535) = 66";
    EXPECT_EQ(b[2] | b[3] << 8, 32768) << "0.5 -> round(32767.5) = 32768";
  }
  dev->destroy(src);
}

// X2 on the Rgba16Hdr path: k_16_16_16_16 encode vectors, an additive blend (ONE, ONE) of a second
// write onto them, the resolve and the signed fetch, against the EDRAM blender model
// encode(src + decode(dst)). Words bit-exact; values read 1 ULP (a shader division by 32767).
// The shaders write the rounded steps unclamped; the clamp (and NaN -> 0) is the store pass after
// each pass (GpuTargets::clampFixedPoint), which a PlatformDevice records by itself.
TEST_P(X360GpuTest, Rgba16HdrFixedPointAndAdditiveBlend) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<float> first = {0.0f, 1.0f, 0.123456f, 31.99f, 40.0f, -1.0f, nan, 0.5f * 32.0f / 32767.0f,
                                    20.0f, 2.5f, 0.001f, 7.25f};
  const std::vector<float> second = {0.25f, 1.0f, 0.5f, 0.5f, 1.0f, 3.0f, 1.0f, 0.0f, 20.0f, -1.5f, 0.001f, 0.01f};
  const uint32_t w = uint32_t(first.size() / 4);
  LogicalTarget t{"light", LogicalFormat::Rgba16Hdr, true, TargetRole::LBuffer, "lights"};
  TargetPlan plan = planTargets(platform, {&t, 1}, w, 1, {});
  const PhysicalTarget& pt = plan.targets[0];
  EXPECT_EQ(pt.mapping.consoleBytesPerPixel, 8u);
  EXPECT_EQ(pt.resolve.effectiveBits, 15);
  GpuTargets gpu(*dev, plan);
  rhi::TextureHandle a = source(rhi::Format::RGBA32F, w, 1, first.data());
  rhi::TextureHandle b = source(rhi::Format::RGBA32F, w, 1, second.data());
  rhi::BlendState add;
  add.enabled = true;
  add.srcColor = add.dstColor = add.srcAlpha = add.dstAlpha = rhi::BlendFactor::One;
  pass(gpu.attachment("light"), {}, fullscreen(kWriteHdrFs, plan, pt.attachmentFormat, rhi::Format::Undefined), a);
  gpu.clampFixedPoint("light");
  std::vector<uint8_t> once = gpu.consoleBytes("light");
  pass(gpu.attachment("light"), {}, fullscreen(kWriteHdrFs, plan, pt.attachmentFormat, rhi::Format::Undefined, add), b,
       true);
  gpu.clampFixedPoint("light");
  std::vector<uint8_t> edram = gpu.consoleBytes("light");
  ASSERT_TRUE(gpu.resolve("light")) << gpu.error();
  std::vector<uint8_t> resolved = gpu.consoleBytes("light", true);
  rhi::TextureHandle out = target(rhi::Format::RGBA32F, w, 1);
  pass(out, {}, fullscreen(kReadHdrFs, plan, rhi::Format::RGBA32F, rhi::Format::Undefined), gpu.readTexture("light"));
  std::vector<float> got = asFloats(dev->readTexture(out));
  ASSERT_EQ(once.size(), first.size() * 2);
  ASSERT_EQ(edram.size(), first.size() * 2);
  ASSERT_EQ(got.size(), first.size());
  auto word = [](const std::vector<uint8_t>& bytes, size_t i) { return uint16_t(bytes[i * 2] | bytes[i * 2 + 1] << 8); };
  for (size_t i = 0; i < first.size(); ++i) {
    const int16_t s1 = x360::encodeFixed16(first[i], 0).value;
    const int16_t blended = x360::encodeFixed16(second[i] + x360::decodeFixed16(s1), 0).value;
    EXPECT_EQ(word(once, i), uint16_t(s1)) << "write of " << first[i];
    EXPECT_EQ(word(edram, i), uint16_t(blended)) << first[i] << " + " << second[i];
    EXPECT_EQ(word(resolved, i), uint16_t(blended)) << "resolve keeps the raw int16";
    const float model = x360::fetchFixed16Signed(uint16_t(blended), 5);
    EXPECT_LE(ulpDistance(got[i], model), 1) << first[i] << " + " << second[i] << ": " << got[i] << " vs " << model;
  }
  EXPECT_EQ(word(once, 1), 0x0400);   // +1
  EXPECT_EQ(word(once, 4), 0x7FFF);   // 40 clamps to +32
  EXPECT_EQ(word(once, 6), 0x0000);   // NaN -> 0
  EXPECT_EQ(word(once, 7), 0x0001);   // half a step rounds away from zero
  EXPECT_EQ(word(edram, 8), 0x7FFF);  // 20 + 20 clamps to +32
  dev->destroy(out);
  dev->destroy(a);
  dev->destroy(b);
}

// X2: the blender clamps after every blend, not once at resolve. Three additive passes through
// a PlatformDevice (as a technique draws): 20 + 20 stores +32 (0x7FFF), and a further -20 then
// stores 12 (0x3000), not 20; likewise negated, and 40 (clamped by the encode) - 20 = 12. Every
// word matches the CPU model's blend (x360::blendAddFixed16) and the resolve keeps it.
TEST_P(X360GpuTest, Rgba16HdrClampsAfterEveryBlend) {
  const std::vector<std::vector<float>> draws = {{20.0f, -20.0f, 40.0f, 1.0f, 31.0f, 0.5f, -40.0f, 0.0f},
                                                 {20.0f, -20.0f, -20.0f, 1.0f, 31.0f, 0.5f, 20.0f, 0.0f},
                                                 {-20.0f, 20.0f, 0.0f, 1.0f, -31.0f, 0.5f, 0.0f, 0.0f}};
  const uint32_t w = 2;
  LogicalTarget t{"light", LogicalFormat::Rgba16Hdr, true, TargetRole::LBuffer, "lights"};
  TargetPlan plan = planTargets(platform, {&t, 1}, w, 1, {});
  const PhysicalTarget& pt = plan.targets[0];
  PlatformDevice device(*dev, platform, {});
  GpuTargets gpu(device, plan);
  rhi::BlendState add;
  add.enabled = true;
  add.srcColor = add.dstColor = add.srcAlpha = add.dstAlpha = rhi::BlendFactor::One;
  rhi::PipelineDesc pd;
  pd.vertexShader = shader(rhi::ShaderStage::Vertex, kFullscreenVs, plan);
  pd.fragmentShader = shader(rhi::ShaderStage::Fragment, kWriteHdrFs, plan);
  pd.colorTargets[0].format = pt.attachmentFormat;
  pd.colorTargets[0].blend = add;
  pd.colorTargetCount = 1;
  rhi::PipelineHandle p = device.createPipeline(pd);
  std::vector<int16_t> model(draws[0].size(), 0);
  for (size_t d = 0; d < draws.size(); ++d) {
    rhi::TextureHandle src = source(rhi::Format::RGBA32F, w, 1, draws[d].data());
    rhi::PassDesc pass;
    pass.colors[0].texture = gpu.attachment("light");
    pass.colors[0].load = d == 0 ? rhi::LoadOp::Clear : rhi::LoadOp::Load;
    pass.colors[0].clearColor = gpu.clearColor("light", {0, 0, 0, 0});
    device.beginPass(pass);
    device.setPipeline(p);
    rhi::ResourceBinding b;
    b.binding = 0;
    b.kind = rhi::BindingKind::SampledTexture;
    b.texture = src;
    device.setBindings({&b, 1});
    device.draw(3);
    device.endPass();
    device.destroy(src);
    for (size_t i = 0; i < model.size(); ++i) model[i] = x360::blendAddFixed16(model[i], draws[d][i]).value;
  }
  std::vector<uint8_t> edram = gpu.consoleBytes("light");
  ASSERT_TRUE(gpu.resolve("light")) << gpu.error();
  std::vector<uint8_t> resolved = gpu.consoleBytes("light", true);
  ASSERT_EQ(edram.size(), model.size() * 2);
  ASSERT_EQ(resolved.size(), model.size() * 2);
  auto word = [](const std::vector<uint8_t>& bytes, size_t i) { return int16_t(bytes[i * 2] | bytes[i * 2 + 1] << 8); };
  for (size_t i = 0; i < model.size(); ++i) {
    EXPECT_EQ(word(edram, i), model[i]) << "channel " << i;
    EXPECT_EQ(word(resolved, i), model[i]) << "resolved channel " << i;
  }
  EXPECT_EQ(model[0], 0x3000);   // 20 + 20 -> +32 (clamped), - 20 -> 12288 = 12.0004
  EXPECT_EQ(model[1], -0x3000);  // the same negated
  EXPECT_EQ(model[2], 0x3000);   // 40 (clamped by the encode) - 20
  EXPECT_EQ(model[3], 3072);     // in range: no clamp, 1 + 1 + 1
  device.destroy(p);
}

// Console colour-mask bits (A, R, G, B) as host channels of the packed RGBA8 storage, whose bytes
// are [lo X, hi X, lo Y, hi Y] = console [R, A, B, G].
uint8_t hostMaskOf(uint8_t consoleMask) { return ps3::hostWriteMaskOfConsole(consoleMask); }

// P3: blending a packed16x2 target blends the high and low bytes independently. The GPU stores
// exactly the model's wrong answer and E_PACKED_BLEND fires; identical values survive any blend
// (the pack's sanity vector), and without blending nothing is reported.
// A colour surface (8-bit colour, the frame's output, LIDR's light index) is A8R8G8B8: the
// shader's (r, g, b, a) lie in memory as [A, R, G, B].
TEST_P(Ps3GpuTest, EightBitColourSurfacesAreArgbInMemory) {
  for (LogicalFormat format : {LogicalFormat::Rgba8Unorm, LogicalFormat::Output, LogicalFormat::Rgba8Bits}) {
    SCOPED_TRACE(std::string(logicalFormatName(format)));
    LogicalTarget t{"color", format, true, TargetRole::Plain, "main"};
    TargetPlan plan = planTargets(platform, {&t, 1}, 2, 1, {});
    GpuTargets gpu(*dev, plan);
    const uint8_t host[8] = {0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88};  // (r, g, b, a) per pixel
    dev->writeTexture(gpu.attachment("color"), 0, 0, host);
    EXPECT_EQ(gpu.consoleBytes("color"), (std::vector<uint8_t>{0x44, 0x11, 0x22, 0x33, 0x88, 0x55, 0x66, 0x77}));
  }
}

TEST_P(Ps3GpuTest, PackedBlendCorruptsValuesAsTheModelSays) {
  const float x00ff = 255.0f / 65535.0f, x0100 = 256.0f / 65535.0f, x1234 = 0x1234 / 65535.0f;
  LogicalTarget t{"dsf", LogicalFormat::Rg16Unorm, true, TargetRole::GBuffer, "geometry"};
  TargetPlan plan = planTargets(platform, {&t, 1}, 2, 1, {});
  GpuTargets gpu(*dev, plan);
  const std::vector<float> dst = {x00ff, x1234, x1234, x1234}, src = {x0100, x1234, x1234, x1234};
  rhi::TextureHandle d = source(rhi::Format::RG32F, 2, 1, dst.data()), s = source(rhi::Format::RG32F, 2, 1, src.data());
  const PhysicalTarget& pt = plan.targets[0];
  pass(gpu.writeTarget("dsf"), {}, fullscreen(kWriteRg16BitsFs, plan, pt.writeFormat, rhi::Format::Undefined), d);
  rhi::BlendState half;  // 0.5 src + 0.5 dst
  half.enabled = true;
  half.srcColor = half.dstColor = half.srcAlpha = half.dstAlpha = rhi::BlendFactor::ConstantColor;
  dev->setBlendConstant({0.5f, 0.5f, 0.5f, 0.5f});
  pass(gpu.attachment("dsf"), {}, fullscreen(kWriteRg16Fs, plan, pt.attachmentFormat, rhi::Format::Undefined, half), s,
       true);
  std::vector<uint8_t> bytes = gpu.consoleBytes("dsf");
  ASSERT_EQ(bytes.size(), 8u);
  BlendState model;
  model.enabled = true;
  model.srcColor = model.dstColor = model.srcAlpha = model.dstAlpha = BlendFactor::ConstantAlpha;
  model.constantAlpha = 0.5f;
  for (int px = 0; px < 2; ++px) {
    ps3::Argb8Bytes expected = ps3::blendArgb8(ps3::packTwo16InArgb8(src[px * 2], src[px * 2 + 1]),
                                               ps3::packTwo16InArgb8(dst[px * 2], dst[px * 2 + 1]), model);
    for (int k = 0; k < 4; ++k) EXPECT_EQ(bytes[px * 4 + k], expected[k]) << "pixel " << px << " byte " << k;
  }
  const int x = bytes[0] << 8 | bytes[1];
  EXPECT_TRUE(x == 127 || x == 128 || x == 383 || x == 384) << "decoded " << x << " instead of about 255.5";
  EXPECT_EQ(bytes[2] << 8 | bytes[3], 0x1234);  // Y: identical values blend to themselves
  EXPECT_EQ(bytes[4] << 8 | bytes[5], 0x1234);
  DiagnosticList diags;
  ps3::PackedTargetDraw draw;
  draw.target = "dsf";
  draw.blend = model;
  ps3::checkPackedTargetDraw(draw, diags);
  EXPECT_TRUE(diags.has("E_PACKED_BLEND"));
  DiagnosticList none;
  draw.blend = {};
  ps3::checkPackedTargetDraw(draw, none);
  EXPECT_FALSE(none.has("E_PACKED_BLEND"));
  dev->destroy(d);
  dev->destroy(s);
}

// P3: a colour write mask that covers only the high byte of X (console A) splits the value: the
// GPU keeps the destination's low byte, as the model says, and W_PACKED_PARTIAL_WRITEMASK fires;
// a mask covering both bytes of X (A and R) is the near miss.
TEST_P(Ps3GpuTest, PartialWriteMaskSplitsPackedValues) {
  LogicalTarget t{"dsf", LogicalFormat::Rg16Unorm, true, TargetRole::GBuffer, "geometry"};
  TargetPlan plan = planTargets(platform, {&t, 1}, 1, 1, {});
  const std::vector<float> dst = {0x1234 / 65535.0f, 0x5678 / 65535.0f}, src = {0xABCD / 65535.0f, 0xEF01 / 65535.0f};
  const ps3::Argb8Bytes d = ps3::packTwo16InArgb8(dst[0], dst[1]), s = ps3::packTwo16InArgb8(src[0], src[1]);
  for (uint8_t mask : {uint8_t(ps3::kWriteA), uint8_t(ps3::kWriteA | ps3::kWriteR)}) {
    GpuTargets gpu(*dev, plan);
    rhi::TextureHandle dt = source(rhi::Format::RG32F, 1, 1, dst.data()), st = source(rhi::Format::RG32F, 1, 1, src.data());
    const PhysicalTarget& pt = plan.targets[0];
    pass(gpu.writeTarget("dsf"), {}, fullscreen(kWriteRg16BitsFs, plan, pt.writeFormat, rhi::Format::Undefined), dt);
    pass(gpu.attachment("dsf"), {},
         fullscreen(kWriteRg16Fs, plan, pt.attachmentFormat, rhi::Format::Undefined, {}, hostMaskOf(mask)), st, true);
    std::vector<uint8_t> bytes = gpu.consoleBytes("dsf");
    ASSERT_EQ(bytes.size(), 4u);
    const uint8_t bits[4] = {ps3::kWriteA, ps3::kWriteR, ps3::kWriteG, ps3::kWriteB};
    for (int k = 0; k < 4; ++k) EXPECT_EQ(bytes[k], (mask & bits[k]) ? s[k] : d[k]) << "mask " << int(mask) << " byte " << k;
    DiagnosticList diags;
    ps3::PackedTargetDraw draw;
    draw.target = "dsf";
    draw.writeMask = mask;
    ps3::checkPackedTargetDraw(draw, diags);
    EXPECT_EQ(diags.has("W_PACKED_PARTIAL_WRITEMASK"), mask == ps3::kWriteA);
    if (mask == ps3::kWriteA) {
      EXPECT_EQ(bytes[0] << 8 | bytes[1], 0xAB34);  // neither 0x1234 nor 0xABCD
    }
    dev->destroy(dt);
    dev->destroy(st);
  }
}

rhi::SamplerHandle linearSampler(rhi::Device& dev) {
  rhi::SamplerDesc d;
  d.minFilter = d.magFilter = rhi::Filter::Linear;
  return dev.createSampler(d);
}

// P2 filter trap: bilinear sampling halfway between X = 0x00FF and 0x0100. Through the A8R8G8B8
// byte view a per-byte rounding decode rebuilds 127/128/383/384 (the model, with an exact filter:
// 384) and W_PACKED_FILTER fires; through the Y16_X16 view the filter is a real 16-bit one (255.5).
TEST_P(Ps3GpuTest, ByteViewFilterTrap) {
  LogicalTarget t{"dsf", LogicalFormat::Rg16Unorm, true, TargetRole::GBuffer, "geometry"};
  TargetPlan plan = planTargets(platform, {&t, 1}, 2, 1, {});
  GpuTargets gpu(*dev, plan);
  const std::vector<float> xy = {255.0f / 65535.0f, 0.0f, 256.0f / 65535.0f, 0.0f};
  rhi::TextureHandle src = source(rhi::Format::RG32F, 2, 1, xy.data());
  const PhysicalTarget& pt = plan.targets[0];
  pass(gpu.writeTarget("dsf"), {}, fullscreen(kWriteRg16BitsFs, plan, pt.writeFormat, rhi::Format::Undefined), src);
  // Host RGBA8 bytes are [lo X, hi X, ...]: console A (hi) is .g, R (lo) is .r.
  const char* fs = R"(#version 450
layout(binding = 0) uniform sampler2D uBytes;
layout(binding = 1) uniform sampler2D uY16;
layout(location = 0) out vec2 o;
void main() {
  vec4 b = texture(uBytes, vec2(0.5, 0.5));
  o = vec2(floor(255.0 * b.g + 0.5) * 256.0 + floor(255.0 * b.r + 0.5), texture(uY16, vec2(0.5, 0.5)).r * 65535.0);
})";
  rhi::PipelineHandle p = fullscreen(fs, plan, rhi::Format::RG32F, rhi::Format::Undefined);
  rhi::SamplerHandle lin = linearSampler(*dev);
  rhi::TextureHandle out = target(rhi::Format::RG32F, 1, 1);
  rhi::PassDesc pd;
  pd.colors[0].texture = out;
  dev->beginPass(pd);
  dev->setPipeline(p);
  rhi::ResourceBinding b[2];
  b[0].binding = 0;
  b[0].kind = rhi::BindingKind::SampledTexture;
  b[0].texture = gpu.attachment("dsf");
  b[0].sampler = lin;
  b[1] = b[0];
  b[1].binding = 1;
  b[1].texture = gpu.readTexture("dsf");
  dev->setBindings({b, 2});
  dev->draw(3);
  dev->endPass();
  std::vector<float> got = asFloats(dev->readTexture(out));
  ASSERT_EQ(got.size(), 2u);
  ps3::Argb f = ps3::filterArgb8({0x00, 0xFF, 0, 0}, {0x01, 0x00, 0, 0}, 0.5f);
  const float model = ps3::decodePacked16RoundPerByte(f[0], f[1]);
  EXPECT_EQ(model, 384.0f);
  EXPECT_TRUE(got[0] == 127 || got[0] == 128 || got[0] == 383 || got[0] == 384) << got[0];
  RecordProperty("byte_view_decode", std::to_string(got[0]));
  EXPECT_NEAR(got[1], ps3::filterY16(255, 256, 0.5f), 0.5) << "the Y16_X16 view filters 16-bit values";
  DiagnosticList trap, safe;
  ps3::PackedTextureRead read;
  read.texture = "dsf";
  read.viewFormat = ps3::kTextureA8R8G8B8;
  read.filter = Filter::Linear;
  ps3::checkPackedTextureRead(read, trap);
  EXPECT_TRUE(trap.has("W_PACKED_FILTER"));
  EXPECT_TRUE(trap.has("W_PACKED_VIEW_MISMATCH"));
  read.viewFormat = ps3::kTextureY16X16;
  ps3::checkPackedTextureRead(read, safe);
  EXPECT_FALSE(safe.has("W_PACKED_FILTER"));
  EXPECT_FALSE(safe.has("W_PACKED_VIEW_MISMATCH"));
  dev->destroy(out);
  dev->destroy(lin);
  dev->destroy(src);
}

// One host texel order for every emulated A8R8G8B8 surface: the packed16x2 colour surface and
// the depth-as-ARGB8 bitcast keep console channel A in the same host channel
// (ps3::kHostChannelOfConsole), so a shader or a readback reads A8R8G8B8 data one way. Colour
// X = 0x1234, Y = 0x5678 is console [12 34 56 78]; D24 = 0xABCDEF, S = 0x5A is [AB CD EF 5A].
// The raw host texels of both match the model's order, and both read back as memory bytes.
TEST_P(Ps3GpuTest, Argb8HostTexelOrderIsOneForColourAndDepth) {
  const std::vector<LogicalTarget> logical = {{"dsf", LogicalFormat::Rg16Unorm, true, TargetRole::GBuffer, "geometry"},
                                              {"depth", LogicalFormat::Depth24Stencil8, true, TargetRole::GBuffer,
                                               "geometry"}};
  TargetPlan plan = planTargets(platform, logical, 1, 1, {});
  GpuTargets gpu(*dev, plan);
  const std::vector<float> xy = {0x1234 / 65535.0f, 0x5678 / 65535.0f};
  rhi::TextureHandle src = source(rhi::Format::RG32F, 1, 1, xy.data());
  const PhysicalTarget& colour = *plan.find("dsf");
  pass(gpu.writeTarget("dsf"), {}, fullscreen(kWriteRg16BitsFs, plan, colour.writeFormat, rhi::Format::Undefined), src);
  // Depth D24 = 0xABCDEF with stencil 0x5A, uploaded as the packed (D24 << 8) | S word.
  const uint32_t depthWord = 0xABCDEFu << 8 | 0x5Au;
  dev->writeTexture(gpu.attachment("depth"), 0, 0, &depthWord);
  ASSERT_TRUE(gpu.resolve("depth")) << gpu.error();
  const std::vector<uint8_t> colourHost = dev->readTexture(gpu.attachment("dsf"));
  const std::vector<uint8_t> depthHost = dev->readTexture(gpu.readTexture("depth"));
  ASSERT_EQ(colourHost.size(), 4u);
  ASSERT_EQ(depthHost.size(), 4u);
  const ps3::Argb8Bytes colourConsole = {0x12, 0x34, 0x56, 0x78}, depthConsole = {0xAB, 0xCD, 0xEF, 0x5A};
  const int hostA = ps3::kHostChannelOfConsole[ps3::kA];
  EXPECT_EQ(colourHost[hostA], 0x12) << "colour: console A (high byte of X) in host channel " << hostA;
  EXPECT_EQ(depthHost[hostA], 0xAB) << "depth: console A (D_hi) in host channel " << hostA;
  const std::array<uint8_t, 4> colourModel = ps3::hostTexelOfArgb8(colourConsole);
  const std::array<uint8_t, 4> depthModel = ps3::hostTexelOfArgb8(depthConsole);
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(colourHost[k], colourModel[k]) << "colour host channel " << k;
    EXPECT_EQ(depthHost[k], depthModel[k]) << "depth host channel " << k;
  }
  EXPECT_EQ(gpu.consoleBytes("dsf"), std::vector<uint8_t>(colourConsole.begin(), colourConsole.end()));
  EXPECT_EQ(gpu.consoleBytes("depth", true), std::vector<uint8_t>(depthConsole.begin(), depthConsole.end()));
  dev->destroy(src);
}

// P4 traps on the GPU read path (the bytes of the depth-as-ARGB8 texture are written directly;
// the bitcast pass itself is covered by DepthVectorsMatchTheModel):
//  * wrong remap: decoding .rgb with the identity remap reads (0xCD, 0xEF, 0x5A) -> 0.80443;
//  * filter: bilinear halfway between D24 0x00FFFF and 0x010000 rounds each byte and decodes
//    about 0x018080 = 98432 instead of 65535.5.
TEST_P(Ps3GpuTest, DepthWrongRemapAndFilterTraps) {
  LogicalTarget t{"depth", LogicalFormat::Depth24Stencil8, true, TargetRole::GBuffer, "geometry"};
  TargetPlan plan = planTargets(platform, {&t, 1}, 2, 1, {});
  GpuTargets gpu(*dev, plan);
  auto bytesOf = [](uint32_t d24, uint8_t s) { return ps3::depthStencilMemoryBytes(d24, s); };
  std::array<uint8_t, 8> texels{};
  auto put = [&](int px, uint32_t d24, uint8_t s) {
    std::array<uint8_t, 4> b = ps3::hostTexelOfArgb8(bytesOf(d24, s));
    std::copy(b.begin(), b.end(), texels.begin() + px * 4);
  };
  const char* pointFs = R"(#version 450
#include "platform.glsl"
layout(binding = 0) uniform PARITY_DEPTH_SAMPLER uDepth;
layout(location = 0) out float o;
void main() { o = parityReadDepth(texelFetch(uDepth, ivec2(gl_FragCoord.xy), 0)); })";
  const char* linearFs = R"(#version 450
#include "platform.glsl"
layout(binding = 0) uniform PARITY_DEPTH_SAMPLER uDepth;
layout(location = 0) out float o;
void main() { o = parityReadDepth(texture(uDepth, vec2(0.5, 0.5))); })";
  put(0, 0xABCDEF, 0x5A);
  put(1, 0xABCDEF, 0x5A);
  dev->writeTexture(gpu.readTexture("depth"), 0, 0, texels.data());
  for (uint32_t remap : {ps3::kRemapBarg, ps3::kRemapIdentity}) {
    TargetPlan p = plan;
    for (auto& [k, v] : p.shaderDefines)
      if (k == "PARITY_PS3_DEPTH_REMAP") v = remap == ps3::kRemapBarg ? "0xAA93u" : "0xAAE4u";
    rhi::TextureHandle out = target(rhi::Format::R32F, 2, 1);
    pass(out, {}, fullscreen(pointFs, p, rhi::Format::R32F, rhi::Format::Undefined), gpu.readTexture("depth"));
    std::vector<float> got = asFloats(dev->readTexture(out));
    const float model = ps3::texDepth2DPrecise(ps3::sampleDepthAsArgb8(0xABCDEF, 0x5A, remap));
    EXPECT_LE(ulpDistance(got[0], model), 1) << "remap " << std::hex << remap << ": " << got[0] << " vs " << model;
    EXPECT_NEAR(got[0], remap == ps3::kRemapBarg ? 0.67111108727 : 0.80443, 1e-5);
    DiagnosticList diags;
    ps3::DepthAsColorRead read;
    read.surface = "depth";
    read.remap = remap;
    ps3::checkDepthAsColorRead(read, diags);
    EXPECT_EQ(diags.has("E_DEPTH_AS_COLOR_REMAP"), remap != ps3::kRemapBarg);
    dev->destroy(out);
  }
  put(0, 0x00FFFF, 0);
  put(1, 0x010000, 0);
  dev->writeTexture(gpu.readTexture("depth"), 0, 0, texels.data());
  rhi::SamplerHandle lin = linearSampler(*dev);
  rhi::TextureHandle out = target(rhi::Format::R32F, 1, 1);
  pass(out, {}, fullscreen(linearFs, plan, rhi::Format::R32F, rhi::Format::Undefined), gpu.readTexture("depth"), false,
       lin);
  const float got = asFloats(dev->readTexture(out))[0];
  const uint32_t d24 = uint32_t(std::lround(double(got) * 16777215.0));
  std::set<uint32_t> perByteRoundings;
  for (uint32_t hi : {0u, 1u})
    for (uint32_t mid : {127u, 128u})
      for (uint32_t lo : {127u, 128u}) perByteRoundings.insert(hi << 16 | mid << 8 | lo);
  EXPECT_TRUE(perByteRoundings.count(d24)) << "decoded " << d24 << " instead of about 65535.5";
  std::array<float, 3> f = ps3::filterDepthBytes(0x00FFFF, 0x010000, 0.5f);
  const uint32_t modelD24 = uint32_t(std::floor(f[0] * 255.0f + 0.5f)) << 16 |
                            uint32_t(std::floor(f[1] * 255.0f + 0.5f)) << 8 | uint32_t(std::floor(f[2] * 255.0f + 0.5f));
  EXPECT_EQ(modelD24, 0x018080u);
  RecordProperty("filtered_d24", std::to_string(d24));
  DiagnosticList trap, safe;
  ps3::DepthAsColorRead read;
  read.surface = "depth";
  read.magFilter = Filter::Linear;
  ps3::checkDepthAsColorRead(read, trap);
  EXPECT_TRUE(trap.has("W_DEPTH_AS_COLOR_FILTER"));
  read.magFilter = Filter::Nearest;
  ps3::checkDepthAsColorRead(read, safe);
  EXPECT_TRUE(safe.empty()) << safe.all().front().code;
  dev->destroy(out);
  dev->destroy(lin);
}

// D1: depth is read only through the R24X8 copy. The read texture is a separate R32_UINT
// texture holding the 24-bit word; depth drawn after the copy is invisible until the next copy
// (W_DX10_DEPTH_NOT_RESOLVED), and MSAA or bound-for-writing reads are refused / nulled.
TEST_P(Dx10GpuTest, DepthReadOnlyThroughTheR24X8Copy) {
  LogicalTarget t{"depth", LogicalFormat::Depth24Stencil8, true, TargetRole::GBuffer, "geometry"};
  TargetPlan plan = planTargets(platform, {&t, 1}, 2, 1, {});
  const PhysicalTarget& pt = plan.targets[0];
  EXPECT_EQ(pt.readFormat, rhi::Format::R32_UINT);
  EXPECT_TRUE(pt.resolve.needed);
  GpuTargets gpu(*dev, plan);
  EXPECT_NE(gpu.readTexture("depth"), gpu.attachment("depth"));
  const std::vector<float> first = {float(0xABCDEF / 16777215.0), 1.0f}, second = {0.25f, 0.5f};
  rhi::TextureHandle a = source(rhi::Format::R32F, 2, 1, first.data()), b = source(rhi::Format::R32F, 2, 1, second.data());
  rhi::PipelineHandle write = fullscreen(kWriteDepthFs, plan, rhi::Format::Undefined, pt.attachmentFormat);
  rhi::PipelineHandle read = fullscreen(kReadDepthFs, plan, rhi::Format::R32F, rhi::Format::Undefined);
  pass({}, gpu.attachment("depth"), write, a);
  ASSERT_TRUE(gpu.resolve("depth")) << gpu.error();
  pass({}, gpu.attachment("depth"), write, b);  // after the copy: not visible through it
  rhi::TextureHandle out = target(rhi::Format::R32F, 2, 1);
  pass(out, {}, read, gpu.readTexture("depth"));
  std::vector<float> got = asFloats(dev->readTexture(out));
  EXPECT_LE(ulpDistance(got[0], 0.67111108727f), 1) << got[0];
  EXPECT_EQ(got[1], 1.0f);
  DiagnosticList stale;
  dx10::DepthRead r;
  r.resource = "depth";
  r.resolvedSinceLastDepthWrite = false;
  EXPECT_EQ(dx10::checkDepthRead(r, stale), dx10::DepthReadOutcome::Allowed);
  EXPECT_TRUE(stale.has("W_DX10_DEPTH_NOT_RESOLVED"));
  ASSERT_TRUE(gpu.resolve("depth")) << gpu.error();
  pass(out, {}, read, gpu.readTexture("depth"));
  got = asFloats(dev->readTexture(out));
  EXPECT_EQ(got[0], dx10::decodeR24X8(dx10::quantizeD24(0.25f)));
  EXPECT_EQ(got[1], dx10::decodeR24X8(dx10::quantizeD24(0.5f)));
  DiagnosticList msaa, hazard, fine;
  r.resolvedSinceLastDepthWrite = true;
  EXPECT_EQ(dx10::checkDepthRead(r, fine), dx10::DepthReadOutcome::Allowed);
  EXPECT_TRUE(fine.empty());
  r.sampleCount = 4;
  EXPECT_EQ(dx10::checkDepthRead(r, msaa), dx10::DepthReadOutcome::Refused);
  EXPECT_TRUE(msaa.has("E_DX10_MSAA_DEPTH_READ"));
  r.sampleCount = 1;
  r.boundAsDsv = true;
  dx10::DepthReadOutcome o = dx10::checkDepthRead(r, hazard);
  EXPECT_EQ(o, dx10::DepthReadOutcome::NulledSrv);
  EXPECT_TRUE(hazard.has("W_DX10_SRV_DSV_HAZARD"));
  EXPECT_EQ(dx10::sampleDepth(0xABCDEF, o), 0.0f);
  dev->destroy(out);
  dev->destroy(a);
  dev->destroy(b);
}

// X5 on the GPU: a guest screen-space quad drawn with the layer's viewport shift
// (hostPixelCenterOffset). D3D9 centres (HALFPIXELOFFSET FALSE): pixel (3, 1) of the (0,0)-(4,4)
// quad interpolates UV (0.75, 0.25) and the thin quad x in [0.5, 1.5) covers column 1; with
// HALFPIXELOFFSET TRUE: (0.875, 0.375) and column 0. Every pixel's UV and coverage against the
// model; UVs to 1e-6 (attribute interpolation is not exact arithmetic).
TEST_P(X360GpuTest, PixelCentresUvAndCoverage) {
  auto quadVs = [](const x360::ScreenQuad& q, float size) {
    char b[1024];
    std::snprintf(b, sizeof b, R"(#version 450
layout(location = 0) out vec2 vUv;
void main() {
  const vec2 corner[6] = vec2[](vec2(0, 0), vec2(1, 0), vec2(0, 1), vec2(1, 0), vec2(1, 1), vec2(0, 1));
  vec2 c = corner[gl_VertexIndex];
  vec2 p = mix(vec2(%.9g, %.9g), vec2(%.9g, %.9g), c);
  vUv = mix(vec2(%.9g, %.9g), vec2(%.9g, %.9g), c);
  gl_Position = vec4(p / %.9g * 2.0 - 1.0, 0.0, 1.0);
})",
                  q.x0, q.y0, q.x1, q.y1, q.u0, q.v0, q.u1, q.v1, size);
    return std::string(b);
  };
  const char* uvFs = R"(#version 450
layout(location = 0) in vec2 vUv;
layout(location = 0) out vec4 o;
void main() { o = vec4(vUv, 1.0, 1.0); })";
  const uint32_t n = 4;
  for (bool halfPixelOffset : {false, true}) {
    PlatformParams params;
    params.halfPixelOffset = halfPixelOffset;
    const x360::PixelCenter center = x360::pixelCenterFor(halfPixelOffset, params);
    LogicalTarget t{"post", LogicalFormat::Rgba8Unorm, false, TargetRole::Plain, "post"};
    TargetPlan plan = planTargets(platform, {&t, 1}, n, n, params);
    rhi::Viewport vp;
    vp.x = vp.y = hostPixelCenterOffset(platform, params);
    vp.width = vp.height = float(n);
    EXPECT_EQ(vp.x, halfPixelOffset ? 0.0f : 0.5f);
    for (const x360::ScreenQuad& q : {x360::ScreenQuad{0, 0, 4, 4, 0, 0, 1, 1}, x360::ScreenQuad{0.5f, 0, 1.5f, 4, 0, 0, 1, 1}}) {
      rhi::TextureHandle out = target(rhi::Format::RGBA32F, n, n);
      pass(out, {}, fullscreen(uvFs, plan, rhi::Format::RGBA32F, rhi::Format::Undefined, {}, rhi::ColorMask_All,
                               quadVs(q, float(n))),
           {}, false, {}, 6, &vp);
      std::vector<float> got = asFloats(dev->readTexture(out));
      ASSERT_EQ(got.size(), size_t(n) * n * 4);
      for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x) {
          const float* texel = &got[(y * n + x) * 4];
          const bool covered = x360::quadCoversPixel(q, int(x), int(y), center);
          EXPECT_EQ(texel[3] == 1.0f, covered) << "hpo " << halfPixelOffset << " quad x0 " << q.x0 << " pixel " << x << "," << y;
          if (!covered || texel[3] != 1.0f) continue;
          x360::ScreenPoint uv = x360::quadUvAtPixel(q, int(x), int(y), center);
          EXPECT_NEAR(texel[0], uv.x, 1e-6) << "pixel " << x << "," << y;
          EXPECT_NEAR(texel[1], uv.y, 1e-6) << "pixel " << x << "," << y;
        }
      if (q.x1 == 4) {
        const float* p31 = &got[(1 * n + 3) * 4];
        EXPECT_NEAR(p31[0], halfPixelOffset ? 0.875f : 0.75f, 1e-6);
        EXPECT_NEAR(p31[1], halfPixelOffset ? 0.375f : 0.25f, 1e-6);
      } else {
        EXPECT_EQ(got[(0 * n + (halfPixelOffset ? 0 : 1)) * 4 + 3], 1.0f) << "covered column";
        EXPECT_EQ(got[(0 * n + (halfPixelOffset ? 1 : 0)) * 4 + 3], 0.0f) << "uncovered column";
      }
      dev->destroy(out);
    }
  }
}

std::string paramName(const ::testing::TestParamInfo<Param>& info) {
  return std::get<0>(info.param) + "_" + std::string(platformName(std::get<1>(info.param)));
}

INSTANTIATE_TEST_SUITE_P(Platforms, PlatformGpuTest,
                         ::testing::Combine(::testing::ValuesIn(parity::test::allBackends()),
                                            ::testing::Values(PlatformId::Reference, PlatformId::Dx10, PlatformId::Ps3,
                                                              PlatformId::X360)),
                         paramName);
INSTANTIATE_TEST_SUITE_P(Consoles, ConsoleGpuTest,
                         ::testing::Combine(::testing::ValuesIn(parity::test::allBackends()),
                                            ::testing::Values(PlatformId::Dx10, PlatformId::Ps3, PlatformId::X360)),
                         paramName);
INSTANTIATE_TEST_SUITE_P(X360, X360GpuTest,
                         ::testing::Combine(::testing::ValuesIn(parity::test::allBackends()),
                                            ::testing::Values(PlatformId::X360)),
                         paramName);
INSTANTIATE_TEST_SUITE_P(X360, X360MsaaGpuTest,
                         ::testing::Combine(::testing::ValuesIn(parity::test::allBackends()),
                                            ::testing::Values(PlatformId::X360)),
                         paramName);
INSTANTIATE_TEST_SUITE_P(Ps3, Ps3GpuTest,
                         ::testing::Combine(::testing::ValuesIn(parity::test::allBackends()),
                                            ::testing::Values(PlatformId::Ps3)),
                         paramName);
INSTANTIATE_TEST_SUITE_P(Dx10, Dx10GpuTest,
                         ::testing::Combine(::testing::ValuesIn(parity::test::allBackends()),
                                            ::testing::Values(PlatformId::Dx10)),
                         paramName);

}  // namespace
}  // namespace parity::platforms
