// The platform layers' real GPU path on every backend, compared with the CPU models.
//
// Each test renders known values through the platform's write path (platform.glsl's
// parityWriteRg16, or the depth test), runs the platform's resolve / copy pass (GpuTargets), reads
// them through the read path (parityReadRg16 / parityReadDepth) into an RG32F / R32F target and
// compares with the CPU model of platforms/<platform>/.
//
// Tolerances:
//  * Integer words (x360 EDRAM int16 and resolved words, PS3 packed bytes, D24 words) are compared
//    bit for bit: the shaders evaluate the model's fp32 expressions in the same order with
//    `precise` (no contraction) and the unorm8/snorm16 conversions of exact k/255, s/32767 are
//    exact.
//  * Final floats (what a technique's shader reads) may differ by 1 ULP: they come from the texture
//    unit's unorm/snorm-to-float conversion or a shader division by 65535, 32767 or 16777215,
//    neither of which GLSL/SPIR-V requires to be correctly rounded (the model's are), and the
//    pack itself allows 1 ULP for texDepth2D_precise (P4).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "platforms/dx10/depth_read.h"
#include "platforms/platform_layer.h"
#include "platforms/ps3/depth_read.h"
#include "platforms/ps3/packed16.h"
#include "platforms/x360/fixed16.h"
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

// Writes the source RG32F texel through the platform's write path.
const char* kWriteRg16Fs = R"(#version 450
#include "platform.glsl"
layout(binding = 0) uniform sampler2D uSource;
layout(location = 0) out vec4 o;
void main() { o = parityWriteRg16(texelFetch(uSource, ivec2(gl_FragCoord.xy), 0).xy); })";

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

  rhi::PipelineHandle fullscreen(const std::string& fs, const TargetPlan& plan, rhi::Format color, rhi::Format depth) {
    rhi::PipelineDesc p;
    p.vertexShader = shader(rhi::ShaderStage::Vertex, kFullscreenVs, plan);
    p.fragmentShader = shader(rhi::ShaderStage::Fragment, fs, plan);
    if (color != rhi::Format::Undefined) {
      p.colorTargets[0].format = color;
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

  void pass(rhi::TextureHandle color, rhi::TextureHandle depth, rhi::PipelineHandle p, rhi::TextureHandle input) {
    rhi::PassDesc pd;
    pd.colors[0].texture = color;
    pd.depthStencil.texture = depth;
    dev->beginPass(pd);
    dev->setPipeline(p);
    rhi::ResourceBinding b;
    b.binding = 0;
    b.kind = rhi::BindingKind::SampledTexture;
    b.texture = input;
    dev->setBindings({&b, 1});
    dev->draw(3);
    dev->endPass();
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
    pass(gpu.attachment("dsf"), {}, fullscreen(kWriteRg16Fs, plan, pt.attachmentFormat, rhi::Format::Undefined), src);
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
TEST_P(PlatformGpuTest, X360ResolvePathsABC) {
  if (platform != PlatformId::X360) GTEST_SKIP() << "x360 only";
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
TEST_P(PlatformGpuTest, X360Fixed16EncodeVectors) {
  if (platform != PlatformId::X360) GTEST_SKIP() << "x360 only";
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

// X3 (3): the MSAA averaging vector, 2x samples 0x0800 / 0xF800 resolved with k01 into unsigned
// k_16_16 (path A's destination): the model gives 0, mainline Xenia's -1 unpack clamp 0.50003.
TEST_P(PlatformGpuTest, X360MsaaAveragingVector) {
  if (platform != PlatformId::X360) GTEST_SKIP() << "x360 only";
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

std::string paramName(const ::testing::TestParamInfo<Param>& info) {
  return std::get<0>(info.param) + "_" + std::string(platformName(std::get<1>(info.param)));
}

INSTANTIATE_TEST_SUITE_P(Platforms, PlatformGpuTest,
                         ::testing::Combine(::testing::ValuesIn(parity::test::allBackends()),
                                            ::testing::Values(PlatformId::Reference, PlatformId::Dx10, PlatformId::Ps3,
                                                              PlatformId::X360)),
                         paramName);

}  // namespace
}  // namespace parity::platforms
