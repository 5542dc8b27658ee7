// RHI conformance of the texture formats and dimensions beyond the first set: D16, the 8/16-bit
// snorm and two-channel integer formats, the packed B10G11R11_UFLOAT, the signed and 128-bit
// integer formats, Tex1D and Tex3D. Every test runs on every backend and compares read-back
// texels with values worked out by hand (the 11/11/10 float bit layouts, snorm c / 127, D16
// q / 65535), never with a backend's own output.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "rhi/rhi.h"
#include "tests/test_support.h"

namespace parity::rhi {
namespace {

using parity::test::allBackends;
using parity::test::BackendName;

const char* kFullscreenVs = R"(#version 450
void main() {
  vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
  gl_Position = vec4(p * 2.0 - 1.0, 0.2, 1.0);
})";

template <class T>
std::vector<T> as(const std::vector<uint8_t>& bytes) {
  std::vector<T> v(bytes.size() / sizeof(T));
  if (!v.empty()) std::memcpy(v.data(), bytes.data(), v.size() * sizeof(T));
  return v;
}

template <class T>
std::vector<uint8_t> bytesOf(const std::vector<T>& v) {
  std::vector<uint8_t> b(v.size() * sizeof(T));
  if (!b.empty()) std::memcpy(b.data(), v.data(), b.size());
  return b;
}

class RhiTextureFormatsTest : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    dev = parity::test::makeDevice(GetParam());
    if (!dev) GTEST_SKIP() << "backend " << GetParam() << " unavailable";
  }
  void TearDown() override { dev.reset(); }

  TextureHandle texture(TextureDesc d) {
    if (d.label.empty()) d.label = formatInfo(d.format).name;
    TextureHandle t = dev->createTexture(d);
    EXPECT_TRUE(t) << "createTexture " << d.label;
    return t;
  }
  TextureHandle texture2D(Format f, uint32_t w, uint32_t h, const void* data = nullptr,
                          uint32_t usage = TextureUsage_Default) {
    TextureDesc d;
    d.format = f;
    d.width = w, d.height = h;
    d.initialData = data;
    d.usage = usage;
    return texture(d);
  }
  PipelineHandle fullscreen(const char* fs, Format color, Format depth = Format::Undefined,
                            CompareOp depthCompare = CompareOp::Always) {
    PipelineDesc d;
    d.vertexShader = parity::test::makeShader(*dev, ShaderStage::Vertex, kFullscreenVs);
    d.fragmentShader = parity::test::makeShader(*dev, ShaderStage::Fragment, fs);
    d.colorTargetCount = color == Format::Undefined ? 0 : 1;
    d.colorTargets[0].format = color;
    d.depthStencilFormat = depth;
    d.depthStencil.depthCompare = depthCompare;
    d.depthStencil.depthWrite = depth != Format::Undefined;
    d.label = "formats fullscreen";
    PipelineHandle p = dev->createPipeline(d);
    EXPECT_TRUE(p);
    return p;
  }
  ComputePipelineHandle compute(const char* cs) {
    ComputePipelineDesc d;
    d.computeShader = parity::test::makeShader(*dev, ShaderStage::Compute, cs);
    d.label = "formats compute";
    ComputePipelineHandle p = dev->createComputePipeline(d);
    EXPECT_TRUE(p);
    return p;
  }
  // Draws `fs` over the whole of `color` (cleared to `clear`), optionally reading `sampled` at
  // binding 0.
  void drawInto(TextureHandle color, Format format, const char* fs, TextureHandle sampled = {},
                std::array<float, 4> clear = {0, 0, 0, 0}) {
    PipelineHandle p = fullscreen(fs, format);
    ResourceBinding b;
    b.binding = 0;
    b.kind = BindingKind::SampledTexture;
    b.texture = sampled;
    PassDesc pass;
    pass.colors[0].texture = color;
    pass.colors[0].clearColor = clear;
    pass.label = "formats";
    dev->beginPass(pass);
    dev->setPipeline(p);
    if (sampled) dev->setBindings({&b, 1});
    dev->draw(3);
    dev->endPass();
  }
  std::vector<uint8_t> read(TextureHandle t, uint32_t layer = 0, TextureAspect aspect = TextureAspect::Color) {
    return dev->readTexture(t, ReadbackRegion{layer, 0, aspect});
  }

  std::unique_ptr<Device> dev;
};

// ---------------------------------------------------------------------------------------------
// Upload and readback move every new colour format's texels unchanged.
// ---------------------------------------------------------------------------------------------
TEST_P(RhiTextureFormatsTest, NewColourFormatsRoundTripUnchanged) {
  // Distinct bytes per texel; snorm bytes avoid 0x80 (-128 and -127 both mean -1.0, and GL may
  // store either).
  for (Format f : {Format::RG8_UINT, Format::RG8_SNORM, Format::R16_SNORM, Format::RGBA8_SNORM, Format::RGBA16_SNORM,
                   Format::B10G11R11_UFLOAT, Format::R32_SINT, Format::RGBA32_UINT, Format::RGBA32_SINT}) {
    const uint32_t size = formatInfo(f).bytesPerTexel * 4;
    std::vector<uint8_t> texels(size), later(size);
    for (uint32_t i = 0; i < size; ++i) {
      texels[i] = static_cast<uint8_t>(0x11 + 7 * i);
      later[i] = static_cast<uint8_t>(0x61 - 5 * i);
    }
    if (f == Format::B10G11R11_UFLOAT) {
      // Finite normal values only (an upload may go through floats): (1, 0.5, 2), 0, (1, 0, 0),
      // (0, 0, 0.5).
      texels = bytesOf(std::vector<uint32_t>{0x801C03C0u, 0u, 15u << 6, (14u << 5) << 22});
      later = bytesOf(std::vector<uint32_t>{(14u << 5) << 22, 15u << 6, 0u, 0x801C03C0u});
    }
    TextureHandle t = texture2D(f, 2, 2, texels.data());
    EXPECT_EQ(read(t), texels) << formatInfo(f).name << " initial data";
    dev->writeTexture(t, 0, 0, later.data());
    EXPECT_EQ(read(t), later) << formatInfo(f).name << " writeTexture";
  }
}

// ---------------------------------------------------------------------------------------------
// B10G11R11_UFLOAT: R in bits 0-10 and G in 11-21 (5-bit exponent, bias 15, 6-bit mantissa), B
// in 22-31 (5-bit mantissa).
// ---------------------------------------------------------------------------------------------
TEST_P(RhiTextureFormatsTest, B10G11R11RendersAndSamplesThePackedLayout) {
  // (1.0, 0.5, 2.0): R = 15 << 6, G = 14 << 6, B = 16 << 5.
  const uint32_t rendered = (15u << 6) | (14u << 6) << 11 | (16u << 5) << 22;
  ASSERT_EQ(rendered, 0x801C03C0u);
  TextureHandle target = texture2D(Format::B10G11R11_UFLOAT, 2, 2);
  drawInto(target, Format::B10G11R11_UFLOAT, R"(#version 450
layout(location = 0) out vec4 o;
void main() { o = vec4(1.0, 0.5, 2.0, 1.0); })");
  EXPECT_EQ(as<uint32_t>(read(target)), std::vector<uint32_t>(4, rendered));

  // (0.25, 3.0, 0.75) uploaded: R = 13 << 6; G = 3.0 = 1.5 * 2: 16 << 6 | 32; B = 0.75 = 1.5 / 2:
  // 14 << 5 | 16.
  const uint32_t word = (13u << 6) | ((16u << 6) | 32u) << 11 | ((14u << 5) | 16u) << 22;
  std::vector<uint32_t> words(4, word);
  TextureHandle source = texture2D(Format::B10G11R11_UFLOAT, 2, 2, words.data(), TextureUsage_Sampled);
  TextureHandle result = texture2D(Format::RGBA32F, 2, 2);
  drawInto(result, Format::RGBA32F, R"(#version 450
layout(set = 0, binding = 0) uniform sampler2D tex;
layout(location = 0) out vec4 o;
void main() { o = texelFetch(tex, ivec2(gl_FragCoord.xy), 0); })",
           source);
  std::vector<float> got = as<float>(read(result));
  ASSERT_EQ(got.size(), 16u);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(got[i * 4 + 0], 0.25f);
    EXPECT_EQ(got[i * 4 + 1], 3.0f);
    EXPECT_EQ(got[i * 4 + 2], 0.75f);
    EXPECT_EQ(got[i * 4 + 3], 1.0f);  // no alpha channel: sampled as 1
  }
}

// ---------------------------------------------------------------------------------------------
// Snorm formats sample as max(c / (2^(b-1) - 1), -1).
// ---------------------------------------------------------------------------------------------
TEST_P(RhiTextureFormatsTest, SnormFormatsSampleAsNormalisedValues) {
  struct Case {
    Format format;
    std::vector<uint8_t> texel;  // one texel
    std::array<float, 4> expected;
  };
  auto s16 = [](int16_t v) {
    uint16_t u = static_cast<uint16_t>(v);
    return std::vector<uint8_t>{static_cast<uint8_t>(u & 0xFF), static_cast<uint8_t>(u >> 8)};
  };
  std::vector<uint8_t> rgba16;
  for (int16_t v : {32767, -16384, 0, -32768}) {
    std::vector<uint8_t> b = s16(v);
    rgba16.insert(rgba16.end(), b.begin(), b.end());
  }
  const std::vector<Case> cases = {
      {Format::RG8_SNORM, {127, static_cast<uint8_t>(-64)}, {1.0f, -64.0f / 127.0f, 0.0f, 1.0f}},
      {Format::R16_SNORM, s16(-1000), {-1000.0f / 32767.0f, 0.0f, 0.0f, 1.0f}},
      {Format::RGBA8_SNORM,
       {static_cast<uint8_t>(-127), 64, 0, static_cast<uint8_t>(-128)},
       {-1.0f, 64.0f / 127.0f, 0.0f, -1.0f}},
      {Format::RGBA16_SNORM, rgba16, {1.0f, -16384.0f / 32767.0f, 0.0f, -1.0f}},
  };
  for (const Case& c : cases) {
    TextureHandle source = texture2D(c.format, 1, 1, c.texel.data(), TextureUsage_Sampled);
    TextureHandle result = texture2D(Format::RGBA32F, 1, 1);
    drawInto(result, Format::RGBA32F, R"(#version 450
layout(set = 0, binding = 0) uniform sampler2D tex;
layout(location = 0) out vec4 o;
void main() { o = texelFetch(tex, ivec2(0), 0); })",
             source);
    std::vector<float> got = as<float>(read(result));
    ASSERT_EQ(got.size(), 4u);
    // Within 1 ulp: the conversion may multiply by the reciprocal.
    for (int i = 0; i < 4; ++i)
      EXPECT_NEAR(got[i], c.expected[i], 1.2e-7f * std::max(1.0f, std::fabs(c.expected[i])))
          << formatInfo(c.format).name << " channel " << i;
  }
}

// ---------------------------------------------------------------------------------------------
// Integer formats: signed clears, shader writes of the full 32-bit range, RG8_UINT.
// ---------------------------------------------------------------------------------------------
TEST_P(RhiTextureFormatsTest, IntegerFormatsClearAndRenderExactly) {
  // Cleared to a negative value, then the top row drawn over.
  TextureHandle r32 = texture2D(Format::R32_SINT, 2, 2);
  {
    PipelineDesc d;
    // Two triangles over NDC y in [-1, 0]: row 0 of two.
    d.vertexShader = parity::test::makeShader(*dev, ShaderStage::Vertex, R"(#version 450
const vec2 k[6] = vec2[](vec2(-1, -1), vec2(1, -1), vec2(1, 0), vec2(-1, -1), vec2(1, 0), vec2(-1, 0));
void main() { gl_Position = vec4(k[gl_VertexIndex], 0.5, 1.0); })");
    d.fragmentShader = parity::test::makeShader(*dev, ShaderStage::Fragment, R"(#version 450
layout(location = 0) out int o;
void main() { o = -2147483647 - 1; })");
    d.colorTargetCount = 1;
    d.colorTargets[0].format = Format::R32_SINT;
    PipelineHandle p = dev->createPipeline(d);
    PassDesc pass;
    pass.colors[0].texture = r32;
    pass.colors[0].clearColor = {-5, 0, 0, 0};
    dev->beginPass(pass);
    dev->setPipeline(p);
    dev->draw(6);
    dev->endPass();
  }
  EXPECT_EQ(as<int32_t>(read(r32)), (std::vector<int32_t>{INT32_MIN, INT32_MIN, -5, -5}));

  TextureHandle sint4 = texture2D(Format::RGBA32_SINT, 1, 1);
  drawInto(sint4, Format::RGBA32_SINT, R"(#version 450
layout(location = 0) out ivec4 o;
void main() { o = ivec4(-1, 2147483647, -123456789, 0); })");
  EXPECT_EQ(as<int32_t>(read(sint4)), (std::vector<int32_t>{-1, 2147483647, -123456789, 0}));

  TextureHandle uint4 = texture2D(Format::RGBA32_UINT, 1, 1);
  drawInto(uint4, Format::RGBA32_UINT, R"(#version 450
layout(location = 0) out uvec4 o;
void main() { o = uvec4(4294967295u, 4000000000u, 1u, 0u); })");
  EXPECT_EQ(as<uint32_t>(read(uint4)), (std::vector<uint32_t>{4294967295u, 4000000000u, 1u, 0u}));

  TextureHandle rg8 = texture2D(Format::RG8_UINT, 1, 1);
  drawInto(rg8, Format::RG8_UINT, R"(#version 450
layout(location = 0) out uvec2 o;
void main() { o = uvec2(200u, 7u); })");
  EXPECT_EQ(read(rg8), (std::vector<uint8_t>{200, 7}));

  // Sampled with isampler2D: the texel's bits as signed integers.
  std::vector<int32_t> texel = {-7, 8, -9, 10};
  TextureHandle src = texture2D(Format::RGBA32_SINT, 1, 1, texel.data(), TextureUsage_Sampled);
  TextureHandle copy = texture2D(Format::RGBA32_SINT, 1, 1);
  drawInto(copy, Format::RGBA32_SINT, R"(#version 450
layout(set = 0, binding = 0) uniform isampler2D tex;
layout(location = 0) out ivec4 o;
void main() { o = texelFetch(tex, ivec2(0), 0) * 3; })",
           src);
  EXPECT_EQ(as<int32_t>(read(copy)), (std::vector<int32_t>{-21, 24, -27, 30}));
}

// ---------------------------------------------------------------------------------------------
// D16: written as 16-bit unorm words, read through the depth aspect as q / 65535.
// ---------------------------------------------------------------------------------------------
TEST_P(RhiTextureFormatsTest, D16WritesReadsBackAndDepthTests) {
  std::vector<uint16_t> words = {0, 1, 0x8000, 0xFFFF};
  TextureDesc d;
  d.format = Format::D16;
  d.width = d.height = 2;
  d.initialData = words.data();
  TextureHandle depth = texture(d);
  std::vector<float> got = as<float>(read(depth, 0, TextureAspect::Depth));
  ASSERT_EQ(got.size(), 4u);
  for (int i = 0; i < 4; ++i)
    EXPECT_EQ(got[i], static_cast<float>(words[i] / 65535.0)) << "texel " << i;

  // A draw at z = 0.2 (13107 / 65535 exactly) with Less passes where the stored depth is
  // greater: texels 2 and 3 only, which then hold 0.2.
  TextureHandle color = texture2D(Format::RGBA8, 2, 2);
  PipelineHandle p = fullscreen(R"(#version 450
layout(location = 0) out vec4 o;
void main() { o = vec4(1.0); })",
                                Format::RGBA8, Format::D16, CompareOp::Less);
  PassDesc pass;
  pass.colors[0].texture = color;
  pass.depthStencil.texture = depth;
  pass.depthStencil.load = LoadOp::Load;
  dev->beginPass(pass);
  dev->setPipeline(p);
  dev->draw(3);
  dev->endPass();
  got = as<float>(read(depth, 0, TextureAspect::Depth));
  ASSERT_EQ(got.size(), 4u);
  const float fifth = static_cast<float>(13107.0 / 65535.0);
  EXPECT_EQ(got, (std::vector<float>{0.0f, static_cast<float>(1.0 / 65535.0), fifth, fifth}));
  EXPECT_EQ(read(color), (std::vector<uint8_t>{0, 0, 0, 0, 0, 0, 0, 0, 255, 255, 255, 255, 255, 255, 255, 255}));
}

// ---------------------------------------------------------------------------------------------
// Tex1D: one row, sampled with sampler1D, rendered to.
// ---------------------------------------------------------------------------------------------
TEST_P(RhiTextureFormatsTest, Tex1DSamplesRendersAndReadsBack) {
  std::vector<uint8_t> texels = {10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 110, 120, 130, 140, 150, 160};
  TextureDesc d;
  d.type = TextureType::Tex1D;
  d.width = 4;
  d.initialData = texels.data();
  TextureHandle line = texture(d);
  EXPECT_EQ(read(line), texels);

  TextureHandle result = texture2D(Format::RGBA8, 4, 2);
  drawInto(result, Format::RGBA8, R"(#version 450
layout(set = 0, binding = 0) uniform sampler1D tex;
layout(location = 0) out vec4 o;
void main() { o = texelFetch(tex, 3 - int(gl_FragCoord.x), 0); })",
           line);
  std::vector<uint8_t> got = read(result);
  ASSERT_EQ(got.size(), 32u);
  for (uint32_t y = 0; y < 2; ++y)
    for (uint32_t x = 0; x < 4; ++x)
      for (uint32_t c = 0; c < 4; ++c)
        EXPECT_EQ(got[(y * 4 + x) * 4 + c], texels[(3 - x) * 4 + c]) << "pixel " << x << ", " << y;

  drawInto(line, Format::RGBA8, R"(#version 450
layout(location = 0) out vec4 o;
void main() { o = vec4(gl_FragCoord.x * 0.25 - 0.125, 0.0, 1.0, 1.0); })");
  // x = 0.5 .. 3.5 writes 0.0, 0.25, 0.5, 0.75: unorm8 0, 64 (63.75), 128 (127.5 rounds up), 191.
  std::vector<uint8_t> rendered = read(line);
  ASSERT_EQ(rendered.size(), 16u);
  EXPECT_EQ(rendered[0], 0);
  EXPECT_EQ(rendered[4], 64);
  EXPECT_EQ(rendered[12], 191);
  EXPECT_EQ(rendered[14], 255);
}

// Tex1D with layers: a 1D array texture, its layers in transfers and in sampler1DArray and
// sampler1DArrayShadow reads, a layer as an attachment.
TEST_P(RhiTextureFormatsTest, Tex1DArrayLayersTransferSampleAndRender) {
  // 4x2 layers, texel x of layer l = (10 x + 100 l, 1, 2, 3).
  std::vector<uint8_t> texels;
  for (uint8_t layer = 0; layer < 2; ++layer)
    for (uint8_t x = 0; x < 4; ++x) texels.insert(texels.end(), {static_cast<uint8_t>(10 * x + 100 * layer), 1, 2, 3});
  TextureDesc d;
  d.type = TextureType::Tex1D;
  d.width = 4;
  d.layers = 2;
  d.initialData = texels.data();
  TextureHandle lines = texture(d);
  EXPECT_EQ(read(lines, 1), std::vector<uint8_t>(texels.begin() + 16, texels.end()));

  TextureHandle result = texture2D(Format::RGBA8, 4, 1);
  drawInto(result, Format::RGBA8, R"(#version 450
layout(set = 0, binding = 0) uniform sampler1DArray tex;
layout(location = 0) out vec4 o;
void main() { o = texelFetch(tex, ivec2(3 - int(gl_FragCoord.x), 1), 0); })",
           lines);
  std::vector<uint8_t> got = read(result);
  ASSERT_EQ(got.size(), 16u);
  for (uint32_t x = 0; x < 4; ++x) EXPECT_EQ(got[x * 4], 100 + 10 * (3 - x)) << "pixel " << x;

  // Depth in layer 1 compared with texture(sampler1DArrayShadow, (u, layer, reference)):
  // depth 0, 1/3, 2/3, 1 against 0.5 with LESS passes where the reference is below the depth.
  std::vector<float> depths = {1, 1, 1, 1, 0, 1.0f / 3, 2.0f / 3, 1};
  d.format = Format::D32F;
  d.initialData = depths.data();
  d.usage = TextureUsage_Sampled;
  TextureHandle shadow = texture(d);
  SamplerDesc sd;
  sd.compareEnabled = true;
  sd.compare = CompareOp::Less;
  SamplerHandle compare = dev->createSampler(sd);
  PipelineHandle p = fullscreen(R"(#version 450
layout(set = 0, binding = 0) uniform sampler1DArrayShadow tex;
layout(location = 0) out vec4 o;
void main() { o = vec4(texture(tex, vec3(gl_FragCoord.x / 4.0, 1.0, 0.5))); })",
                                Format::RGBA8);
  ResourceBinding b;
  b.kind = BindingKind::SampledTexture;
  b.texture = shadow;
  b.sampler = compare;
  dev->setBindings({&b, 1});
  PassDesc pass;
  pass.colors[0].texture = result;
  dev->beginPass(pass);
  dev->setPipeline(p);
  dev->draw(3);
  dev->endPass();
  got = read(result);
  ASSERT_EQ(got.size(), 16u);
  EXPECT_EQ((std::vector<uint8_t>{got[0], got[4], got[8], got[12]}), (std::vector<uint8_t>{0, 0, 255, 255}));
  dev->destroy(compare);

  // Layer 1 as an attachment: the other layer keeps its texels.
  PassDesc layer1;
  layer1.colors[0].texture = lines;
  layer1.colors[0].layer = 1;
  layer1.colors[0].load = LoadOp::Clear;
  layer1.colors[0].clearColor = {1, 0, 0, 1};
  dev->beginPass(layer1);
  dev->endPass();
  EXPECT_EQ(read(lines, 1), (std::vector<uint8_t>{255, 0, 0, 255, 255, 0, 0, 255, 255, 0, 0, 255, 255, 0, 0, 255}));
  EXPECT_EQ(read(lines, 0), std::vector<uint8_t>(texels.begin(), texels.begin() + 16));
}

// ---------------------------------------------------------------------------------------------
// Tex3D: slices as layers in transfers, sampler3D / image3D in shaders, a slice as an attachment.
// ---------------------------------------------------------------------------------------------
TEST_P(RhiTextureFormatsTest, Tex3DSlicesTransferSampleStoreAndRender) {
  // 2x2x3 R32_UINT, texel (x, y, z) = 100 z + 10 y + x.
  std::vector<uint32_t> volume;
  for (uint32_t z = 0; z < 3; ++z)
    for (uint32_t y = 0; y < 2; ++y)
      for (uint32_t x = 0; x < 2; ++x) volume.push_back(100 * z + 10 * y + x);
  TextureDesc d;
  d.type = TextureType::Tex3D;
  d.format = Format::R32_UINT;
  d.width = d.height = 2;
  d.depth = 3;
  d.usage = TextureUsage_Sampled | TextureUsage_Storage | TextureUsage_RenderTarget;
  d.initialData = volume.data();
  TextureHandle vol = texture(d);
  for (uint32_t z = 0; z < 3; ++z)
    EXPECT_EQ(as<uint32_t>(read(vol, z)), std::vector<uint32_t>(volume.begin() + 4 * z, volume.begin() + 4 * z + 4))
        << "slice " << z;
  std::vector<uint32_t> slice1 = {7, 6, 5, 4};
  dev->writeTexture(vol, 1, 0, slice1.data());
  EXPECT_EQ(as<uint32_t>(read(vol, 1)), slice1);
  EXPECT_EQ(as<uint32_t>(read(vol, 2)), (std::vector<uint32_t>{200, 201, 210, 211}));

  // Compute: out[i] = texel read through usampler3D + 1000; then every texel doubled through
  // uimage3D.
  BufferDesc bd;
  bd.size = 12 * 4;
  bd.label = "volume out";
  BufferHandle out = dev->createBuffer(bd);
  ComputePipelineHandle p = compute(R"(#version 450
layout(local_size_x = 2, local_size_y = 2, local_size_z = 3) in;
layout(set = 0, binding = 0) uniform usampler3D src;
layout(set = 0, binding = 1, r32ui) uniform uimage3D dst;
layout(set = 0, binding = 2) buffer Out { uint v[]; } o;
void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  o.v[c.z * 4 + c.y * 2 + c.x] = texelFetch(src, c, 0).r + 1000u;
})");
  TextureViewDesc vd;
  vd.parent = vol;
  vd.label = "volume view";
  TextureHandle view = dev->createTextureView(vd);
  ResourceBinding rb[3];
  rb[0].binding = 0, rb[0].kind = BindingKind::SampledTexture, rb[0].texture = view;
  rb[1].binding = 1, rb[1].kind = BindingKind::StorageTexture, rb[1].texture = vol;
  rb[2].binding = 2, rb[2].kind = BindingKind::StorageBuffer, rb[2].buffer = out;
  dev->setComputePipeline(p);
  dev->setBindings(rb);
  dev->dispatch(1);
  std::vector<uint32_t> expected;
  for (uint32_t z = 0; z < 3; ++z)
    for (uint32_t i = 0; i < 4; ++i) expected.push_back((z == 1 ? slice1[i] : volume[z * 4 + i]) + 1000);
  EXPECT_EQ(as<uint32_t>(dev->readBuffer(out, 0, bd.size)), expected);

  ComputePipelineHandle store = compute(R"(#version 450
layout(local_size_x = 2, local_size_y = 2, local_size_z = 3) in;
layout(set = 0, binding = 1, r32ui) uniform uimage3D dst;
void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  imageStore(dst, c, uvec4(imageLoad(dst, c).r * 2u));
})");
  dev->setComputePipeline(store);
  dev->dispatch(1);
  EXPECT_EQ(as<uint32_t>(read(vol, 0)), (std::vector<uint32_t>{0, 2, 20, 22}));
  EXPECT_EQ(as<uint32_t>(read(vol, 1)), (std::vector<uint32_t>{14, 12, 10, 8}));
  EXPECT_EQ(as<uint32_t>(read(vol, 2)), (std::vector<uint32_t>{400, 402, 420, 422}));

  // Slice 2 as a colour attachment: the others keep their texels.
  PipelineHandle fill = fullscreen(R"(#version 450
layout(location = 0) out uint o;
void main() { o = 9u; })",
                                   Format::R32_UINT);
  PassDesc pass;
  pass.colors[0].texture = vol;
  pass.colors[0].layer = 2;
  pass.colors[0].load = LoadOp::Load;
  dev->beginPass(pass);
  dev->setPipeline(fill);
  dev->draw(3);
  dev->endPass();
  EXPECT_EQ(as<uint32_t>(read(vol, 2)), std::vector<uint32_t>(4, 9));
  EXPECT_EQ(as<uint32_t>(read(vol, 1)), (std::vector<uint32_t>{14, 12, 10, 8}));
  dev->destroy(view);
}

// ---------------------------------------------------------------------------------------------
// Multisampled storage images (Capabilities::storageMultisample): each sample stored and loaded
// on its own.
// ---------------------------------------------------------------------------------------------
TEST_P(RhiTextureFormatsTest, MultisampledStorageImageKeepsEverySample) {
  if (!dev->info().caps.storageMultisample)
    GTEST_SKIP() << dev->info().renderer << " has no multisampled storage images";
  TextureDesc d;
  d.width = d.height = 2;
  d.samples = 4;
  d.usage = TextureUsage_RenderTarget | TextureUsage_Storage;
  d.label = "multisampled storage";
  TextureHandle ms = texture(d);
  TextureDesc one;
  one.format = Format::RGBA8;
  one.width = one.height = 2;
  one.usage = TextureUsage_Storage;
  one.label = "sample copy";
  TextureHandle copies[2] = {texture(one), texture(one)};
  ComputePipelineHandle p = compute(R"(#version 450
layout(local_size_x = 2, local_size_y = 2) in;
layout(set = 0, binding = 0, rgba8) uniform image2DMS ms;
layout(set = 0, binding = 1, rgba8) uniform writeonly image2D sample1;
layout(set = 0, binding = 2, rgba8) uniform writeonly image2D sample3;
void main() {
  ivec2 c = ivec2(gl_GlobalInvocationID.xy);
  for (int s = 0; s < 4; ++s) imageStore(ms, c, s, vec4(s / 4.0, 0.0, 1.0 - s / 4.0, 1.0));
  imageStore(sample1, c, imageLoad(ms, c, 1));
  imageStore(sample3, c, imageLoad(ms, c, 3));
})");
  ResourceBinding rb[3];
  rb[0].binding = 0, rb[0].kind = BindingKind::StorageTexture, rb[0].texture = ms;
  rb[1].binding = 1, rb[1].kind = BindingKind::StorageTexture, rb[1].texture = copies[0];
  rb[2].binding = 2, rb[2].kind = BindingKind::StorageTexture, rb[2].texture = copies[1];
  dev->setComputePipeline(p);
  dev->setBindings(rb);
  dev->dispatch(1);
  // Sample 1: (0.25, 0, 0.75) -> unorm8 (64, 0, 191); sample 3: (0.75, 0, 0.25) -> (191, 0, 64).
  std::vector<uint8_t> s1, s3;
  for (int i = 0; i < 4; ++i) {
    s1.insert(s1.end(), {64, 0, 191, 255});
    s3.insert(s3.end(), {191, 0, 64, 255});
  }
  EXPECT_EQ(read(copies[0]), s1);
  EXPECT_EQ(read(copies[1]), s3);
}

INSTANTIATE_TEST_SUITE_P(Rhi, RhiTextureFormatsTest, ::testing::ValuesIn(allBackends()), BackendName());

}  // namespace
}  // namespace parity::rhi
