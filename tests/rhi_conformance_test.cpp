// RHI conformance suite: every convention and behaviour of rhi/rhi.h, checked on every backend
// by reading pixels (or buffer bytes) back and comparing with values worked out by hand from the
// specs and the measured driver facts (unorm8 output of k/255 is exactly k; blending,
// stencil and texture-view facts as measured on Mesa llvmpipe/lavapipe). Nothing here is taken
// from a backend's own output.
//
// Images are tiny (at most 16x16) because CI runs software rasterisers on 2 cores.
// Rect helper: the "rect" vertex shader draws two triangles covering a rectangle given in NDC by
// push constants. Both triangles are counter-clockwise as seen in the image (image y grows
// downwards with NDC y); flip = 1 reverses the vertex order (clockwise).
#include <gtest/gtest.h>

#include <cstdio>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <functional>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "rhi/rhi.h"
#include "rhi/shader_compiler.h"
#include "rhi/timing_device.h"
#include "tests/test_support.h"

namespace parity::rhi {
namespace {

using parity::test::allBackends;
using parity::test::BackendName;

// ---------------------------------------------------------------------------------------------
// Shaders
// ---------------------------------------------------------------------------------------------
const char* kRectVs = R"(#version 450
layout(push_constant) uniform PC { vec4 rect; vec4 color; float z; int flip; } pc;
layout(location = 0) out vec4 vColor;
layout(location = 1) out vec2 vUV;
const vec2 kCorners[6] = vec2[](vec2(0, 0), vec2(0, 1), vec2(1, 1), vec2(0, 0), vec2(1, 1), vec2(1, 0));
void main() {
  int i = pc.flip != 0 ? 5 - gl_VertexIndex : gl_VertexIndex;
  vec2 c = kCorners[i];
  gl_Position = vec4(mix(pc.rect.xy, pc.rect.zw, c), pc.z, 1.0);
  vColor = pc.color;
  vUV = c;
})";

const char* kColorFs = R"(#version 450
layout(location = 0) in vec4 vColor;
layout(location = 0) out vec4 o;
void main() { o = vColor; })";

const char* kFullscreenVs = R"(#version 450
void main() {
  vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
  gl_Position = vec4(p * 2.0 - 1.0, 0.5, 1.0);
})";

struct RectPC {
  float rect[4];
  float color[4];
  float z;
  int32_t flip;
};
static_assert(sizeof(RectPC) == 40);

// ---------------------------------------------------------------------------------------------
// Pixel helpers
// ---------------------------------------------------------------------------------------------
using Px = std::array<int, 4>;
using Pf = std::array<float, 4>;

template <class T>
T load(const std::vector<uint8_t>& bytes, size_t byteOffset) {
  T v{};
  if (byteOffset + sizeof(T) <= bytes.size()) std::memcpy(&v, bytes.data() + byteOffset, sizeof(T));
  return v;
}

Px rgba8(const std::vector<uint8_t>& b, uint32_t w, uint32_t x, uint32_t y) {
  size_t o = (size_t(y) * w + x) * 4;
  if (o + 4 > b.size()) return {-1, -1, -1, -1};
  return {b[o], b[o + 1], b[o + 2], b[o + 3]};
}

Pf rgba32f(const std::vector<uint8_t>& b, uint32_t w, uint32_t x, uint32_t y) {
  size_t o = (size_t(y) * w + x) * 16;
  return {load<float>(b, o), load<float>(b, o + 4), load<float>(b, o + 8), load<float>(b, o + 12)};
}

std::string str(const Px& p) {
  std::ostringstream s;
  s << "(" << p[0] << ", " << p[1] << ", " << p[2] << ", " << p[3] << ")";
  return s.str();
}

// Compares a whole RGBA8 image with expected(x, y); reports the first few mismatches.
void expectRgba8Image(const std::vector<uint8_t>& px, uint32_t w, uint32_t h,
                      const std::function<Px(uint32_t, uint32_t)>& expected, const char* what = "") {
  ASSERT_EQ(px.size(), size_t(w) * h * 4) << what;
  int reported = 0, mismatches = 0;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      Px got = rgba8(px, w, x, y), want = expected(x, y);
      if (got == want) continue;
      ++mismatches;
      if (reported++ < 6)
        ADD_FAILURE() << what << " pixel (" << x << ", " << y << "): expected " << str(want) << ", got " << str(got);
    }
  EXPECT_EQ(mismatches, 0) << what << ": mismatching pixels";
}

// Pixel-space rectangle [x0, x1) x [y0, y1) of a w x h target, in NDC (exact for powers of two).
std::array<float, 4> ndcRect(float x0, float y0, float x1, float y1, float w, float h) {
  return {-1.0f + 2.0f * x0 / w, -1.0f + 2.0f * y0 / h, -1.0f + 2.0f * x1 / w, -1.0f + 2.0f * y1 / h};
}

constexpr std::array<float, 4> kFullNdc{-1, -1, 1, 1};

std::array<float, 4> unorm(int r, int g, int b, int a) { return {r / 255.0f, g / 255.0f, b / 255.0f, a / 255.0f}; }

// Correctly rounded fp32 of q / (2^24 - 1), the documented D24 depth readback value.
float d24(double depth) {
  double q = std::nearbyint(depth * 16777215.0);
  return static_cast<float>(q / 16777215.0);
}

// ---------------------------------------------------------------------------------------------
// Fixture
// ---------------------------------------------------------------------------------------------
class RhiConformanceTest : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    dev = parity::test::makeDevice(GetParam());
    if (!dev) GTEST_SKIP() << "backend " << GetParam() << " unavailable";
  }
  void TearDown() override { dev.reset(); }

  // Defined with the depth tests below.
  void checkDepthTestLess(Format depthFormat, float left, float right);

  TextureHandle texture(Format f, uint32_t w, uint32_t h, uint32_t usage = TextureUsage_Default,
                        const void* data = nullptr, uint32_t samples = 1, const char* label = "conformance") {
    TextureDesc d;
    d.format = f;
    d.width = w;
    d.height = h;
    d.usage = usage;
    d.initialData = data;
    d.samples = samples;
    d.label = label;
    TextureHandle t = dev->createTexture(d);
    EXPECT_TRUE(t) << "createTexture " << formatInfo(f).name;
    return t;
  }
  TextureHandle texture(const TextureDesc& d) {
    TextureHandle t = dev->createTexture(d);
    EXPECT_TRUE(t) << "createTexture " << d.label;
    return t;
  }
  // A 4x4 sampled RGBA8 texture with 3 mips, level m filled with colours[m].
  TextureHandle threeColouredMips(const std::array<Px, 3>& colours) {
    TextureDesc d;
    d.width = d.height = 4;
    d.mipLevels = 3;
    d.usage = TextureUsage_Sampled;
    d.label = "three mips";
    TextureHandle tex = texture(d);
    for (uint32_t m = 0; m < 3; ++m) {
      std::vector<uint8_t> level;
      for (uint32_t i = 0; i < (4u >> m) * (4u >> m); ++i)
        for (int c = 0; c < 4; ++c) level.push_back(uint8_t(colours[m][c]));
      dev->writeTexture(tex, 0, m, level.data());
    }
    return tex;
  }
  BufferHandle buffer(size_t size, const void* data = nullptr, uint32_t usage = BufferUsage_All) {
    BufferDesc d;
    d.size = size;
    d.initialData = data;
    d.usage = usage;
    d.label = "conformance";
    BufferHandle b = dev->createBuffer(d);
    EXPECT_TRUE(b);
    return b;
  }
  ShaderHandle shader(ShaderStage stage, const char* glsl) { return parity::test::makeShader(*dev, stage, glsl); }

  // The vertex-fetch tests: two points from `vb`, vertex i drawn at pixel i of a 2x1 `format`
  // target (each writes what it fetched into its pixel), read back.
  std::vector<uint8_t> drawTwoPointsAndRead(PipelineDesc d, BufferHandle vb, uint32_t stride, Format format) {
    d.vertexBuffers[0].stride = stride;
    d.topology = PrimitiveTopology::Points;
    d.colorTargetCount = 1;
    d.colorTargets[0].format = format;
    PipelineHandle p = pipeline(d);
    TextureHandle t = texture(format, 2, 1);
    dev->beginPass(pass(t));
    dev->setPipeline(p);
    dev->setVertexBuffer(0, vb);
    dev->draw(2);
    dev->endPass();
    return read(t);
  }

  // Rect vertex shader + fragment shader, one colour target.
  PipelineDesc rectDesc(Format color, const char* fs = kColorFs) {
    PipelineDesc d;
    d.vertexShader = shader(ShaderStage::Vertex, kRectVs);
    d.fragmentShader = shader(ShaderStage::Fragment, fs);
    d.colorTargetCount = color == Format::Undefined ? 0 : 1;
    d.colorTargets[0].format = color;
    d.label = "conformance rect";
    return d;
  }
  PipelineDesc fullscreenDesc(Format color, const char* fs) {
    PipelineDesc d;
    d.vertexShader = shader(ShaderStage::Vertex, kFullscreenVs);
    d.fragmentShader = shader(ShaderStage::Fragment, fs);
    d.colorTargetCount = 1;
    d.colorTargets[0].format = color;
    d.label = "conformance fullscreen";
    return d;
  }
  PipelineHandle pipeline(const PipelineDesc& d) {
    PipelineHandle p = dev->createPipeline(d);
    EXPECT_TRUE(p) << "createPipeline " << d.label;
    return p;
  }
  // One pass into `target` drawing fullscreenDesc's triangle with `p`, under the bindings set.
  void drawFullscreen(PipelineHandle p, TextureHandle target) {
    dev->beginPass(pass(target));
    dev->setPipeline(p);
    dev->draw(3);
    dev->endPass();
  }
  static ResourceBinding storageBuffer(uint32_t binding, BufferHandle b) {
    ResourceBinding rb;
    rb.binding = binding;
    rb.kind = BindingKind::StorageBuffer;
    rb.buffer = b;
    return rb;
  }
  ComputePipelineHandle computePipeline(const char* cs) {
    ComputePipelineDesc d;
    d.computeShader = shader(ShaderStage::Compute, cs);
    d.label = "conformance compute";
    ComputePipelineHandle p = dev->createComputePipeline(d);
    EXPECT_TRUE(p);
    return p;
  }

  void drawRect(const std::array<float, 4>& rect, const std::array<float, 4>& color, float z = 0.5f,
                bool flip = false) {
    RectPC pc{};
    std::memcpy(pc.rect, rect.data(), sizeof(pc.rect));
    std::memcpy(pc.color, color.data(), sizeof(pc.color));
    pc.z = z;
    pc.flip = flip ? 1 : 0;
    dev->pushConstants(&pc, sizeof(pc));
    dev->draw(6);
  }

  static PassDesc pass(TextureHandle color, std::array<float, 4> clear = {0, 0, 0, 0}, TextureHandle depth = {}) {
    PassDesc p;
    p.colors[0].texture = color;
    p.colors[0].clearColor = clear;
    p.depthStencil.texture = depth;
    p.label = "conformance";
    return p;
  }

  std::vector<uint8_t> read(TextureHandle t, uint32_t layer = 0, uint32_t mip = 0,
                            TextureAspect aspect = TextureAspect::Color) {
    return dev->readTexture(t, ReadbackRegion{layer, mip, aspect});
  }

  std::unique_ptr<Device> dev;
};

// ---------------------------------------------------------------------------------------------
// Clears
// ---------------------------------------------------------------------------------------------
TEST_P(RhiConformanceTest, ClearRGBA8) {
  TextureHandle t = texture(Format::RGBA8, 4, 4);
  dev->beginPass(pass(t, unorm(51, 102, 153, 255)));
  dev->endPass();
  expectRgba8Image(read(t), 4, 4, [](uint32_t, uint32_t) { return Px{51, 102, 153, 255}; });
}

TEST_P(RhiConformanceTest, ClearRGBA32F) {
  TextureHandle t = texture(Format::RGBA32F, 4, 4);
  const Pf clear{0.125f, -2.5f, 1.0e6f, 1.0f / 3.0f};
  dev->beginPass(pass(t, clear));
  dev->endPass();
  std::vector<uint8_t> px = read(t);
  ASSERT_EQ(px.size(), 4u * 4 * 16);
  for (uint32_t y = 0; y < 4; ++y)
    for (uint32_t x = 0; x < 4; ++x) EXPECT_EQ(rgba32f(px, 4, x, y), clear) << "pixel " << x << ", " << y;
}

TEST_P(RhiConformanceTest, ClearInteger) {
  // Integer targets take the clear colour converted to integers.
  TextureHandle a = texture(Format::RGBA8_UINT, 4, 4), b = texture(Format::R32_UINT, 4, 4);
  PassDesc p = pass(a, {7, 200, 0, 255});
  p.colors[1].texture = b;
  p.colors[1].clearColor = {123456, 0, 0, 0};
  dev->beginPass(p);
  dev->endPass();
  expectRgba8Image(
      read(a), 4, 4,
      [](uint32_t, uint32_t) {
        return Px{7, 200, 0, 255};
      },
      "RGBA8_UINT");
  std::vector<uint8_t> r = read(b);
  ASSERT_EQ(r.size(), 4u * 4 * 4);
  for (size_t i = 0; i < 16; ++i) EXPECT_EQ(load<uint32_t>(r, i * 4), 123456u) << "texel " << i;
}

// ---------------------------------------------------------------------------------------------
// Viewport, scissor, orientation
// ---------------------------------------------------------------------------------------------
// Push constants are state of each draw: 10240 one-pixel rectangles in one pass, each with its
// own colour, more changes than the GL backend's ring of slots holds (1 MiB of 128-byte slots),
// so the ring wraps within the pass.
TEST_P(RhiConformanceTest, PushConstantsOfEveryDrawAreItsOwn) {
  constexpr uint32_t kW = 128, kH = 80;
  TextureHandle t = texture(Format::RGBA8, kW, kH);
  PipelineHandle p = pipeline(rectDesc(Format::RGBA8));
  auto colour = [](uint32_t x, uint32_t y) { return Px{int(x * 2 % 256), int(y * 3 % 256), int((x + y) % 251), 255}; };
  dev->beginPass(pass(t));
  dev->setPipeline(p);
  for (uint32_t y = 0; y < kH; ++y)
    for (uint32_t x = 0; x < kW; ++x) {
      const Px c = colour(x, y);
      drawRect({-1.0f + 2.0f * x / kW, -1.0f + 2.0f * y / kH, -1.0f + 2.0f * (x + 1) / kW, -1.0f + 2.0f * (y + 1) / kH},
               unorm(c[0], c[1], c[2], c[3]));
    }
  dev->endPass();
  expectRgba8Image(read(t), kW, kH, colour);
}

TEST_P(RhiConformanceTest, Viewport) {
  TextureHandle t = texture(Format::RGBA8, 16, 16);
  PipelineHandle p = pipeline(rectDesc(Format::RGBA8));
  dev->beginPass(pass(t));
  dev->setPipeline(p);
  Viewport vp;
  vp.x = 4;
  vp.y = 8;  // rows counted from row 0
  vp.width = 8;
  vp.height = 4;
  dev->setViewport(vp);
  drawRect(kFullNdc, unorm(0, 255, 0, 255));
  dev->endPass();
  expectRgba8Image(read(t), 16, 16, [](uint32_t x, uint32_t y) {
    return x >= 4 && x < 12 && y >= 8 && y < 12 ? Px{0, 255, 0, 255} : Px{0, 0, 0, 0};
  });
}

TEST_P(RhiConformanceTest, ViewportFractionalOrigin) {
  // Viewport origin (0.5, 0.25), 8x8: the rect's uv (0..1 across the viewport) at the centre of
  // pixel (i, j) is ((i + 0.5 - 0.5) / 8, (j + 0.5 - 0.25) / 8). An origin rounded to whole
  // pixels would give (i + 0.5) / 8 instead.
  TextureHandle t = texture(Format::RGBA32F, 16, 16);
  PipelineHandle p = pipeline(rectDesc(Format::RGBA32F, R"(#version 450
layout(location = 1) in vec2 vUV;
layout(location = 0) out vec4 o;
void main() { o = vec4(vUV, 0.0, 1.0); })"));
  dev->beginPass(pass(t, {-1, -1, -1, -1}));
  dev->setPipeline(p);
  Viewport vp;
  vp.x = 0.5f;
  vp.y = 0.25f;
  vp.width = 8;
  vp.height = 8;
  dev->setViewport(vp);
  drawRect(kFullNdc, {1, 1, 1, 1});
  dev->endPass();
  std::vector<uint8_t> px = read(t);
  ASSERT_EQ(px.size(), 16u * 16 * 16);
  for (uint32_t j = 1; j < 8; ++j)
    for (uint32_t i = 1; i < 8; ++i) {
      Pf v = rgba32f(px, 16, i, j);
      EXPECT_NEAR(v[0], i / 8.0f, 1e-4f) << "pixel " << i << ", " << j;
      EXPECT_NEAR(v[1], (j + 0.25f) / 8.0f, 1e-4f) << "pixel " << i << ", " << j;
    }
  EXPECT_EQ(rgba32f(px, 16, 12, 12), (Pf{-1, -1, -1, -1})) << "outside the viewport";
  EXPECT_EQ(rgba32f(px, 16, 4, 12), (Pf{-1, -1, -1, -1})) << "below the viewport";
}

TEST_P(RhiConformanceTest, Scissor) {
  TextureHandle a = texture(Format::RGBA8, 16, 16), b = texture(Format::RGBA8, 16, 16);
  PipelineDesc d = rectDesc(Format::RGBA8);
  d.raster.scissorEnabled = true;
  PipelineHandle scissored = pipeline(d);
  d.raster.scissorEnabled = false;
  PipelineHandle unscissored = pipeline(d);

  dev->beginPass(pass(a));
  dev->setPipeline(scissored);
  dev->setScissor({2, 3, 5, 6});
  drawRect(kFullNdc, unorm(255, 255, 255, 255));
  dev->endPass();
  // The same rectangle set with a pipeline that has scissorEnabled = false is ignored.
  dev->beginPass(pass(b));
  dev->setPipeline(unscissored);
  dev->setScissor({2, 3, 5, 6});
  drawRect(kFullNdc, unorm(255, 255, 255, 255));
  dev->endPass();
  expectRgba8Image(
      read(a), 16, 16,
      [](uint32_t x, uint32_t y) {
        return x >= 2 && x < 7 && y >= 3 && y < 9 ? Px{255, 255, 255, 255} : Px{0, 0, 0, 0};
      },
      "scissored");
  expectRgba8Image(
      read(b), 16, 16,
      [](uint32_t, uint32_t) {
        return Px{255, 255, 255, 255};
      },
      "unscissored");
}

TEST_P(RhiConformanceTest, NdcTopLeftIsImageTopLeft) {
  // NDC x < 0, y < 0 (here the quarter [-1, -0.5]^2) lands in the low columns and low rows.
  TextureHandle t = texture(Format::RGBA8, 16, 16);
  PipelineHandle p = pipeline(rectDesc(Format::RGBA8));
  dev->beginPass(pass(t));
  dev->setPipeline(p);
  drawRect({-1.0f, -1.0f, -0.5f, -0.5f}, unorm(255, 0, 0, 255));
  dev->endPass();
  expectRgba8Image(read(t), 16, 16, [](uint32_t x, uint32_t y) {
    return x < 4 && y < 4 ? Px{255, 0, 0, 255} : Px{0, 0, 0, 0};
  });
}

TEST_P(RhiConformanceTest, FragCoordOrigin) {
  // gl_FragCoord.xy at pixel (x, y) is (x + 0.5, y + 0.5): row 0 has gl_FragCoord.y = 0.5.
  TextureHandle t = texture(Format::RGBA32F, 8, 4);
  PipelineHandle p = pipeline(fullscreenDesc(Format::RGBA32F, R"(#version 450
layout(location = 0) out vec4 o;
void main() { o = vec4(gl_FragCoord.xy, 0.0, 1.0); })"));
  drawFullscreen(p, t);
  std::vector<uint8_t> px = read(t);
  ASSERT_EQ(px.size(), 8u * 4 * 16);
  for (uint32_t y = 0; y < 4; ++y)
    for (uint32_t x = 0; x < 8; ++x)
      EXPECT_EQ(rgba32f(px, 8, x, y), (Pf{x + 0.5f, y + 0.5f, 0.0f, 1.0f})) << "pixel " << x << ", " << y;
}

TEST_P(RhiConformanceTest, TextureRowZeroIsSampledAtVZero) {
  // Texel (x, y) = (60x, 60y, 7, 255), uploaded row 0 first. Sampling at uv = gl_FragCoord / 4
  // (nearest) must reproduce the texture: v = 0.125 (row 0 of the target) reads row 0.
  std::vector<uint8_t> data(4 * 4 * 4);
  for (uint32_t y = 0; y < 4; ++y)
    for (uint32_t x = 0; x < 4; ++x) {
      uint8_t* t = &data[(y * 4 + x) * 4];
      t[0] = uint8_t(60 * x);
      t[1] = uint8_t(60 * y);
      t[2] = 7;
      t[3] = 255;
    }
  TextureHandle src = texture(Format::RGBA8, 4, 4, TextureUsage_Sampled, data.data());
  TextureHandle dst = texture(Format::RGBA8, 4, 4);
  PipelineHandle p = pipeline(fullscreenDesc(Format::RGBA8, R"(#version 450
layout(set = 0, binding = 0) uniform sampler2D tex;
layout(location = 0) out vec4 o;
void main() { o = texture(tex, gl_FragCoord.xy / 4.0); })"));
  ResourceBinding b;
  b.binding = 0;
  b.kind = BindingKind::SampledTexture;
  b.texture = src;
  dev->setBindings({&b, 1});
  drawFullscreen(p, dst);
  expectRgba8Image(read(dst), 4, 4, [](uint32_t x, uint32_t y) { return Px{int(60 * x), int(60 * y), 7, 255}; });
}

TEST_P(RhiConformanceTest, ReadbackRowOrderAndSubresources) {
  // A 3x2 texture (odd row length) written and read back: bytes in the same order, row 0 first.
  std::vector<uint8_t> small(3 * 2 * 4);
  for (size_t i = 0; i < small.size(); ++i) small[i] = uint8_t(i * 7 + 1);
  TextureHandle t = texture(Format::RGBA8, 3, 2, TextureUsage_Sampled);
  dev->writeTexture(t, 0, 0, small.data());
  EXPECT_EQ(read(t), small);

  std::vector<float> floats(3 * 2 * 4);
  for (size_t i = 0; i < floats.size(); ++i) floats[i] = float(i) * 0.5f - 3.0f;
  TextureHandle f = texture(Format::RGBA32F, 3, 2, TextureUsage_Sampled);
  dev->writeTexture(f, 0, 0, floats.data());
  std::vector<uint8_t> fb = read(f);
  ASSERT_EQ(fb.size(), floats.size() * 4);
  EXPECT_EQ(std::memcmp(fb.data(), floats.data(), fb.size()), 0);

  // Layer 2, mip 1 (2x1) of a 4x2 array with 3 layers and 2 mips.
  TextureDesc ad;
  ad.type = TextureType::Tex2DArray;
  ad.width = 4;
  ad.height = 2;
  ad.layers = 3;
  ad.mipLevels = 2;
  ad.usage = TextureUsage_Sampled;
  ad.label = "array";
  TextureHandle a = texture(ad);
  std::vector<uint8_t> mip1 = {1, 2, 3, 4, 5, 6, 7, 8};
  std::vector<uint8_t> layer0(4 * 2 * 4, 0x5A);
  dev->writeTexture(a, 2, 1, mip1.data());
  dev->writeTexture(a, 0, 0, layer0.data());
  EXPECT_EQ(read(a, 2, 1), mip1);
  EXPECT_EQ(read(a, 0, 0), layer0);
}

// ---------------------------------------------------------------------------------------------
// Winding and culling
// ---------------------------------------------------------------------------------------------
const char* kFacingFs = R"(#version 450
layout(location = 0) out vec4 o;
void main() { o = gl_FrontFacing ? vec4(0.0, 1.0, 0.0, 1.0) : vec4(1.0, 0.0, 0.0, 1.0); })";

TEST_P(RhiConformanceTest, FrontFaceAndCulling) {
  // Left half: rect drawn counter-clockwise as seen in the image; right half: clockwise.
  const auto left = ndcRect(0, 0, 8, 16, 16, 16), right = ndcRect(8, 0, 16, 16, 16, 16);
  const Px green{0, 255, 0, 255}, red{255, 0, 0, 255}, none{0, 0, 0, 0};
  struct Case {
    const char* name;
    FrontFace front;
    CullMode cull;
    Px expectLeft, expectRight;
  };
  const Case cases[] = {
      {"CCW front, cull back", FrontFace::CounterClockwise, CullMode::Back, green, none},
      {"CCW front, cull front", FrontFace::CounterClockwise, CullMode::Front, none, red},
      {"CCW front, no culling", FrontFace::CounterClockwise, CullMode::None, green, red},
      {"CW front, cull back", FrontFace::Clockwise, CullMode::Back, none, green},
      {"CW front, no culling", FrontFace::Clockwise, CullMode::None, red, green},
  };
  for (const Case& c : cases) {
    TextureHandle t = texture(Format::RGBA8, 16, 16);
    PipelineDesc d = rectDesc(Format::RGBA8, kFacingFs);
    d.raster.frontFace = c.front;
    d.raster.cull = c.cull;
    PipelineHandle p = pipeline(d);
    dev->beginPass(pass(t));
    dev->setPipeline(p);
    drawRect(left, {1, 1, 1, 1}, 0.5f, false);
    drawRect(right, {1, 1, 1, 1}, 0.5f, true);
    dev->endPass();
    expectRgba8Image(
        read(t), 16, 16, [&](uint32_t x, uint32_t) { return x < 8 ? c.expectLeft : c.expectRight; }, c.name);
  }
}

// ---------------------------------------------------------------------------------------------
// Depth
// ---------------------------------------------------------------------------------------------
// Left half at z = 0.25 (green) drawn first, then the whole target at z = 0.75 (red) with LESS:
// the nearer rect stays in front although it was drawn first. The depth read back must be
// `left` on the left half and `right` on the right.
void RhiConformanceTest::checkDepthTestLess(Format depthFormat, float left, float right) {
  TextureHandle c = texture(Format::RGBA8, 16, 16), d = texture(depthFormat, 16, 16);
  PipelineDesc pd = rectDesc(Format::RGBA8);
  pd.depthStencilFormat = depthFormat;
  pd.depthStencil.depthCompare = CompareOp::Less;
  pd.depthStencil.depthWrite = true;
  PipelineHandle p = pipeline(pd);
  dev->beginPass(pass(c, {0, 0, 0, 0}, d));
  dev->setPipeline(p);
  drawRect(ndcRect(0, 0, 8, 16, 16, 16), unorm(0, 255, 0, 255), 0.25f);
  drawRect(kFullNdc, unorm(255, 0, 0, 255), 0.75f);
  dev->endPass();
  expectRgba8Image(read(c), 16, 16, [](uint32_t x, uint32_t) {
    return x < 8 ? Px{0, 255, 0, 255} : Px{255, 0, 0, 255};
  });
  std::vector<uint8_t> depth = read(d, 0, 0, TextureAspect::Depth);
  ASSERT_EQ(depth.size(), 16u * 16 * 4);
  for (uint32_t y = 0; y < 16; ++y)
    for (uint32_t x = 0; x < 16; ++x)
      EXPECT_EQ(load<float>(depth, (y * 16 + x) * 4), x < 8 ? left : right) << "depth at " << x << ", " << y;
}

TEST_P(RhiConformanceTest, DepthTestLessD32F) { checkDepthTestLess(Format::D32F, 0.25f, 0.75f); }

TEST_P(RhiConformanceTest, DepthTestLessD24S8) {
  // Stored d24 = round(d * 16777215): 0x400000 and 12582911; read back as q / 16777215.
  const float left = d24(0.25), right = d24(0.75);
  EXPECT_EQ(left, static_cast<float>(4194304.0 / 16777215.0));
  EXPECT_EQ(right, static_cast<float>(12582911.0 / 16777215.0));
  checkDepthTestLess(Format::D24S8, left, right);
}

TEST_P(RhiConformanceTest, ViewportDepthRange) {
  // minDepth 0.25, maxDepth 0.75: window depth = 0.25 + 0.5 z. z = 0.25 -> 0.375, z = 0.875 -> 0.6875.
  TextureHandle c = texture(Format::RGBA8, 16, 16), d = texture(Format::D32F, 16, 16);
  PipelineDesc pd = rectDesc(Format::RGBA8);
  pd.depthStencilFormat = Format::D32F;
  pd.depthStencil.depthCompare = CompareOp::Always;
  pd.depthStencil.depthWrite = true;
  PipelineHandle p = pipeline(pd);
  dev->beginPass(pass(c, {0, 0, 0, 0}, d));
  dev->setPipeline(p);
  Viewport vp;
  vp.minDepth = 0.25f;
  vp.maxDepth = 0.75f;
  dev->setViewport(vp);
  drawRect(ndcRect(0, 0, 8, 16, 16, 16), unorm(0, 255, 0, 255), 0.25f);
  drawRect(ndcRect(8, 0, 16, 16, 16, 16), unorm(0, 0, 255, 255), 0.875f);
  dev->endPass();
  std::vector<uint8_t> depth = read(d, 0, 0, TextureAspect::Depth);
  ASSERT_EQ(depth.size(), 16u * 16 * 4);
  for (uint32_t y = 0; y < 16; ++y)
    for (uint32_t x = 0; x < 16; ++x)
      EXPECT_EQ(load<float>(depth, (y * 16 + x) * 4), x < 8 ? 0.375f : 0.6875f) << "depth at " << x << ", " << y;
}

TEST_P(RhiConformanceTest, ShadowSamplerCompare) {
  // Depth 0.25 on the left half, 0.75 on the right; sampled through sampler2DShadow with
  // LESS_EQUAL and reference 0.5: result = (0.5 <= depth) ? 1 : 0, so 0 left and 1 right. Once
  // with an explicit compare sampler, once with the null default (documented as LessEqual).
  TextureHandle c = texture(Format::RGBA8, 16, 16), d = texture(Format::D32F, 16, 16);
  PipelineDesc pd = rectDesc(Format::RGBA8);
  pd.depthStencilFormat = Format::D32F;
  pd.depthStencil.depthWrite = true;
  PipelineHandle write = pipeline(pd);
  dev->beginPass(pass(c, {0, 0, 0, 0}, d));
  dev->setPipeline(write);
  drawRect(ndcRect(0, 0, 8, 16, 16, 16), {1, 1, 1, 1}, 0.25f);
  drawRect(ndcRect(8, 0, 16, 16, 16, 16), {1, 1, 1, 1}, 0.75f);
  dev->endPass();

  SamplerDesc sd;
  sd.compareEnabled = true;
  sd.compare = CompareOp::LessEqual;
  SamplerHandle s = dev->createSampler(sd);
  ASSERT_TRUE(s);
  PipelineHandle p = pipeline(fullscreenDesc(Format::RGBA8, R"(#version 450
layout(set = 0, binding = 0) uniform sampler2DShadow tex;
layout(location = 0) out vec4 o;
void main() { o = vec4(texture(tex, vec3(gl_FragCoord.xy / 16.0, 0.5))); })"));
  for (SamplerHandle sampler : {s, SamplerHandle{}}) {
    TextureHandle out = texture(Format::RGBA8, 16, 16);
    ResourceBinding rb;
    rb.kind = BindingKind::SampledTexture;
    rb.texture = d;
    rb.sampler = sampler;
    dev->setBindings({&rb, 1});
    dev->beginPass(pass(out));
    dev->setPipeline(p);
    dev->draw(3);
    dev->endPass();
    expectRgba8Image(
        read(out), 16, 16,
        [](uint32_t x, uint32_t) {
          return x < 8 ? Px{0, 0, 0, 0} : Px{255, 255, 255, 255};
        },
        sampler ? "compare sampler" : "default sampler");
  }
}

TEST_P(RhiConformanceTest, StencilSampledThroughUsampler) {
  // Stencil written with REPLACE (0x11 left, 0xA5 right) is read back by a usampler2D bound to
  // the D24S8 texture, and by the stencil readback.
  TextureHandle c = texture(Format::RGBA8, 16, 16), d = texture(Format::D24S8, 16, 16);
  PipelineDesc pd = rectDesc(Format::RGBA8);
  pd.depthStencilFormat = Format::D24S8;
  pd.depthStencil.stencilEnabled = true;
  pd.depthStencil.front.pass = pd.depthStencil.back.pass = StencilOp::Replace;
  PipelineHandle mark = pipeline(pd);
  dev->beginPass(pass(c, {0, 0, 0, 0}, d));
  dev->setPipeline(mark);
  dev->setStencilReference(0x11);
  drawRect(ndcRect(0, 0, 8, 16, 16, 16), {1, 1, 1, 1});
  dev->setStencilReference(0xA5);
  drawRect(ndcRect(8, 0, 16, 16, 16, 16), {1, 1, 1, 1});
  dev->endPass();

  TextureHandle out = texture(Format::R32_UINT, 16, 16);
  PipelineHandle p = pipeline(fullscreenDesc(Format::R32_UINT, R"(#version 450
layout(set = 0, binding = 0) uniform usampler2D stencil;
layout(location = 0) out uint o;
void main() { o = texelFetch(stencil, ivec2(gl_FragCoord.xy), 0).r; })"));
  ResourceBinding rb;
  rb.kind = BindingKind::SampledTexture;
  rb.texture = d;
  dev->setBindings({&rb, 1});
  drawFullscreen(p, out);
  std::vector<uint8_t> u = read(out), st = read(d, 0, 0, TextureAspect::Stencil);
  ASSERT_EQ(u.size(), 16u * 16 * 4);
  ASSERT_EQ(st.size(), 16u * 16);
  for (uint32_t y = 0; y < 16; ++y)
    for (uint32_t x = 0; x < 16; ++x) {
      uint32_t want = x < 8 ? 0x11 : 0xA5;
      EXPECT_EQ(load<uint32_t>(u, (y * 16 + x) * 4), want) << "sampled stencil at " << x << ", " << y;
      EXPECT_EQ(uint32_t(st[y * 16 + x]), want) << "read-back stencil at " << x << ", " << y;
    }
}

// ---------------------------------------------------------------------------------------------
// Stencil
// ---------------------------------------------------------------------------------------------
TEST_P(RhiConformanceTest, StencilIncrementWrapAndClamp) {
  // Cleared to 254; three increments: wrap gives 254 -> 255 -> 0 -> 1, clamp stays at 255.
  TextureHandle c = texture(Format::RGBA8, 16, 16), d = texture(Format::D24S8, 16, 16);
  PipelineDesc pd = rectDesc(Format::RGBA8);
  pd.depthStencilFormat = Format::D24S8;
  pd.depthStencil.stencilEnabled = true;
  pd.depthStencil.front.pass = pd.depthStencil.back.pass = StencilOp::IncrementWrap;
  PipelineHandle wrap = pipeline(pd);
  pd.depthStencil.front.pass = pd.depthStencil.back.pass = StencilOp::IncrementClamp;
  PipelineHandle clamp = pipeline(pd);
  PassDesc ps = pass(c, {0, 0, 0, 0}, d);
  ps.depthStencil.clearStencil = 254;
  dev->beginPass(ps);
  dev->setPipeline(wrap);
  for (int i = 0; i < 3; ++i) drawRect(ndcRect(0, 0, 8, 16, 16, 16), {1, 1, 1, 1});
  dev->setPipeline(clamp);
  for (int i = 0; i < 3; ++i) drawRect(ndcRect(8, 0, 16, 16, 16, 16), {1, 1, 1, 1});
  dev->endPass();
  std::vector<uint8_t> s = read(d, 0, 0, TextureAspect::Stencil);
  ASSERT_EQ(s.size(), 16u * 16);
  for (uint32_t y = 0; y < 16; ++y)
    for (uint32_t x = 0; x < 16; ++x) EXPECT_EQ(int(s[y * 16 + x]), x < 8 ? 1 : 255) << "stencil at " << x << ", " << y;
}

TEST_P(RhiConformanceTest, StencilTwoSidedAndEqualTest) {
  // Cleared to 5. Front faces increment, back faces decrement: the left rect (counter-clockwise,
  // front) leaves 6, the right rect (clockwise, back) 4. Then EQUAL 6 lets green through on the
  // left only.
  TextureHandle c = texture(Format::RGBA8, 16, 16), d = texture(Format::D24S8, 16, 16);
  PipelineDesc pd = rectDesc(Format::RGBA8);
  pd.depthStencilFormat = Format::D24S8;
  pd.depthStencil.stencilEnabled = true;
  pd.depthStencil.front.pass = StencilOp::IncrementClamp;
  pd.depthStencil.back.pass = StencilOp::DecrementClamp;
  pd.colorTargets[0].writeMask = 0;
  PipelineHandle mark = pipeline(pd);
  pd.depthStencil.front = pd.depthStencil.back =
      StencilFaceState{CompareOp::Equal, StencilOp::Keep, StencilOp::Keep, StencilOp::Keep};
  pd.colorTargets[0].writeMask = ColorMask_All;
  PipelineHandle test = pipeline(pd);
  PassDesc ps = pass(c, {0, 0, 0, 0}, d);
  ps.depthStencil.clearStencil = 5;
  dev->beginPass(ps);
  dev->setPipeline(mark);
  drawRect(ndcRect(0, 0, 8, 16, 16, 16), {1, 1, 1, 1}, 0.5f, false);
  drawRect(ndcRect(8, 0, 16, 16, 16, 16), {1, 1, 1, 1}, 0.5f, true);
  dev->setPipeline(test);
  dev->setStencilReference(6);
  drawRect(kFullNdc, unorm(0, 255, 0, 255));
  dev->endPass();
  expectRgba8Image(read(c), 16, 16, [](uint32_t x, uint32_t) { return x < 8 ? Px{0, 255, 0, 255} : Px{0, 0, 0, 0}; });
  std::vector<uint8_t> s = read(d, 0, 0, TextureAspect::Stencil);
  ASSERT_EQ(s.size(), 16u * 16);
  for (uint32_t y = 0; y < 16; ++y)
    for (uint32_t x = 0; x < 16; ++x) EXPECT_EQ(int(s[y * 16 + x]), x < 8 ? 6 : 4) << "stencil at " << x << ", " << y;
}

// ---------------------------------------------------------------------------------------------
// Multiple render targets and blending
// ---------------------------------------------------------------------------------------------
TEST_P(RhiConformanceTest, MultipleRenderTargets) {
  TextureHandle t0 = texture(Format::RGBA8, 4, 4), t1 = texture(Format::RGBA32F, 4, 4),
                t2 = texture(Format::R32_UINT, 4, 4), t3 = texture(Format::RG16_FLOAT, 4, 4);
  PipelineDesc d = fullscreenDesc(Format::RGBA8, R"(#version 450
layout(location = 0) out vec4 o0;
layout(location = 1) out vec4 o1;
layout(location = 2) out uint o2;
layout(location = 3) out vec2 o3;
void main() {
  o0 = vec4(51.0, 102.0, 153.0, 255.0) / 255.0;
  o1 = vec4(1.5, -2.25, 1.0e10, 0.1);
  o2 = 0xDEADBEEFu;
  o3 = vec2(0.5, -3.0);
})");
  d.colorTargetCount = 4;
  d.colorTargets[1].format = Format::RGBA32F;
  d.colorTargets[2].format = Format::R32_UINT;
  d.colorTargets[3].format = Format::RG16_FLOAT;
  PipelineHandle p = pipeline(d);
  PassDesc ps = pass(t0);
  ps.colors[1].texture = t1;
  ps.colors[2].texture = t2;
  ps.colors[3].texture = t3;
  dev->beginPass(ps);
  dev->setPipeline(p);
  dev->draw(3);
  dev->endPass();
  expectRgba8Image(
      read(t0), 4, 4,
      [](uint32_t, uint32_t) {
        return Px{51, 102, 153, 255};
      },
      "RGBA8");
  std::vector<uint8_t> f = read(t1), u = read(t2), h = read(t3);
  ASSERT_EQ(f.size(), 16u * 16);
  ASSERT_EQ(u.size(), 16u * 4);
  ASSERT_EQ(h.size(), 16u * 4);
  for (uint32_t i = 0; i < 16; ++i) {
    EXPECT_EQ(rgba32f(f, 4, i % 4, i / 4), (Pf{1.5f, -2.25f, 1.0e10f, 0.1f})) << "RGBA32F texel " << i;
    EXPECT_EQ(load<uint32_t>(u, i * 4), 0xDEADBEEFu) << "R32_UINT texel " << i;
    // Half floats: 0.5 = 0x3800, -3.0 = 0xC200.
    EXPECT_EQ(load<uint16_t>(h, i * 4), 0x3800) << "RG16_FLOAT texel " << i;
    EXPECT_EQ(load<uint16_t>(h, i * 4 + 2), 0xC200) << "RG16_FLOAT texel " << i;
  }
}

TEST_P(RhiConformanceTest, BlendAdd) {
  // dst (64, 100, 0, 128) + src (64, 200, 10, 127), factors ONE/ONE: (128, 255 saturated, 10, 255).
  TextureHandle t = texture(Format::RGBA8, 4, 4);
  PipelineDesc d = rectDesc(Format::RGBA8);
  BlendState& b = d.colorTargets[0].blend;
  b.enabled = true;
  b.srcColor = b.dstColor = b.srcAlpha = b.dstAlpha = BlendFactor::One;
  PipelineHandle p = pipeline(d);
  dev->beginPass(pass(t, unorm(64, 100, 0, 128)));
  dev->setPipeline(p);
  drawRect(kFullNdc, unorm(64, 200, 10, 127));
  dev->endPass();
  expectRgba8Image(read(t), 4, 4, [](uint32_t, uint32_t) { return Px{128, 255, 10, 255}; });
}

TEST_P(RhiConformanceTest, BlendMinMax) {
  // dst (100, 200, 50, 255), src (150, 100, 50, 0); the factors (ZERO) are ignored by MIN/MAX.
  for (BlendOp op : {BlendOp::Min, BlendOp::Max}) {
    TextureHandle t = texture(Format::RGBA8, 4, 4);
    PipelineDesc d = rectDesc(Format::RGBA8);
    BlendState& b = d.colorTargets[0].blend;
    b.enabled = true;
    b.srcColor = b.dstColor = b.srcAlpha = b.dstAlpha = BlendFactor::Zero;
    b.colorOp = b.alphaOp = op;
    PipelineHandle p = pipeline(d);
    dev->beginPass(pass(t, unorm(100, 200, 50, 255)));
    dev->setPipeline(p);
    drawRect(kFullNdc, unorm(150, 100, 50, 0));
    dev->endPass();
    const Px want = op == BlendOp::Min ? Px{100, 100, 50, 0} : Px{150, 200, 50, 255};
    expectRgba8Image(
        read(t), 4, 4, [&](uint32_t, uint32_t) { return want; }, op == BlendOp::Min ? "MIN" : "MAX");
  }
}

TEST_P(RhiConformanceTest, BlendConstantColorPacking) {
  // Pixel k = 16y + x. Pass i (0..3) writes b_i << 6 with b_i = (k >> 2i) & 3, blended ADD with
  // (ONE, CONSTANT_COLOR) and constant 0.25: dst = src + dst / 4. After four passes every
  // channel holds b0 | b1 << 2 | b2 << 4 | b3 << 6 = k.
  TextureHandle t = texture(Format::RGBA8, 16, 16);
  PipelineDesc d = fullscreenDesc(Format::RGBA8, R"(#version 450
layout(push_constant) uniform PC { int shift; } pc;
layout(location = 0) out vec4 o;
void main() {
  int k = int(gl_FragCoord.y) * 16 + int(gl_FragCoord.x);
  o = vec4(float(((k >> pc.shift) & 3) << 6) / 255.0);
})");
  BlendState& b = d.colorTargets[0].blend;
  b.enabled = true;
  b.srcColor = b.srcAlpha = BlendFactor::One;
  b.dstColor = b.dstAlpha = BlendFactor::ConstantColor;
  PipelineHandle p = pipeline(d);
  for (int i = 0; i < 4; ++i) {
    PassDesc ps = pass(t);
    ps.colors[0].load = i == 0 ? LoadOp::Clear : LoadOp::Load;
    dev->beginPass(ps);
    dev->setPipeline(p);
    dev->setBlendConstant({0.25f, 0.25f, 0.25f, 0.25f});
    int32_t shift = 2 * i;
    dev->pushConstants(&shift, sizeof(shift));
    dev->draw(3);
    dev->endPass();
  }
  expectRgba8Image(read(t), 16, 16, [](uint32_t x, uint32_t y) {
    int k = int(y * 16 + x);
    return Px{k, k, k, k};
  });
}

TEST_P(RhiConformanceTest, ColorWriteMask) {
  // Cleared to (10, 20, 30, 40), drawn (200, 200, 200, 200): target 0 masks R|B, target 1 G|A.
  TextureHandle a = texture(Format::RGBA8, 4, 4), b = texture(Format::RGBA8, 4, 4);
  PipelineDesc d = rectDesc(Format::RGBA8, R"(#version 450
layout(location = 0) in vec4 vColor;
layout(location = 0) out vec4 o0;
layout(location = 1) out vec4 o1;
void main() { o0 = vColor; o1 = vColor; })");
  d.colorTargetCount = 2;
  d.colorTargets[1].format = Format::RGBA8;
  d.colorTargets[0].writeMask = ColorMask_R | ColorMask_B;
  d.colorTargets[1].writeMask = ColorMask_G | ColorMask_A;
  PipelineHandle p = pipeline(d);
  PassDesc ps = pass(a, unorm(10, 20, 30, 40));
  ps.colors[1].texture = b;
  ps.colors[1].clearColor = unorm(10, 20, 30, 40);
  dev->beginPass(ps);
  dev->setPipeline(p);
  drawRect(kFullNdc, unorm(200, 200, 200, 200));
  dev->endPass();
  expectRgba8Image(
      read(a), 4, 4,
      [](uint32_t, uint32_t) {
        return Px{200, 20, 200, 40};
      },
      "R|B");
  expectRgba8Image(
      read(b), 4, 4,
      [](uint32_t, uint32_t) {
        return Px{10, 200, 30, 200};
      },
      "G|A");
}

// ---------------------------------------------------------------------------------------------
// MSAA
// ---------------------------------------------------------------------------------------------
TEST_P(RhiConformanceTest, Msaa4xResolve) {
  // A rect over x in [0, 4.5) pixels. Every 4x sample pattern has two samples left of a pixel's
  // centre line, so column 4 is half covered and resolves to half the colour; columns 0-3 are
  // fully covered, 5-7 empty. Colour (200, 100, 40, 200) halves exactly.
  TextureHandle msaa = texture(Format::RGBA8, 8, 8, TextureUsage_RenderTarget, nullptr, 4);
  TextureHandle resolved = texture(Format::RGBA8, 8, 8);
  PipelineDesc d = rectDesc(Format::RGBA8);
  d.samples = 4;
  PipelineHandle p = pipeline(d);
  PassDesc ps = pass(msaa);
  ps.colors[0].resolveTarget = resolved;
  dev->beginPass(ps);
  dev->setPipeline(p);
  drawRect(ndcRect(0, 0, 4.5f, 8, 8, 8), unorm(200, 100, 40, 200));
  dev->endPass();
  expectRgba8Image(read(resolved), 8, 8, [](uint32_t x, uint32_t) {
    if (x < 4) return Px{200, 100, 40, 200};
    if (x == 4) return Px{100, 50, 20, 100};
    return Px{0, 0, 0, 0};
  });
}

// ---------------------------------------------------------------------------------------------
// Texture views
// ---------------------------------------------------------------------------------------------
TEST_P(RhiConformanceTest, TextureViewSampledAsOtherFormat) {
  // RGBA8 bytes 12 34 56 78: through an RG16_UNORM view (0x3412, 0x7856) / 65535, through an
  // R32_UINT view 0x78563412 (little-endian reinterpretation).
  const uint8_t bytes[4] = {0x12, 0x34, 0x56, 0x78};
  TextureHandle parent = texture(Format::RGBA8, 1, 1, TextureUsage_Sampled, bytes);
  TextureViewDesc vd;
  vd.parent = parent;
  vd.format = Format::RG16_UNORM;
  vd.label = "rg16 view";
  TextureHandle rg16 = dev->createTextureView(vd);
  vd.format = Format::R32_UINT;
  vd.label = "r32ui view";
  TextureHandle r32 = dev->createTextureView(vd);
  ASSERT_TRUE(rg16);
  ASSERT_TRUE(r32);

  TextureHandle outF = texture(Format::RGBA32F, 1, 1), outU = texture(Format::R32_UINT, 1, 1);
  PipelineHandle pf = pipeline(fullscreenDesc(Format::RGBA32F, R"(#version 450
layout(set = 0, binding = 0) uniform sampler2D tex;
layout(location = 0) out vec4 o;
void main() { o = texelFetch(tex, ivec2(0), 0); })"));
  PipelineHandle pu = pipeline(fullscreenDesc(Format::R32_UINT, R"(#version 450
layout(set = 0, binding = 1) uniform usampler2D tex;
layout(location = 0) out uint o;
void main() { o = texelFetch(tex, ivec2(0), 0).r; })"));
  ResourceBinding b[2];
  b[0].binding = 0;
  b[0].kind = BindingKind::SampledTexture;
  b[0].texture = rg16;
  b[1].binding = 1;
  b[1].kind = BindingKind::SampledTexture;
  b[1].texture = r32;
  dev->setBindings(b);
  drawFullscreen(pf, outF);
  drawFullscreen(pu, outU);
  Pf v = rgba32f(read(outF), 1, 0, 0);
  EXPECT_NEAR(v[0], 0x3412 / 65535.0, 1e-7);
  EXPECT_NEAR(v[1], 0x7856 / 65535.0, 1e-7);
  EXPECT_EQ(v[2], 0.0f);
  EXPECT_EQ(v[3], 1.0f);
  EXPECT_EQ(load<uint32_t>(read(outU), 0), 0x78563412u);
  dev->destroy(rg16);
  dev->destroy(r32);
}

TEST_P(RhiConformanceTest, TextureViewRenderTarget) {
  // Rendering (0x1234, 0x5678) / 65535 through an RG16_UNORM view of RGBA8 storage leaves the
  // bytes 34 12 78 56 in the parent.
  TextureHandle parent = texture(Format::RGBA8, 2, 2);
  TextureViewDesc vd;
  vd.parent = parent;
  vd.format = Format::RG16_UNORM;
  TextureHandle view = dev->createTextureView(vd);
  ASSERT_TRUE(view);
  PipelineHandle p = pipeline(fullscreenDesc(Format::RG16_UNORM, R"(#version 450
layout(location = 0) out vec4 o;
void main() { o = vec4(4660.0 / 65535.0, 22136.0 / 65535.0, 0.0, 1.0); })"));
  drawFullscreen(p, view);
  expectRgba8Image(read(parent), 2, 2, [](uint32_t, uint32_t) { return Px{0x34, 0x12, 0x78, 0x56}; });
  dev->destroy(view);
}

// ---------------------------------------------------------------------------------------------
// Compute
// ---------------------------------------------------------------------------------------------
TEST_P(RhiConformanceTest, ComputeStorageBuffer) {
  // 2 groups of 64: out[i] = 3i + 5 (multiplier and addend from push constants).
  ComputePipelineHandle p = computePipeline(R"(#version 450
layout(local_size_x = 64) in;
layout(push_constant) uniform PC { uint mul; uint add; } pc;
layout(set = 0, binding = 2) buffer Out { uint v[]; } o;
void main() { uint i = gl_GlobalInvocationID.x; o.v[i] = i * pc.mul + pc.add; })");
  BufferHandle b = buffer(128 * 4 + 16);
  ResourceBinding rb = storageBuffer(2, b);
  dev->setComputePipeline(p);
  dev->setBindings({&rb, 1});
  uint32_t pc[2] = {3, 5};
  dev->pushConstants(pc, sizeof(pc));
  dev->dispatch(2);
  std::vector<uint8_t> out = dev->readBuffer(b, 0, 128 * 4 + 16);
  ASSERT_EQ(out.size(), 128u * 4 + 16);
  for (uint32_t i = 0; i < 128; ++i) EXPECT_EQ(load<uint32_t>(out, i * 4), 3 * i + 5) << "element " << i;
  for (uint32_t i = 128; i < 132; ++i) EXPECT_EQ(load<uint32_t>(out, i * 4), 0u) << "past the dispatch " << i;
}

// Subgroup size control: with a required size and full subgroups, every invocation sees that
// size, and every subgroup has that many invocations active. Each power of two the device offers.
TEST_P(RhiConformanceTest, RequiredSubgroupSizeWithFullSubgroups) {
  const Capabilities& caps = dev->info().caps;
  if (!caps.subgroupSizeControl) GTEST_SKIP() << dev->info().backend << " has no subgroup size control (OpenGL has none)";
  ASSERT_GE(caps.minSubgroupSize, 1u);
  ASSERT_LE(caps.minSubgroupSize, caps.maxSubgroupSize);
  ASSERT_LE(caps.maxSubgroupSize, 128u);  // Vulkan's bound: a local size of 128 fills whole subgroups
  std::printf("subgroup sizes %u to %u on %s\n", caps.minSubgroupSize, caps.maxSubgroupSize, dev->info().renderer.c_str());
  ShaderHandle cs = parity::test::makeShader(*dev, ShaderStage::Compute, R"(#version 450
#extension GL_KHR_shader_subgroup_arithmetic : require
layout(local_size_x = 128) in;
layout(std430, binding = 0) buffer Out { uint size[128]; uint members[128]; } o;
void main() {
  o.size[gl_LocalInvocationIndex] = gl_SubgroupSize;
  o.members[gl_LocalInvocationIndex] = subgroupAdd(1u);
})");
  ASSERT_TRUE(cs);
  for (uint32_t size = caps.minSubgroupSize; size <= caps.maxSubgroupSize; size *= 2) {
    SCOPED_TRACE("requiredSubgroupSize " + std::to_string(size));
    ComputePipelineDesc d;
    d.computeShader = cs;
    d.requiredSubgroupSize = size;
    d.fullSubgroups = true;
    ComputePipelineHandle p = dev->createComputePipeline(d);
    ASSERT_TRUE(p);
    BufferHandle out = buffer(256 * 4);
    ResourceBinding rb = storageBuffer(0, out);
    dev->setComputePipeline(p);
    dev->setBindings({&rb, 1});
    dev->dispatch(1);
    std::vector<uint8_t> result = dev->readBuffer(out, 0, 256 * 4);
    for (uint32_t i = 0; i < 128; ++i) {
      EXPECT_EQ(load<uint32_t>(result, i * 4), size) << "invocation " << i;
      EXPECT_EQ(load<uint32_t>(result, 512 + i * 4), size) << "invocation " << i;
    }
    dev->destroy(p);
  }
}

TEST_P(RhiConformanceTest, LdexpTakesA64BitExponent) {
  // ldexp(0.5, e) for 64-bit e: the backends narrow e to 32 bits (rhi/spirv_lowering.h), which
  // must clamp, not truncate (the low words of these exponents are 3, 5, 2 and -1). Only exponents
  // that underflow: an overflowing ldexp is undefined in GLSL and SPIR-V.
  // In assembly: this glslang has no ldexp overload with a 64-bit exponent.
  CompiledShader cs = assembleSpirv(R"(
OpCapability Shader
OpCapability Int64
%glsl = OpExtInstImport "GLSL.std.450"
OpMemoryModel Logical GLSL450
OpEntryPoint GLCompute %main "main" %index
OpExecutionMode %main LocalSize 4 1 1
OpDecorate %index BuiltIn LocalInvocationIndex
OpDecorate %longs ArrayStride 8
OpDecorate %floats ArrayStride 4
OpMemberDecorate %Exponents 0 Offset 0
OpMemberDecorate %Results 0 Offset 0
OpDecorate %Exponents Block
OpDecorate %Results Block
OpDecorate %e DescriptorSet 0
OpDecorate %e Binding 0
OpDecorate %r DescriptorSet 0
OpDecorate %r Binding 1
%void = OpTypeVoid
%fn = OpTypeFunction %void
%uint = OpTypeInt 32 0
%int = OpTypeInt 32 1
%long = OpTypeInt 64 1
%float = OpTypeFloat 32
%uint_4 = OpConstant %uint 4
%int_0 = OpConstant %int 0
%half = OpConstant %float 0.5
%longs = OpTypeArray %long %uint_4
%floats = OpTypeArray %float %uint_4
%Exponents = OpTypeStruct %longs
%Results = OpTypeStruct %floats
%ptr_Exponents = OpTypePointer StorageBuffer %Exponents
%ptr_Results = OpTypePointer StorageBuffer %Results
%ptr_long = OpTypePointer StorageBuffer %long
%ptr_float = OpTypePointer StorageBuffer %float
%ptr_index = OpTypePointer Input %uint
%e = OpVariable %ptr_Exponents StorageBuffer
%r = OpVariable %ptr_Results StorageBuffer
%index = OpVariable %ptr_index Input
%main = OpFunction %void None %fn
%entry = OpLabel
%i = OpLoad %uint %index
%exponentAt = OpAccessChain %ptr_long %e %int_0 %i
%exponent = OpLoad %long %exponentAt
%result = OpExtInst %float %glsl Ldexp %half %exponent
%resultAt = OpAccessChain %ptr_float %r %int_0 %i
OpStore %resultAt %result
OpReturn
OpFunctionEnd
)", "ldexp64", 1, 3);
  ASSERT_TRUE(cs.ok()) << cs.error;
  ShaderDesc sd;
  sd.stage = ShaderStage::Compute;
  sd.spirv = cs.spirv;
  sd.label = "ldexp64";
  ComputePipelineDesc d;
  d.computeShader = dev->createShader(sd);
  ComputePipelineHandle p = dev->createComputePipeline(d);
  ASSERT_TRUE(p);
  const int64_t exponents[4] = {3, -9223372036854775803LL, -4294967294LL, -4294967297LL};
  BufferHandle in = buffer(sizeof(exponents)), out = buffer(16);
  dev->writeBuffer(in, 0, exponents, sizeof(exponents));
  ResourceBinding rb[2];
  rb[0] = storageBuffer(0, in);
  rb[1] = storageBuffer(1, out);
  dev->setComputePipeline(p);
  dev->setBindings({rb, 2});
  dev->dispatch(1);
  std::vector<uint8_t> result = dev->readBuffer(out, 0, 16);
  ASSERT_EQ(result.size(), 16u);
  EXPECT_EQ(load<float>(result, 0), 4.0f);
  EXPECT_EQ(load<float>(result, 4), 0.0f);
  EXPECT_EQ(load<float>(result, 8), 0.0f);
  EXPECT_EQ(load<float>(result, 12), 0.0f);
  std::vector<std::string> notes = dev->takeNotes();
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("64-bit exponents narrowed to 32 bits"), std::string::npos) << notes[0];
}

TEST_P(RhiConformanceTest, TrinaryMinMaxOfEveryKind) {
  // GL_AMD_shader_trinary_minmax's min3, max3 and mid3 of floats, ints and uints, every operand
  // order: the backends expand them into min and max (rhi/spirv_lowering.h) for devices without
  // VK_AMD_shader_trinary_minmax. Each wrong expansion (an operand dropped, min for max, the mid
  // of two) gives another value for some order.
  ComputePipelineHandle p = computePipeline(R"(#version 450
#extension GL_AMD_shader_trinary_minmax : require
layout(local_size_x = 6) in;
layout(std430, set = 0, binding = 0) buffer B { vec3 f[6]; ivec3 i[6]; uvec3 u[6]; } buf;
void main() {
  const ivec3 orders[6] = ivec3[](ivec3(0, 1, 2), ivec3(0, 2, 1), ivec3(1, 0, 2), ivec3(1, 2, 0), ivec3(2, 0, 1), ivec3(2, 1, 0));
  uint n = gl_LocalInvocationIndex;
  ivec3 o = orders[n];
  vec3 fv = vec3(o) * 1.5 - 1.0;  // -1, 0.5, 2 in some order
  ivec3 iv = o * 7 - 5;           // -5, 2, 9
  uvec3 uv = uvec3(o) * 3u + 1u;  // 1, 4, 7
  buf.f[n] = vec3(min3(fv.x, fv.y, fv.z), max3(fv.x, fv.y, fv.z), mid3(fv.x, fv.y, fv.z));
  buf.i[n] = ivec3(min3(iv.x, iv.y, iv.z), max3(iv.x, iv.y, iv.z), mid3(iv.x, iv.y, iv.z));
  buf.u[n] = uvec3(min3(uv.x, uv.y, uv.z), max3(uv.x, uv.y, uv.z), mid3(uv.x, uv.y, uv.z));
}
)");
  ASSERT_TRUE(p);
  BufferHandle out = buffer(3 * 6 * 16);
  ResourceBinding rb = storageBuffer(0, out);
  dev->setComputePipeline(p);
  dev->setBindings({&rb, 1});
  dev->dispatch(1);
  std::vector<uint8_t> r = dev->readBuffer(out, 0, 3 * 6 * 16);
  ASSERT_EQ(r.size(), 288u);
  for (size_t n = 0; n < 6; ++n) {
    SCOPED_TRACE("order " + std::to_string(n));
    EXPECT_EQ(load<float>(r, n * 16), -1.0f);
    EXPECT_EQ(load<float>(r, n * 16 + 4), 2.0f);
    EXPECT_EQ(load<float>(r, n * 16 + 8), 0.5f);
    EXPECT_EQ(load<int32_t>(r, 96 + n * 16), -5);
    EXPECT_EQ(load<int32_t>(r, 96 + n * 16 + 4), 9);
    EXPECT_EQ(load<int32_t>(r, 96 + n * 16 + 8), 2);
    EXPECT_EQ(load<uint32_t>(r, 192 + n * 16), 1u);
    EXPECT_EQ(load<uint32_t>(r, 192 + n * 16 + 4), 7u);
    EXPECT_EQ(load<uint32_t>(r, 192 + n * 16 + 8), 4u);
  }
  std::vector<std::string> notes = dev->takeNotes();
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("9 min3/max3/mid3 of SPV_AMD_shader_trinary_minmax expanded"), std::string::npos) << notes[0];
  dev->destroy(p);
}

TEST_P(RhiConformanceTest, ComputeStd430Layout) {
  // std430 offsets: a 0, b 16, b2 28 (packed after the vec3), c 32, d 40 (stride 4), e 64,
  // m 80 (columns 16 apart), f 128, g 144; struct stride 160; tail 320.
  ComputePipelineHandle p = computePipeline(R"(#version 450
layout(local_size_x = 1) in;
struct S { float a; vec3 b; float b2; vec2 c; float d[3]; vec4 e; mat3 m; int f; vec3 g; };
layout(std430, set = 0, binding = 0) buffer B { S s[2]; uint tail; } buf;
void main() {
  for (int i = 0; i < 2; ++i) {
    float o = float(i) * 100.0;
    buf.s[i].a = 1.0 + o;
    buf.s[i].b = vec3(2.0, 3.0, 4.0) + o;
    buf.s[i].b2 = 5.0 + o;
    buf.s[i].c = vec2(6.0, 7.0) + o;
    buf.s[i].d[0] = 8.0 + o;
    buf.s[i].d[1] = 9.0 + o;
    buf.s[i].d[2] = 10.0 + o;
    buf.s[i].e = vec4(11.0, 12.0, 13.0, 14.0) + o;
    buf.s[i].m = mat3(vec3(15.0, 16.0, 17.0) + o, vec3(18.0, 19.0, 20.0) + o, vec3(21.0, 22.0, 23.0) + o);
    buf.s[i].f = -24 - i;
    buf.s[i].g = vec3(25.0, 26.0, 27.0) + o;
  }
  buf.tail = 0xC0FFEEu;
})");
  std::vector<uint8_t> init(384, 0xCC);
  BufferHandle b = buffer(init.size(), init.data());
  ResourceBinding rb = storageBuffer(0, b);
  dev->setComputePipeline(p);
  dev->setBindings({&rb, 1});
  dev->dispatch(1);
  std::vector<uint8_t> out = dev->readBuffer(b, 0, init.size());
  ASSERT_EQ(out.size(), init.size());
  for (int i = 0; i < 2; ++i) {
    const size_t base = 160 * i;
    const float o = 100.0f * i;
    auto f = [&](size_t off) { return load<float>(out, base + off); };
    EXPECT_EQ(f(0), 1 + o) << "a";
    EXPECT_EQ(f(16), 2 + o) << "b.x";
    EXPECT_EQ(f(20), 3 + o) << "b.y";
    EXPECT_EQ(f(24), 4 + o) << "b.z";
    EXPECT_EQ(f(28), 5 + o) << "b2";
    EXPECT_EQ(f(32), 6 + o) << "c.x";
    EXPECT_EQ(f(36), 7 + o) << "c.y";
    EXPECT_EQ(f(40), 8 + o) << "d[0]";
    EXPECT_EQ(f(44), 9 + o) << "d[1]";
    EXPECT_EQ(f(48), 10 + o) << "d[2]";
    for (int k = 0; k < 4; ++k) EXPECT_EQ(f(64 + 4 * k), 11 + k + o) << "e[" << k << "]";
    for (int col = 0; col < 3; ++col)
      for (int row = 0; row < 3; ++row)
        EXPECT_EQ(f(80 + 16 * col + 4 * row), 15 + 3 * col + row + o) << "m[" << col << "][" << row << "]";
    EXPECT_EQ(load<int32_t>(out, base + 128), -24 - i) << "f";
    for (int k = 0; k < 3; ++k) EXPECT_EQ(f(144 + 4 * k), 25 + k + o) << "g[" << k << "]";
  }
  EXPECT_EQ(load<uint32_t>(out, 320), 0xC0FFEEu) << "tail";
  for (size_t i = 324; i < out.size(); ++i) EXPECT_EQ(out[i], 0xCC) << "byte " << i << " past the block";
}

TEST_P(RhiConformanceTest, ComputeImageStore) {
  // imageStore at texel (x, y): rgba8 (17x, 34y, 3, 255) / 255 and r32ui 1000x + y.
  TextureHandle a = texture(Format::RGBA8, 4, 4, TextureUsage_Storage | TextureUsage_Sampled);
  TextureHandle b = texture(Format::R32_UINT, 4, 4, TextureUsage_Storage | TextureUsage_Sampled);
  ComputePipelineHandle p = computePipeline(R"(#version 450
layout(local_size_x = 4, local_size_y = 4) in;
layout(set = 0, binding = 0, rgba8) uniform writeonly image2D img;
layout(set = 0, binding = 1, r32ui) uniform writeonly uimage2D uimg;
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  imageStore(img, p, vec4(float(17 * p.x), float(34 * p.y), 3.0, 255.0) / 255.0);
  imageStore(uimg, p, uvec4(uint(1000 * p.x + p.y)));
})");
  ResourceBinding rb[2];
  rb[0].binding = 0;
  rb[0].kind = BindingKind::StorageTexture;
  rb[0].texture = a;
  rb[1].binding = 1;
  rb[1].kind = BindingKind::StorageTexture;
  rb[1].texture = b;
  dev->setComputePipeline(p);
  dev->setBindings(rb);
  dev->dispatch(1);
  expectRgba8Image(read(a), 4, 4, [](uint32_t x, uint32_t y) { return Px{int(17 * x), int(34 * y), 3, 255}; });
  std::vector<uint8_t> u = read(b);
  ASSERT_EQ(u.size(), 64u);
  for (uint32_t y = 0; y < 4; ++y)
    for (uint32_t x = 0; x < 4; ++x) EXPECT_EQ(load<uint32_t>(u, (y * 4 + x) * 4), 1000 * x + y) << x << ", " << y;
}

// ---------------------------------------------------------------------------------------------
// Vertex input, indexed and instanced draws
// ---------------------------------------------------------------------------------------------
const char* kVertexColorVs = R"(#version 450
layout(location = 0) in vec2 pos;
layout(location = 1) in vec4 col;
layout(location = 0) out vec4 vColor;
void main() { gl_Position = vec4(pos, 0.5, 1.0); vColor = col; })";

struct ColoredVertex {
  float x, y;
  uint8_t rgba[4];
};
static_assert(sizeof(ColoredVertex) == 12);

TEST_P(RhiConformanceTest, IndexedDraw) {
  // Quad A (vertices 0-3) covers the left half in red, quad B (4-7) the right half in green.
  // 16-bit indices {0,1,2, 2,1,3}: A with vertexOffset 0, B with vertexOffset 4. 32-bit indices
  // with firstIndex 3 draw A again into a second target.
  const ColoredVertex v[8] = {
      {-1, -1, {255, 0, 0, 255}}, {-1, 1, {255, 0, 0, 255}}, {0, -1, {255, 0, 0, 255}}, {0, 1, {255, 0, 0, 255}},
      {0, -1, {0, 255, 0, 255}},  {0, 1, {0, 255, 0, 255}},  {1, -1, {0, 255, 0, 255}}, {1, 1, {0, 255, 0, 255}},
  };
  const uint16_t idx16[6] = {0, 1, 2, 2, 1, 3};
  const uint32_t idx32[9] = {7, 7, 7, 0, 1, 2, 2, 1, 3};
  BufferHandle vb = buffer(sizeof(v), v, BufferUsage_Vertex);
  BufferHandle ib16 = buffer(sizeof(idx16), idx16, BufferUsage_Index);
  BufferHandle ib32 = buffer(sizeof(idx32), idx32, BufferUsage_Index);
  PipelineDesc d;
  d.vertexShader = shader(ShaderStage::Vertex, kVertexColorVs);
  d.fragmentShader = shader(ShaderStage::Fragment, kColorFs);
  d.attributeCount = 2;
  d.attributes[0] = {0, VertexFormat::Float2, 0, 0};
  d.attributes[1] = {1, VertexFormat::UByte4Norm, 8, 0};
  d.vertexBuffers[0].stride = sizeof(ColoredVertex);
  d.colorTargetCount = 1;
  d.colorTargets[0].format = Format::RGBA8;
  PipelineHandle p = pipeline(d);
  TextureHandle a = texture(Format::RGBA8, 16, 16), b = texture(Format::RGBA8, 16, 16);
  dev->beginPass(pass(a));
  dev->setPipeline(p);
  dev->setVertexBuffer(0, vb);
  dev->setIndexBuffer(ib16, IndexType::UInt16);
  dev->drawIndexed(6, 1, 0, 0);
  dev->drawIndexed(6, 1, 0, 4);
  dev->endPass();
  dev->beginPass(pass(b));
  dev->setPipeline(p);
  dev->setVertexBuffer(0, vb);
  dev->setIndexBuffer(ib32, IndexType::UInt32);
  dev->drawIndexed(6, 1, 3, 0);
  dev->endPass();
  expectRgba8Image(
      read(a), 16, 16,
      [](uint32_t x, uint32_t) {
        return x < 8 ? Px{255, 0, 0, 255} : Px{0, 255, 0, 255};
      },
      "uint16, vertexOffset");
  expectRgba8Image(
      read(b), 16, 16,
      [](uint32_t x, uint32_t) {
        return x < 8 ? Px{255, 0, 0, 255} : Px{0, 0, 0, 0};
      },
      "uint32, firstIndex");
}

TEST_P(RhiConformanceTest, InstancedDraw) {
  // A unit quad (slot 0, per vertex) placed per instance (slot 1: offset + colour). Instance i
  // covers quadrant i (0 top-left, 1 top-right, 2 bottom-left, 3 bottom-right). Drawn with
  // firstInstance 1 and 3 instances: quadrant 0 stays empty. Alpha = 50 * gl_InstanceIndex,
  // which counts from firstInstance.
  const float quad[12] = {0, 0, 0, 1, 1, 1, 0, 0, 1, 1, 1, 0};
  struct Instance {
    float dx, dy;
    uint8_t rgba[4];
  };
  const Instance inst[4] = {
      {-1, -1, {9, 9, 9, 255}}, {0, -1, {255, 0, 0, 255}}, {-1, 0, {0, 255, 0, 255}}, {0, 0, {0, 0, 255, 255}}};
  BufferHandle vq = buffer(sizeof(quad), quad, BufferUsage_Vertex);
  BufferHandle vi = buffer(sizeof(inst), inst, BufferUsage_Vertex);
  PipelineDesc d;
  d.vertexShader = shader(ShaderStage::Vertex, R"(#version 450
layout(location = 0) in vec2 corner;
layout(location = 1) in vec2 offset;
layout(location = 2) in vec4 col;
layout(location = 0) out vec4 vColor;
void main() {
  gl_Position = vec4(corner + offset, 0.5, 1.0);
  vColor = vec4(col.rgb, float(50 * gl_InstanceIndex) / 255.0);
})");
  d.fragmentShader = shader(ShaderStage::Fragment, kColorFs);
  d.attributeCount = 3;
  d.attributes[0] = {0, VertexFormat::Float2, 0, 0};
  d.attributes[1] = {1, VertexFormat::Float2, 0, 1};
  d.attributes[2] = {2, VertexFormat::UByte4Norm, 8, 1};
  d.vertexBuffers[0].stride = 8;
  d.vertexBuffers[1].stride = sizeof(Instance);
  d.vertexBuffers[1].perInstance = true;
  d.colorTargetCount = 1;
  d.colorTargets[0].format = Format::RGBA8;
  PipelineHandle p = pipeline(d);
  TextureHandle t = texture(Format::RGBA8, 16, 16);
  dev->beginPass(pass(t));
  dev->setPipeline(p);
  dev->setVertexBuffer(0, vq);
  dev->setVertexBuffer(1, vi);
  dev->draw(6, 3, 0, 1);
  dev->endPass();
  expectRgba8Image(read(t), 16, 16, [](uint32_t x, uint32_t y) {
    int q = (y >= 8 ? 2 : 0) + (x >= 8 ? 1 : 0);
    switch (q) {
      case 1:
        return Px{255, 0, 0, 50};
      case 2:
        return Px{0, 255, 0, 100};
      case 3:
        return Px{0, 0, 255, 150};
      default:
        return Px{0, 0, 0, 0};
    }
  });
}

// Integer vertex formats are fetched as integers, unconverted, each component in its place: two
// points, each writing a weighted sum of every attribute's components to an RGBA32_SINT pixel.
TEST_P(RhiConformanceTest, StrideZeroIsAConstantAttribute) {
  // Positions per vertex from slot 0, a colour from slot 1 with stride 0: both points read the
  // colour at the slot's offset (16 bytes in, past a decoy), not consecutive elements.
  const float positions[4] = {-0.5f, 0.0f, 0.5f, 0.0f};
  const float colours[8] = {0.0f, 0.0f, 1.0f, 1.0f, 0.0f, 1.0f, 0.0f, 1.0f};
  BufferHandle vb = buffer(sizeof positions, positions, BufferUsage_Vertex);
  BufferHandle cb = buffer(sizeof colours, colours, BufferUsage_Vertex);
  PipelineDesc d;
  d.vertexShader = shader(ShaderStage::Vertex, R"(#version 450
layout(location = 0) in vec2 position;
layout(location = 1) in vec4 colour;
layout(location = 0) out vec4 c;
void main() { gl_Position = vec4(position, 0.0, 1.0); gl_PointSize = 1.0; c = colour; })");
  d.fragmentShader = shader(ShaderStage::Fragment, R"(#version 450
layout(location = 0) in vec4 c;
layout(location = 0) out vec4 o;
void main() { o = c; })");
  d.attributeCount = 2;
  d.attributes[0] = {0, VertexFormat::Float2, 0, 0};
  d.attributes[1] = {1, VertexFormat::Float4, 0, 1};
  d.vertexBuffers[0].stride = 8;
  d.vertexBuffers[1].stride = 0;
  d.topology = PrimitiveTopology::Points;
  d.colorTargetCount = 1;
  d.colorTargets[0].format = Format::RGBA8;
  PipelineHandle p = pipeline(d);
  TextureHandle t = texture(Format::RGBA8, 2, 1);
  dev->beginPass(pass(t));
  dev->setPipeline(p);
  dev->setVertexBuffer(0, vb);
  dev->setVertexBuffer(1, cb, 16);
  dev->draw(2);
  dev->endPass();
  expectRgba8Image(read(t), 2, 1, [](uint32_t, uint32_t) { return Px{0, 255, 0, 255}; });
}

TEST_P(RhiConformanceTest, IntegerVertexAttributes) {
  struct Vertex {
    uint32_t u1, u2[2], u3[3], u4[4];
    int32_t i1, i2[2], i3[3], i4[4];
  };
  const Vertex v[2] = {{1, {1, 2}, {1, 2, 3}, {1, 2, 3, 4}, -1, {-1, 2}, {-1, 2, -3}, {-1, 2, -3, 4}},
                       {5, {6, 7}, {7, 8, 9}, {9, 8, 7, 6}, -7, {6, -5}, {4, -3, 2}, {-9, 8, -7, 6}}};
  BufferHandle vb = buffer(sizeof(v), v, BufferUsage_Vertex);
  PipelineDesc d;
  d.vertexShader = shader(ShaderStage::Vertex, R"(#version 450
layout(location = 0) in uint u1;
layout(location = 1) in uvec2 u2;
layout(location = 2) in uvec3 u3;
layout(location = 3) in uvec4 u4;
layout(location = 4) in int i1;
layout(location = 5) in ivec2 i2;
layout(location = 6) in ivec3 i3;
layout(location = 7) in ivec4 i4;
layout(location = 0) flat out ivec4 sums;
void main() {
  gl_Position = vec4(float(gl_VertexIndex) - 0.5, 0.0, 0.0, 1.0);
  gl_PointSize = 1.0;
  sums = ivec4(int(u1 + 10u * u2.x + 100u * u2.y), int(u3.x + 10u * u3.y + 100u * u3.z),
               int(u4.x + 10u * u4.y + 100u * u4.z + 1000u * u4.w),
               i1 + 10 * i2.x + 100 * i2.y + 1000 * i3.x + 10000 * i3.y + 100000 * i3.z +
               1000000 * (i4.x + 2 * i4.y + 4 * i4.z + 8 * i4.w));
})");
  d.fragmentShader = shader(ShaderStage::Fragment, R"(#version 450
layout(location = 0) flat in ivec4 sums;
layout(location = 0) out ivec4 o;
void main() { o = sums; })");
  const VertexFormat formats[8] = {VertexFormat::UInt, VertexFormat::UInt2, VertexFormat::UInt3, VertexFormat::UInt4,
                                   VertexFormat::Int,  VertexFormat::Int2,  VertexFormat::Int3,  VertexFormat::Int4};
  const uint32_t offsets[8] = {offsetof(Vertex, u1), offsetof(Vertex, u2), offsetof(Vertex, u3), offsetof(Vertex, u4),
                               offsetof(Vertex, i1), offsetof(Vertex, i2), offsetof(Vertex, i3), offsetof(Vertex, i4)};
  d.attributeCount = 8;
  for (uint32_t a = 0; a < 8; ++a) d.attributes[a] = {a, formats[a], offsets[a], 0};
  std::vector<uint8_t> bytes = drawTwoPointsAndRead(d, vb, sizeof(Vertex), Format::RGBA32_SINT);
  ASSERT_EQ(bytes.size(), 32u);
  int32_t got[8];
  std::memcpy(got, bytes.data(), sizeof got);
  // By hand: u1 + 10 u2.x + 100 u2.y, ...; i4 weighted 1, 2, 4, 8 (vertex 0: -1 + 4 - 12 + 32).
  const int32_t want[8] = {211, 321, 4321, -1 - 10 + 200 - 1000 + 20000 - 300000 + 1000000 * 23,
                           765, 987, 6789, -7 + 60 - 500 + 4000 - 30000 + 200000 + 1000000 * (-9 + 16 - 28 + 48)};
  for (int k = 0; k < 8; ++k) EXPECT_EQ(got[k], want[k]) << "pixel " << k / 4 << " channel " << k % 4;
}

// 64-bit attributes are fetched as doubles: each value is 1 + k·2^-n, which a 32-bit fetch would
// round to 1, and the shader scales the difference back up (exact in float). dvec3 and dvec4 take
// two locations each, so the dvec4 sits at location 4.
TEST_P(RhiConformanceTest, DoubleVertexAttributes) {
  if (!dev->info().caps.doubleVertexFormats) GTEST_SKIP() << "the device has no 64-bit vertex input";
  struct Vertex {
    double d1, d2[2], d3[3], d4[4];
  };
  const double e40 = std::ldexp(1.0, -40), e41 = std::ldexp(1.0, -41), e42 = std::ldexp(1.0, -42), e43 = std::ldexp(1.0, -43);
  const Vertex v[2] = {{1 + e40, {3, 1 + e41}, {5, 6, 1 + e42}, {1 + e43, 7, 8, 9}},
                       {1 + 3 * e40, {4, 1 + 2 * e41}, {1, 2, 1 + 3 * e42}, {1 + 2 * e43, 1, 1, 1}}};
  BufferHandle vb = buffer(sizeof(v), v, BufferUsage_Vertex);
  PipelineDesc d;
  d.vertexShader = shader(ShaderStage::Vertex, R"(#version 450
layout(location = 0) in double d1;
layout(location = 1) in dvec2 d2;
layout(location = 2) in dvec3 d3;
layout(location = 4) in dvec4 d4;
layout(location = 0) flat out vec4 values;
void main() {
  gl_Position = vec4(float(gl_VertexIndex) - 0.5, 0.0, 0.0, 1.0);
  gl_PointSize = 1.0;
  values = vec4(float((d1 - 1.0LF) * 1099511627776.0LF),
                float(d2.x) + 10.0 * float((d2.y - 1.0LF) * 2199023255552.0LF),
                float(d3.x + d3.y) + 100.0 * float((d3.z - 1.0LF) * 4398046511104.0LF),
                float((d4.x - 1.0LF) * 8796093022208.0LF) + 10.0 * float(d4.y + d4.z + d4.w));
})");
  d.fragmentShader = shader(ShaderStage::Fragment, R"(#version 450
layout(location = 0) flat in vec4 values;
layout(location = 0) out vec4 o;
void main() { o = values; })");
  d.attributeCount = 4;
  d.attributes[0] = {0, VertexFormat::Double, offsetof(Vertex, d1), 0};
  d.attributes[1] = {1, VertexFormat::Double2, offsetof(Vertex, d2), 0};
  d.attributes[2] = {2, VertexFormat::Double3, offsetof(Vertex, d3), 0};
  d.attributes[3] = {4, VertexFormat::Double4, offsetof(Vertex, d4), 0};
  std::vector<uint8_t> bytes = drawTwoPointsAndRead(d, vb, sizeof(Vertex), Format::RGBA32F);
  ASSERT_EQ(bytes.size(), 32u);
  float got[8];
  std::memcpy(got, bytes.data(), sizeof got);
  // By hand: vertex 0 (1, 3 + 10, 11 + 100, 1 + 240), vertex 1 (3, 4 + 20, 3 + 300, 2 + 30).
  const float want[8] = {1, 13, 111, 241, 3, 24, 303, 32};
  for (int k = 0; k < 8; ++k) EXPECT_EQ(got[k], want[k]) << "pixel " << k / 4 << " channel " << k % 4;
}

// Matrices and arrays of 64-bit inputs take one attribute per column or element: a dmat2x3's
// dvec3 columns two locations each, then a dvec2 array one each and a double after them.
TEST_P(RhiConformanceTest, DoubleVertexMatricesAndArrays) {
  if (!dev->info().caps.doubleVertexFormats) GTEST_SKIP() << "the device has no 64-bit vertex input";
  struct Vertex {
    double m[2][3], a[2][2], d;
  };
  const double e40 = std::ldexp(1.0, -40), e41 = std::ldexp(1.0, -41), e42 = std::ldexp(1.0, -42), e43 = std::ldexp(1.0, -43);
  const Vertex v[2] = {{{{1 + e40, 2, 3}, {4, 5, 1 + e41}}, {{6, 1 + e42}, {1 + e43, 7}}, 1 + 5 * e40},
                       {{{1 + 2 * e40, 1, 1}, {2, 2, 1 + 3 * e41}}, {{1, 1 + 2 * e42}, {1 + 3 * e43, 2}}, 1 + 7 * e40}};
  BufferHandle vb = buffer(sizeof(v), v, BufferUsage_Vertex);
  PipelineDesc d;
  d.vertexShader = shader(ShaderStage::Vertex, R"(#version 450
layout(location = 0) in dmat2x3 m;
layout(location = 4) in dvec2 a[2];
layout(location = 6) in double d;
layout(location = 0) flat out vec4 values;
void main() {
  gl_Position = vec4(float(gl_VertexIndex) - 0.5, 0.0, 0.0, 1.0);
  gl_PointSize = 1.0;
  values = vec4(float((m[0].x - 1.0LF) * 1099511627776.0LF) + 10.0 * float(m[0].y + m[0].z),
                float(m[1].x + m[1].y) + 100.0 * float((m[1].z - 1.0LF) * 2199023255552.0LF),
                float(a[0].x) + 10.0 * float((a[0].y - 1.0LF) * 4398046511104.0LF) +
                    100.0 * float((a[1].x - 1.0LF) * 8796093022208.0LF) + 1000.0 * float(a[1].y),
                float((d - 1.0LF) * 1099511627776.0LF));
})");
  d.fragmentShader = shader(ShaderStage::Fragment, R"(#version 450
layout(location = 0) flat in vec4 values;
layout(location = 0) out vec4 o;
void main() { o = values; })");
  d.attributeCount = 5;
  d.attributes[0] = {0, VertexFormat::Double3, offsetof(Vertex, m), 0};
  d.attributes[1] = {2, VertexFormat::Double3, offsetof(Vertex, m) + 3 * sizeof(double), 0};
  d.attributes[2] = {4, VertexFormat::Double2, offsetof(Vertex, a), 0};
  d.attributes[3] = {5, VertexFormat::Double2, offsetof(Vertex, a) + 2 * sizeof(double), 0};
  d.attributes[4] = {6, VertexFormat::Double, offsetof(Vertex, d), 0};
  std::vector<uint8_t> bytes = drawTwoPointsAndRead(d, vb, sizeof(Vertex), Format::RGBA32F);
  ASSERT_EQ(bytes.size(), 32u);
  float got[8];
  std::memcpy(got, bytes.data(), sizeof got);
  // By hand: vertex 0 (1 + 50, 9 + 100, 6 + 10 + 100 + 7000, 5), vertex 1 (2 + 20, 4 + 300, 1 + 20 + 300 + 2000, 7).
  const float want[8] = {51, 109, 7116, 5, 22, 304, 2321, 7};
  for (int k = 0; k < 8; ++k) EXPECT_EQ(got[k], want[k]) << "pixel " << k / 4 << " channel " << k % 4;
}

TEST_P(RhiConformanceTest, UniformBufferBindingOffset) {
  // Colour A at offset 0, colour B at offset 256: binding with offset 256 reads B.
  std::vector<float> data(128, 0.0f);
  const float a[4] = {1, 0, 0, 1}, bcol[4] = {0, 0, 1, 1};
  std::memcpy(&data[0], a, sizeof(a));
  std::memcpy(&data[64], bcol, sizeof(bcol));
  BufferHandle ubo = buffer(512, data.data(), BufferUsage_Uniform);
  PipelineHandle p = pipeline(fullscreenDesc(Format::RGBA8, R"(#version 450
layout(set = 0, binding = 3) uniform U { vec4 color; } u;
layout(location = 0) out vec4 o;
void main() { o = u.color; })"));
  TextureHandle t = texture(Format::RGBA8, 4, 4);
  ResourceBinding rb;
  rb.binding = 3;
  rb.kind = BindingKind::UniformBuffer;
  rb.buffer = ubo;
  rb.offset = 256;
  rb.size = 16;
  dev->setBindings({&rb, 1});
  drawFullscreen(p, t);
  expectRgba8Image(read(t), 4, 4, [](uint32_t, uint32_t) { return Px{0, 0, 255, 255}; });
}

// ---------------------------------------------------------------------------------------------
// Array and cube textures
// ---------------------------------------------------------------------------------------------
TEST_P(RhiConformanceTest, ArrayTextureSampling) {
  // 2x2x3 array, layer L filled with colour L; pixel x of a 3x1 target samples layer x.
  const Px colors[3] = {{10, 0, 0, 255}, {0, 20, 0, 255}, {0, 0, 30, 255}};
  std::vector<uint8_t> data;
  for (int l = 0; l < 3; ++l)
    for (int i = 0; i < 4; ++i)
      for (int c = 0; c < 4; ++c) data.push_back(uint8_t(colors[l][c]));
  TextureDesc ad;
  ad.type = TextureType::Tex2DArray;
  ad.width = ad.height = 2;
  ad.layers = 3;
  ad.usage = TextureUsage_Sampled;
  ad.initialData = data.data();
  ad.label = "array";
  TextureHandle arr = texture(ad);
  TextureHandle t = texture(Format::RGBA8, 3, 1);
  PipelineHandle p = pipeline(fullscreenDesc(Format::RGBA8, R"(#version 450
layout(set = 0, binding = 0) uniform sampler2DArray tex;
layout(location = 0) out vec4 o;
void main() { o = texture(tex, vec3(0.5, 0.5, floor(gl_FragCoord.x))); })"));
  ResourceBinding rb;
  rb.kind = BindingKind::SampledTexture;
  rb.texture = arr;
  dev->setBindings({&rb, 1});
  drawFullscreen(p, t);
  expectRgba8Image(read(t), 3, 1, [&](uint32_t x, uint32_t) { return colors[x]; });
}

TEST_P(RhiConformanceTest, CubeTextureSampling) {
  // 2x2 faces in the order +X, -X, +Y, -Y, +Z, -Z; texel (x, y) of face f = (40f + 10,
  // 100x + 50, 100y + 50, 255). Column f of a 6x2 target samples face f at (s, t) = (0.25, 0.25)
  // in row 0 and (0.75, 0.75) in row 1, with directions from the cube face selection table
  // (Vulkan spec 16.5.4, identical in GL): sc = tc = -0.5 or +0.5.
  std::vector<uint8_t> data;
  for (int f = 0; f < 6; ++f)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x)
        for (int v : {40 * f + 10, 100 * x + 50, 100 * y + 50, 255}) data.push_back(uint8_t(v));
  TextureDesc cd;
  cd.type = TextureType::Cube;
  cd.width = cd.height = 2;
  cd.layers = 6;
  cd.usage = TextureUsage_Sampled;
  cd.initialData = data.data();
  cd.label = "cube";
  TextureHandle cube = texture(cd);
  TextureHandle t = texture(Format::RGBA8, 6, 2);
  PipelineHandle p = pipeline(fullscreenDesc(Format::RGBA8, R"(#version 450
layout(set = 0, binding = 0) uniform samplerCube tex;
layout(location = 0) out vec4 o;
void main() {
  int f = int(gl_FragCoord.x);
  float k = gl_FragCoord.y < 1.0 ? -0.5 : 0.5;  // sc = tc = k
  vec3 d;
  if (f == 0) d = vec3(1.0, -k, -k);        // +X: sc = -rz, tc = -ry
  else if (f == 1) d = vec3(-1.0, -k, k);   // -X: sc = +rz, tc = -ry
  else if (f == 2) d = vec3(k, 1.0, k);     // +Y: sc = +rx, tc = +rz
  else if (f == 3) d = vec3(k, -1.0, -k);   // -Y: sc = +rx, tc = -rz
  else if (f == 4) d = vec3(k, -k, 1.0);    // +Z: sc = +rx, tc = -ry
  else d = vec3(-k, -k, -1.0);              // -Z: sc = -rx, tc = -ry
  o = texture(tex, d);
})"));
  ResourceBinding rb;
  rb.kind = BindingKind::SampledTexture;
  rb.texture = cube;
  dev->setBindings({&rb, 1});
  drawFullscreen(p, t);
  expectRgba8Image(read(t), 6, 2, [](uint32_t f, uint32_t row) {
    int xy = row == 0 ? 50 : 150;
    return Px{int(40 * f + 10), xy, xy, 255};
  });
}

TEST_P(RhiConformanceTest, RenderToArrayLayerAndCubeFace) {
  // Layer 1 of a 3-layer array and face 4 (+Z) of a cube are rendered green with LoadOp::Load;
  // the other layers keep their initial contents.
  std::vector<uint8_t> init;
  for (int l = 0; l < 6; ++l)
    for (int i = 0; i < 16; ++i)
      for (int v : {l * 10 + 1, l * 10 + 2, l * 10 + 3, 255}) init.push_back(uint8_t(v));
  TextureDesc ad;
  ad.type = TextureType::Tex2DArray;
  ad.width = ad.height = 4;
  ad.layers = 3;
  ad.initialData = init.data();
  ad.label = "array target";
  TextureHandle arr = texture(ad);
  TextureDesc cd = ad;
  cd.type = TextureType::Cube;
  cd.layers = 6;
  cd.label = "cube target";
  TextureHandle cube = texture(cd);
  PipelineHandle p = pipeline(rectDesc(Format::RGBA8));
  for (auto [tex, layer] : {std::pair{arr, 1u}, std::pair{cube, 4u}}) {
    PassDesc ps = pass(tex);
    ps.colors[0].layer = layer;
    ps.colors[0].load = LoadOp::Load;
    dev->beginPass(ps);
    dev->setPipeline(p);
    drawRect(kFullNdc, unorm(0, 255, 0, 255));
    dev->endPass();
  }
  auto initial = [](int l) { return Px{l * 10 + 1, l * 10 + 2, l * 10 + 3, 255}; };
  for (uint32_t l = 0; l < 3; ++l)
    expectRgba8Image(
        read(arr, l), 4, 4,
        [&](uint32_t, uint32_t) {
          return l == 1 ? Px{0, 255, 0, 255} : initial(l);
        },
        ("array layer " + std::to_string(l)).c_str());
  for (uint32_t l = 0; l < 6; ++l)
    expectRgba8Image(
        read(cube, l), 4, 4,
        [&](uint32_t, uint32_t) {
          return l == 4 ? Px{0, 255, 0, 255} : initial(l);
        },
        ("cube face " + std::to_string(l)).c_str());
}

// ---------------------------------------------------------------------------------------------
// Copies, buffers, timestamps
// ---------------------------------------------------------------------------------------------
TEST_P(RhiConformanceTest, CopyTexture) {
  // RGBA8 -> RGBA8, RGBA8 -> R32_UINT (same size class: raw bytes), into layer 1 of an array,
  // and mip 1 of the source into a 2x2 texture.
  std::vector<uint8_t> mip0(4 * 4 * 4), mip1(2 * 2 * 4);
  for (size_t i = 0; i < mip0.size(); ++i) mip0[i] = uint8_t(i * 3 + 1);
  for (size_t i = 0; i < mip1.size(); ++i) mip1[i] = uint8_t(200 - i);
  TextureDesc sd;
  sd.width = sd.height = 4;
  sd.mipLevels = 2;
  sd.usage = TextureUsage_Sampled;
  sd.label = "copy source";
  TextureHandle src = texture(sd);
  dev->writeTexture(src, 0, 0, mip0.data());
  dev->writeTexture(src, 0, 1, mip1.data());
  TextureHandle same = texture(Format::RGBA8, 4, 4, TextureUsage_Sampled);
  TextureHandle asUint = texture(Format::R32_UINT, 4, 4, TextureUsage_Sampled);
  TextureDesc ad;
  ad.type = TextureType::Tex2DArray;
  ad.width = ad.height = 4;
  ad.layers = 2;
  ad.usage = TextureUsage_Sampled;
  ad.label = "copy array";
  TextureHandle arr = texture(ad);
  TextureHandle small = texture(Format::RGBA8, 2, 2, TextureUsage_Sampled);
  dev->copyTexture(src, same);
  dev->copyTexture(src, asUint);
  dev->copyTexture(src, arr, {}, ReadbackRegion{1, 0, TextureAspect::Color});
  dev->copyTexture(src, small, ReadbackRegion{0, 1, TextureAspect::Color}, {});
  EXPECT_EQ(read(same), mip0);
  EXPECT_EQ(read(asUint), mip0);
  EXPECT_EQ(read(arr, 1), mip0);
  EXPECT_EQ(read(small), mip1);
}

TEST_P(RhiConformanceTest, BufferWriteCopyRead) {
  std::vector<uint8_t> init(64);
  for (size_t i = 0; i < init.size(); ++i) init[i] = uint8_t(i);
  BufferHandle a = buffer(64, init.data()), b = buffer(64);
  const uint8_t patch[4] = {0xAA, 0xBB, 0xCC, 0xDD};
  dev->writeBuffer(a, 8, patch, sizeof(patch));
  dev->copyBuffer(a, 4, b, 32, 16);
  std::vector<uint8_t> wantA = init;
  std::memcpy(&wantA[8], patch, 4);
  std::vector<uint8_t> wantB(64, 0);  // buffers start zeroed
  std::memcpy(&wantB[32], &wantA[4], 16);
  EXPECT_EQ(dev->readBuffer(a, 0, 64), wantA);
  EXPECT_EQ(dev->readBuffer(b, 0, 64), wantB);
  EXPECT_EQ(dev->readBuffer(b, 36, 4), std::vector<uint8_t>({0xAA, 0xBB, 0xCC, 0xDD}));
}

TEST_P(RhiConformanceTest, TimestampsIncrease) {
  TextureHandle t = texture(Format::RGBA8, 16, 16);
  PipelineHandle p = pipeline(rectDesc(Format::RGBA8));
  dev->resetTimestamps();
  TimestampId t0 = dev->writeTimestamp();
  dev->beginPass(pass(t));
  dev->setPipeline(p);
  drawRect(kFullNdc, {1, 1, 1, 1});
  dev->endPass();
  TimestampId t1 = dev->writeTimestamp();
  dev->submit();
  std::optional<uint64_t> a = dev->timestampNs(t0), b = dev->timestampNs(t1);
  ASSERT_TRUE(a.has_value());
  ASSERT_TRUE(b.has_value());
  EXPECT_NE(*a, 0u);
  EXPECT_GE(*b, *a);
}

// The timing decorator behind `parity run`'s pass timings and `parity bench`: one entry per
// pass and copy, named by label, adding up to the frame.
TEST_P(RhiConformanceTest, TimingDeviceTimesEachPassAndCopy) {
  TextureHandle t = texture(Format::RGBA8, 16, 16), u = texture(Format::RGBA8, 16, 16);
  PipelineHandle p = pipeline(rectDesc(Format::RGBA8));
  TimingDevice timed(*dev);
  timed.beginFrame();
  PassDesc first = pass(t);
  first.label = "first";
  timed.beginPass(first);
  timed.setPipeline(p);
  drawRect(kFullNdc, {1, 1, 1, 1});
  timed.endPass();
  timed.copyTexture(t, u);
  PassDesc unnamed = pass(u);
  unnamed.label.clear();
  timed.beginPass(unnamed);
  timed.setPipeline(p);
  drawRect(kFullNdc, {0, 1, 0, 1});
  timed.endPass();
  timed.submit();
  std::vector<PassTiming> timings = timed.passTimings();
  if (!dev->info().caps.timestamps) {
    EXPECT_TRUE(timings.empty());
    EXPECT_EQ(timed.frameGpuMs(), -1);
    return;
  }
  ASSERT_EQ(timings.size(), 3u);
  EXPECT_EQ(timings[0].label, "first");
  EXPECT_EQ(timings[1].label, "copy");
  EXPECT_EQ(timings[2].label, "pass 2");
  double sum = 0;
  for (const PassTiming& e : timings) {
    EXPECT_GE(e.ms, 0.0);
    sum += e.ms;
  }
  EXPECT_NEAR(sum, timed.frameGpuMs(), 1e-9 + 1e-9 * sum);
}

// `parity bench`'s measured rounds: an untimed frame writes no timestamp (on llvmpipe and
// lavapipe each one finishes the queued work) and reports no times; the next timed frame does.
TEST_P(RhiConformanceTest, TimingDeviceUntimedFrameWritesNoTimestamp) {
  struct CountingDevice : ForwardingDevice {
    using ForwardingDevice::ForwardingDevice;
    TimestampId writeTimestamp() override {
      ++written;
      return ForwardingDevice::writeTimestamp();
    }
    int written = 0;
  } counting(*dev);
  TextureHandle t = texture(Format::RGBA8, 16, 16), u = texture(Format::RGBA8, 16, 16);
  PipelineHandle p = pipeline(rectDesc(Format::RGBA8));
  TimingDevice timed(counting);
  const auto frame = [&] {
    timed.beginPass(pass(t));
    timed.setPipeline(p);
    drawRect(kFullNdc, {1, 1, 1, 1});
    timed.endPass();
    timed.copyTexture(t, u);
    timed.submit();
  };
  timed.beginUntimedFrame();
  frame();
  EXPECT_EQ(counting.written, 0);
  EXPECT_TRUE(timed.passTimings().empty());
  EXPECT_EQ(timed.frameGpuMs(), -1);
  if (!dev->info().caps.timestamps) return;
  timed.beginFrame();
  frame();
  EXPECT_EQ(counting.written, 3);  // the frame's start, the pass, the copy
  EXPECT_EQ(timed.passTimings().size(), 2u);
  timed.beginUntimedFrame();
  frame();
  EXPECT_EQ(counting.written, 3);
  EXPECT_TRUE(timed.passTimings().empty());
}

// ---------------------------------------------------------------------------------------------
// Separate textures and samplers, border colours
// ---------------------------------------------------------------------------------------------
// Texel (x, y) of a 4x4 RGBA8 texture: (60x, 60y, 7, 255).
std::vector<uint8_t> gradient4x4() {
  std::vector<uint8_t> data(4 * 4 * 4);
  for (uint32_t y = 0; y < 4; ++y)
    for (uint32_t x = 0; x < 4; ++x) {
      uint8_t* t = &data[(y * 4 + x) * 4];
      t[0] = uint8_t(60 * x), t[1] = uint8_t(60 * y), t[2] = 7, t[3] = 255;
    }
  return data;
}

TEST_P(RhiConformanceTest, SeparateTextureWithTwoSamplers) {
  // One texture2D combined in the shader with two separate samplers. The left 4x4 of an 8x4
  // target reads it through the null (default: nearest, clamp) sampler at uv = gl_FragCoord / 4,
  // which reproduces the texture; the right half reads it at u >= 1.375 through a ClampToBorder
  // sampler with an opaque white border. Two pairs sharing one texture (GL: two texture units;
  // Vulkan: one SAMPLED_IMAGE and two SAMPLER descriptors); bindings not in declaration order.
  std::vector<uint8_t> data = gradient4x4();
  TextureHandle src = texture(Format::RGBA8, 4, 4, TextureUsage_Sampled, data.data());
  TextureHandle dst = texture(Format::RGBA8, 8, 4);
  PipelineHandle p = pipeline(fullscreenDesc(Format::RGBA8, R"(#version 450
layout(set = 0, binding = 2) uniform texture2D tex;
layout(set = 0, binding = 0) uniform sampler defaultSampler;
layout(set = 0, binding = 5) uniform sampler border;
layout(location = 0) out vec4 o;
void main() {
  vec2 uv = gl_FragCoord.xy / 4.0;
  if (gl_FragCoord.x < 4.0) o = texture(sampler2D(tex, defaultSampler), uv);
  else o = texture(sampler2D(tex, border), uv + vec2(0.25, 0.0));
})"));
  SamplerDesc sd;
  sd.addressU = sd.addressV = AddressMode::ClampToBorder;
  sd.borderColor = BorderColor::FloatOpaqueWhite;
  SamplerHandle white = dev->createSampler(sd);
  ASSERT_TRUE(white);
  std::array<ResourceBinding, 3> b{};
  b[0].binding = 2, b[0].kind = BindingKind::SeparateTexture, b[0].texture = src;
  b[1].binding = 0, b[1].kind = BindingKind::SeparateSampler;  // null: the default sampler
  b[2].binding = 5, b[2].kind = BindingKind::SeparateSampler, b[2].sampler = white;
  dev->setBindings(b);
  drawFullscreen(p, dst);
  expectRgba8Image(read(dst), 8, 4, [](uint32_t x, uint32_t y) {
    return x < 4 ? Px{int(60 * x), int(60 * y), 7, 255} : Px{255, 255, 255, 255};
  });
  dev->destroy(white);
}

TEST_P(RhiConformanceTest, SeparateTextureFetchedWithoutSampler) {
  // texelFetch on a texture2D needs no sampler (GL_EXT_samplerless_texture_functions): Vulkan
  // binds only the SAMPLED_IMAGE; GL pairs it with the default sampler on a unit of its own.
  std::vector<uint8_t> data = gradient4x4();
  TextureHandle src = texture(Format::RGBA8, 4, 4, TextureUsage_Sampled, data.data());
  TextureHandle dst = texture(Format::RGBA8, 4, 4);
  PipelineHandle p = pipeline(fullscreenDesc(Format::RGBA8, R"(#version 450
#extension GL_EXT_samplerless_texture_functions : require
layout(set = 0, binding = 3) uniform texture2D tex;
layout(location = 0) out vec4 o;
void main() { o = texelFetch(tex, ivec2(gl_FragCoord.xy), 0); })"));
  ResourceBinding b;
  b.binding = 3;
  b.kind = BindingKind::SeparateTexture;
  b.texture = src;
  dev->setBindings({&b, 1});
  drawFullscreen(p, dst);
  expectRgba8Image(read(dst), 4, 4, [](uint32_t x, uint32_t y) { return Px{int(60 * x), int(60 * y), 7, 255}; });
}

TEST_P(RhiConformanceTest, SeparateShadowSampler) {
  // ShadowSamplerCompare with a separate texture2D and samplerShadow combined as
  // sampler2DShadow(tex, smp): depth 0.25 left, 0.75 right, reference 0.5, LessEqual gives 0 left
  // and 1 right, with an explicit compare sampler and with the null default (which compares
  // for a shadow pair, as the combined default does).
  TextureHandle c = texture(Format::RGBA8, 16, 16), d = texture(Format::D32F, 16, 16);
  PipelineDesc pd = rectDesc(Format::RGBA8);
  pd.depthStencilFormat = Format::D32F;
  pd.depthStencil.depthWrite = true;
  PipelineHandle write = pipeline(pd);
  dev->beginPass(pass(c, {0, 0, 0, 0}, d));
  dev->setPipeline(write);
  drawRect(ndcRect(0, 0, 8, 16, 16, 16), {1, 1, 1, 1}, 0.25f);
  drawRect(ndcRect(8, 0, 16, 16, 16, 16), {1, 1, 1, 1}, 0.75f);
  dev->endPass();

  SamplerDesc sd;
  sd.compareEnabled = true;
  sd.compare = CompareOp::LessEqual;
  SamplerHandle s = dev->createSampler(sd);
  ASSERT_TRUE(s);
  PipelineHandle p = pipeline(fullscreenDesc(Format::RGBA8, R"(#version 450
layout(set = 0, binding = 0) uniform texture2D depthTex;
layout(set = 0, binding = 1) uniform samplerShadow smp;
layout(location = 0) out vec4 o;
void main() { o = vec4(texture(sampler2DShadow(depthTex, smp), vec3(gl_FragCoord.xy / 16.0, 0.5))); })"));
  for (SamplerHandle sampler : {s, SamplerHandle{}}) {
    TextureHandle out = texture(Format::RGBA8, 16, 16);
    std::array<ResourceBinding, 2> rb{};
    rb[0].binding = 0, rb[0].kind = BindingKind::SeparateTexture, rb[0].texture = d;
    rb[1].binding = 1, rb[1].kind = BindingKind::SeparateSampler, rb[1].sampler = sampler;
    dev->setBindings(rb);
    dev->beginPass(pass(out));
    dev->setPipeline(p);
    dev->draw(3);
    dev->endPass();
    expectRgba8Image(
        read(out), 16, 16,
        [](uint32_t x, uint32_t) {
          return x < 8 ? Px{0, 0, 0, 0} : Px{255, 255, 255, 255};
        },
        sampler ? "compare sampler" : "default sampler");
  }
}

TEST_P(RhiConformanceTest, BorderColors) {
  // A 2x2 texture of texels (10, 20, 30, 40) is read by a 2x1 target: pixel 0 inside at
  // uv (0.25, 0.25), pixel 1 outside at uv (-0.5, 0.5) through a ClampToBorder sampler, which
  // returns the border colour. Float colours on an RGBA8 texture written to RGBA8; Int colours
  // on an RGBA8_UINT texture (usampler2D) written to RGBA8_UINT, where 1 is 1, not 255.
  struct Case {
    BorderColor color;
    bool integer;
    Px expected;
  };
  const Case cases[] = {
      {BorderColor::FloatTransparentBlack, false, {0, 0, 0, 0}},
      {BorderColor::FloatOpaqueBlack, false, {0, 0, 0, 255}},
      {BorderColor::FloatOpaqueWhite, false, {255, 255, 255, 255}},
      {BorderColor::IntTransparentBlack, true, {0, 0, 0, 0}},
      {BorderColor::IntOpaqueBlack, true, {0, 0, 0, 1}},
      {BorderColor::IntOpaqueWhite, true, {1, 1, 1, 1}},
  };
  const uint8_t texels[16] = {10, 20, 30, 40, 10, 20, 30, 40, 10, 20, 30, 40, 10, 20, 30, 40};
  TextureHandle unormTex = texture(Format::RGBA8, 2, 2, TextureUsage_Sampled, texels);
  TextureHandle uintTex = texture(Format::RGBA8_UINT, 2, 2, TextureUsage_Sampled, texels);
  TextureHandle unormDst = texture(Format::RGBA8, 2, 1);
  TextureHandle uintDst = texture(Format::RGBA8_UINT, 2, 1);
  PipelineHandle floatPipeline = pipeline(fullscreenDesc(Format::RGBA8, R"(#version 450
layout(set = 0, binding = 0) uniform sampler2D tex;
layout(location = 0) out vec4 o;
void main() { o = texture(tex, gl_FragCoord.x < 1.0 ? vec2(0.25) : vec2(-0.5, 0.5)); })"));
  PipelineHandle uintPipeline = pipeline(fullscreenDesc(Format::RGBA8_UINT, R"(#version 450
layout(set = 0, binding = 0) uniform usampler2D tex;
layout(location = 0) out uvec4 o;
void main() { o = texture(tex, gl_FragCoord.x < 1.0 ? vec2(0.25) : vec2(-0.5, 0.5)); })"));
  for (const Case& c : cases) {
    SamplerDesc sd;
    sd.addressU = sd.addressV = AddressMode::ClampToBorder;
    sd.borderColor = c.color;
    SamplerHandle s = dev->createSampler(sd);
    ASSERT_TRUE(s);
    ResourceBinding b;
    b.kind = BindingKind::SampledTexture;
    b.texture = c.integer ? uintTex : unormTex;
    b.sampler = s;
    dev->setBindings({&b, 1});
    TextureHandle dst = c.integer ? uintDst : unormDst;
    dev->beginPass(pass(dst));
    dev->setPipeline(c.integer ? uintPipeline : floatPipeline);
    dev->draw(3);
    dev->endPass();
    std::vector<uint8_t> px = read(dst);
    EXPECT_EQ(str(rgba8(px, 2, 0, 0)), str(Px{10, 20, 30, 40})) << "border colour " << int(c.color) << ": inside";
    EXPECT_EQ(str(rgba8(px, 2, 1, 0)), str(c.expected)) << "border colour " << int(c.color) << ": outside";
    dev->destroy(s);
  }
}

TEST_P(RhiConformanceTest, TextureViewFromBaseMipSamplesThatLevel) {
  // A 4x4 texture with 3 mips, level m filled with colour m, and a view from mip 1 (what a script's
  // BASE_MIP_LEVEL 1 binds). A 3x1 target with a nearest mip filter: pixel 0 samples the view
  // with texture() at a constant uv (no derivatives: the view's level 0, mip 1), pixel 1 the view
  // with textureLod 1.0 (mip 2), pixel 2 the whole texture with textureLod 0.0 (mip 0).
  const std::array<Px, 3> colors = {{{200, 0, 0, 255}, {0, 150, 0, 255}, {0, 0, 100, 255}}};
  TextureHandle tex = threeColouredMips(colors);
  TextureViewDesc vd;
  vd.parent = tex;
  vd.baseMip = 1;
  vd.label = "from mip 1";
  TextureHandle view = dev->createTextureView(vd);
  ASSERT_TRUE(view);
  SamplerDesc sd;
  sd.mipFilter = MipFilter::Nearest;
  SamplerHandle s = dev->createSampler(sd);
  ASSERT_TRUE(s);
  TextureHandle dst = texture(Format::RGBA8, 3, 1);
  PipelineHandle p = pipeline(fullscreenDesc(Format::RGBA8, R"(#version 450
layout(set = 0, binding = 0) uniform sampler2D fromMip1;
layout(set = 0, binding = 1) uniform sampler2D whole;
layout(location = 0) out vec4 o;
void main() {
  vec2 uv = vec2(0.5);
  if (gl_FragCoord.x < 1.0) o = texture(fromMip1, uv);
  else if (gl_FragCoord.x < 2.0) o = textureLod(fromMip1, uv, 1.0);
  else o = textureLod(whole, uv, 0.0);
})"));
  std::array<ResourceBinding, 2> b{};
  b[0].binding = 0, b[0].kind = BindingKind::SampledTexture, b[0].texture = view, b[0].sampler = s;
  b[1].binding = 1, b[1].kind = BindingKind::SampledTexture, b[1].texture = tex, b[1].sampler = s;
  dev->setBindings(b);
  drawFullscreen(p, dst);
  const Px expected[3] = {colors[1], colors[2], colors[0]};
  expectRgba8Image(read(dst), 3, 1, [&](uint32_t x, uint32_t) { return expected[x]; });
  dev->destroy(view);
  dev->destroy(s);
}

TEST_P(RhiConformanceTest, TextureViewSwizzleMapsSampledComponents) {
  // One RGBA8 texel (10, 20, 30, 40) through a view mapping r <- blue, g <- zero, b <- red,
  // a <- one. Pixel 0 fetches it, pixel 1 filters it, pixel 2 gathers component 0 (the mapped r,
  // blue, from each of the four texels), pixel 3 fetches the parent, which keeps the identity.
  const uint8_t bytes[4] = {10, 20, 30, 40};
  TextureHandle parent = texture(Format::RGBA8, 1, 1, TextureUsage_Sampled, bytes);
  TextureViewDesc vd;
  vd.parent = parent;
  vd.swizzle = {Swizzle::Blue, Swizzle::Zero, Swizzle::Red, Swizzle::One};
  vd.label = "swizzled";
  TextureHandle view = dev->createTextureView(vd);
  ASSERT_TRUE(view);
  TextureHandle dst = texture(Format::RGBA8, 4, 1);
  PipelineHandle p = pipeline(fullscreenDesc(Format::RGBA8, R"(#version 450
layout(set = 0, binding = 0) uniform sampler2D swizzled;
layout(set = 0, binding = 1) uniform sampler2D plain;
layout(location = 0) out vec4 o;
void main() {
  if (gl_FragCoord.x < 1.0) o = texelFetch(swizzled, ivec2(0), 0);
  else if (gl_FragCoord.x < 2.0) o = texture(swizzled, vec2(0.5));
  else if (gl_FragCoord.x < 3.0) o = textureGather(swizzled, vec2(0.5), 0);
  else o = texelFetch(plain, ivec2(0), 0);
})"));
  std::array<ResourceBinding, 2> b{};
  b[0].binding = 0, b[0].kind = BindingKind::SampledTexture, b[0].texture = view;
  b[1].binding = 1, b[1].kind = BindingKind::SampledTexture, b[1].texture = parent;
  dev->setBindings(b);
  drawFullscreen(p, dst);
  const Px mapped{30, 0, 10, 255}, gathered{30, 30, 30, 30}, plain{10, 20, 30, 40};
  const Px expected[4] = {mapped, mapped, gathered, plain};
  expectRgba8Image(read(dst), 4, 1, [&](uint32_t x, uint32_t) { return expected[x]; });
  dev->destroy(view);
}

TEST_P(RhiConformanceTest, SamplerLevelOfDetailClampAndBias) {
  // A 4x4 texture with 3 mips, level m filled with colour m, read with texture() over 4x4 pixels
  // (a level of detail of 0) through four samplers, one per 4x4 region of a 16x4 target: the
  // default (level 0), a bias of 1 (level 1), a minLod of 2 (level 2), and a bias of 2 under a
  // maxLod of 1 (level 1).
  const std::array<Px, 3> colors = {{{200, 0, 0, 255}, {0, 150, 0, 255}, {0, 0, 100, 255}}};
  TextureHandle tex = threeColouredMips(colors);
  SamplerDesc sd[4];
  for (SamplerDesc& s : sd) s.mipFilter = MipFilter::Nearest;
  sd[1].mipLodBias = 1.0f;
  sd[2].minLod = 2.0f;
  sd[3].mipLodBias = 2.0f;
  sd[3].maxLod = 1.0f;
  std::array<SamplerHandle, 4> samplers{};
  std::array<ResourceBinding, 4> b{};
  for (uint32_t i = 0; i < 4; ++i) {
    samplers[i] = dev->createSampler(sd[i]);
    ASSERT_TRUE(samplers[i]) << "sampler " << i;
    b[i].binding = i, b[i].kind = BindingKind::SampledTexture, b[i].texture = tex, b[i].sampler = samplers[i];
  }
  TextureHandle dst = texture(Format::RGBA8, 16, 4);
  PipelineHandle p = pipeline(fullscreenDesc(Format::RGBA8, R"(#version 450
layout(set = 0, binding = 0) uniform sampler2D plain;
layout(set = 0, binding = 1) uniform sampler2D biased;
layout(set = 0, binding = 2) uniform sampler2D clampedBelow;
layout(set = 0, binding = 3) uniform sampler2D clampedAbove;
layout(location = 0) out vec4 o;
void main() {
  // Every 2x2 quad lies in one region, so the derivatives see one sampler and one texel per pixel.
  vec2 uv = mod(gl_FragCoord.xy, 4.0) / 4.0;
  int region = int(gl_FragCoord.x) / 4;
  if (region == 0) o = texture(plain, uv);
  else if (region == 1) o = texture(biased, uv);
  else if (region == 2) o = texture(clampedBelow, uv);
  else o = texture(clampedAbove, uv);
})"));
  dev->setBindings(b);
  drawFullscreen(p, dst);
  const Px expected[4] = {colors[0], colors[1], colors[2], colors[1]};
  expectRgba8Image(read(dst), 16, 4, [&](uint32_t x, uint32_t) { return expected[x / 4]; });
  for (SamplerHandle s : samplers) dev->destroy(s);
}

TEST_P(RhiConformanceTest, TexelBuffers) {
  // One 512-byte buffer bound three ways in a compute shader: bytes 256.. as a uniform texel
  // buffer of RGBA8 (texel i = (10i, 20i, 30i, 255)), bytes 0..255 as a storage texel buffer of
  // RGBA32F (16 texels, texel 0 = (1, 2, 3, 4)), and bytes 256.. again as R32_UINT. The shader
  // stores texel 0 + texelFetch(rgba8, 2) at storage texel 1 and the R32_UINT texel 3 (the
  // RGBA8 texel 3 read as one little-endian word) as a float at texel 2.
  std::vector<uint8_t> data(512, 0);
  const float first[4] = {1, 2, 3, 4};
  std::memcpy(data.data(), first, sizeof(first));
  for (int i = 0; i < 64; ++i) {
    data[256 + 4 * i] = uint8_t(10 * (i % 8)), data[256 + 4 * i + 1] = uint8_t(20 * (i % 8));
    data[256 + 4 * i + 2] = uint8_t(30 * (i % 8)), data[256 + 4 * i + 3] = 255;
  }
  BufferHandle b = buffer(data.size(), data.data());
  ComputePipelineHandle p = computePipeline(R"(#version 450
layout(local_size_x = 1) in;
layout(set = 0, binding = 0, rgba32f) uniform imageBuffer floats;
layout(set = 0, binding = 1) uniform samplerBuffer unorms;
layout(set = 0, binding = 2) uniform usamplerBuffer words;
void main() {
  imageStore(floats, 1, imageLoad(floats, 0) + texelFetch(unorms, 2));
  imageStore(floats, 2, vec4(float(texelFetch(words, 3).r), 0.0, 0.0, 1.0));
})");
  std::array<ResourceBinding, 3> r{};
  r[0].binding = 0, r[0].kind = BindingKind::StorageTexelBuffer, r[0].buffer = b, r[0].size = 256;
  r[0].texelFormat = Format::RGBA32F;
  r[1].binding = 1, r[1].kind = BindingKind::UniformTexelBuffer, r[1].buffer = b, r[1].offset = 256;
  r[1].texelFormat = Format::RGBA8;
  r[2].binding = 2, r[2].kind = BindingKind::UniformTexelBuffer, r[2].buffer = b, r[2].offset = 256;
  r[2].texelFormat = Format::R32_UINT;
  dev->setBindings(r);
  dev->setComputePipeline(p);
  dev->dispatch(1);
  std::vector<uint8_t> out = dev->readBuffer(b, 0, 48);
  // Texel 1: (1 + 20/255, 2 + 40/255, 3 + 60/255, 4 + 1); texel 2: 0xFF5A3C1E = (30, 60, 90, 255).
  const float want1[4] = {1 + 20 / 255.0f, 2 + 40 / 255.0f, 3 + 60 / 255.0f, 5};
  for (int c = 0; c < 4; ++c) EXPECT_FLOAT_EQ(load<float>(out, 16 + 4 * c), want1[c]) << "texel 1 channel " << c;
  EXPECT_EQ(load<float>(out, 32), float(0xFF5A3C1Eu));
  EXPECT_EQ(load<float>(out, 44), 1.0f);
  // Texel 0 is unchanged.
  for (int c = 0; c < 4; ++c) EXPECT_EQ(load<float>(out, 4 * c), first[c]);
}

// ---------------------------------------------------------------------------------------------
// Geometry and tessellation stages
// ---------------------------------------------------------------------------------------------
// The rect shader covers the left half; a later stage moves every vertex one NDC unit right and
// colours it, so only a pipeline that ran that stage fills the right half (and leaves the left
// half clear).
const char* kShiftRightGs = R"(#version 450
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;
layout(location = 0) out vec4 gColor;
void main() {
  for (int i = 0; i < 3; ++i) {
    gl_Position = gl_in[i].gl_Position + vec4(1.0, 0.0, 0.0, 0.0);
    gColor = vec4(0.0, 1.0, 0.0, 1.0);
    EmitVertex();
  }
  EndPrimitive();
})";

const char* kPassPatchTcs = R"(#version 450
layout(vertices = 3) out;
void main() {
  gl_out[gl_InvocationID].gl_Position = gl_in[gl_InvocationID].gl_Position;
  if (gl_InvocationID == 0) {
    gl_TessLevelOuter[0] = gl_TessLevelOuter[1] = gl_TessLevelOuter[2] = 2.0;
    gl_TessLevelInner[0] = 2.0;
  }
})";

const char* kShiftRightTes = R"(#version 450
layout(triangles, equal_spacing, ccw) in;
layout(location = 0) out vec4 tColor;
void main() {
  vec4 p = gl_TessCoord.x * gl_in[0].gl_Position + gl_TessCoord.y * gl_in[1].gl_Position +
           gl_TessCoord.z * gl_in[2].gl_Position;
  gl_Position = p + vec4(1.0, 0.0, 0.0, 0.0);
  tColor = vec4(0.0, 0.0, 1.0, 1.0);
})";

TEST_P(RhiConformanceTest, GeometryStageRunsBetweenVertexAndFragment) {
  TextureHandle t = texture(Format::RGBA8, 16, 16);
  PipelineDesc d = rectDesc(Format::RGBA8);
  d.geometryShader = shader(ShaderStage::Geometry, kShiftRightGs);
  d.label = "conformance geometry";
  PipelineHandle p = pipeline(d);
  dev->beginPass(pass(t));
  dev->setPipeline(p);
  drawRect({-1.0f, -1.0f, 0.0f, 1.0f}, unorm(255, 0, 0, 255));
  dev->endPass();
  expectRgba8Image(read(t), 16, 16, [](uint32_t x, uint32_t) { return x >= 8 ? Px{0, 255, 0, 255} : Px{0, 0, 0, 0}; });
}

TEST_P(RhiConformanceTest, TessellationStagesDrawPatches) {
  TextureHandle t = texture(Format::RGBA8, 16, 16);
  PipelineDesc d = rectDesc(Format::RGBA8);
  d.tessControlShader = shader(ShaderStage::TessControl, kPassPatchTcs);
  d.tessEvaluationShader = shader(ShaderStage::TessEvaluation, kShiftRightTes);
  d.topology = PrimitiveTopology::Patches;
  d.patchControlPoints = 3;
  d.label = "conformance tessellation";
  PipelineHandle p = pipeline(d);
  dev->beginPass(pass(t));
  dev->setPipeline(p);
  drawRect({-1.0f, -1.0f, 0.0f, 1.0f}, unorm(255, 0, 0, 255));  // two patches of three control points
  dev->endPass();
  expectRgba8Image(read(t), 16, 16, [](uint32_t x, uint32_t) { return x >= 8 ? Px{0, 0, 255, 255} : Px{0, 0, 0, 0}; });
}

// A written gl_ClipDistance clips on both backends (Vulkan by every written distance; GL enables
// them for the pipeline): distance 0 = x clips the left half, distance 1 = 1 - 2y the last
// quarter of the rows; a shader writing none clips nothing.
TEST_P(RhiConformanceTest, WrittenClipDistancesClip) {
  TextureHandle t = texture(Format::RGBA8, 8, 8);
  PipelineDesc d = rectDesc(Format::RGBA8);
  d.vertexShader = shader(ShaderStage::Vertex, R"(#version 450
layout(push_constant) uniform PC { vec4 rect; vec4 color; float z; int flip; } pc;
layout(location = 0) out vec4 vColor;
out gl_PerVertex { vec4 gl_Position; float gl_ClipDistance[2]; };
void main() {
  vec2 c = vec2(gl_VertexIndex & 1, gl_VertexIndex >> 1);
  vec2 p = mix(pc.rect.xy, pc.rect.zw, c);
  gl_Position = vec4(p, pc.z, 1.0);
  gl_ClipDistance[0] = p.x;
  gl_ClipDistance[1] = 1.0 - 2.0 * p.y;
  vColor = pc.color;
})");
  d.topology = PrimitiveTopology::TriangleStrip;
  d.label = "clip distances";
  PipelineHandle clipped = pipeline(d);
  PipelineHandle plain = pipeline(rectDesc(Format::RGBA8));
  dev->beginPass(pass(t));
  dev->setPipeline(plain);  // rows 0-1 in red, unclipped
  drawRect({-1.0f, -1.0f, 1.0f, -0.5f}, unorm(255, 0, 0, 255));
  dev->setPipeline(clipped);
  RectPC pc{{-1, -0.5f, 1, 1}, {0, 1, 0, 1}, 0.5f, 0};
  dev->pushConstants(&pc, sizeof pc);
  dev->draw(4);
  dev->endPass();
  // Row r is at y = (r + 0.5) / 4 - 1: distance 1 is negative from row 6 on (y > 0.5).
  expectRgba8Image(read(t), 8, 8, [](uint32_t x, uint32_t y) {
    if (y < 2) return Px{255, 0, 0, 255};
    return x >= 4 && y < 6 ? Px{0, 255, 0, 255} : Px{0, 0, 0, 0};
  });
}

// Vulkan matches stage interfaces by location alone; GLSL without Vulkan semantics does not match
// an output block to loose inputs, so SPIRV-Cross's GLSL of this pair does not link on GL. The
// module still runs there, through GL_ARB_gl_spirv, with push constants (the rect) and a uniform
// block (the scale) at their bindings, and the device says so in a note.
TEST_P(RhiConformanceTest, InterfaceMatchedByLocationAcrossBlockAndLooseVariables) {
  TextureHandle t = texture(Format::RGBA8, 4, 4);
  const float scale[4] = {1, 1, 1, 1};
  BufferHandle ub = buffer(sizeof scale, scale, BufferUsage_Uniform);
  PipelineDesc d = rectDesc(Format::RGBA8);
  d.vertexShader = shader(ShaderStage::Vertex, R"(#version 450
layout(push_constant) uniform PC { vec4 rect; vec4 color; float z; int flip; } pc;
layout(location = 0) out Block { layout(location = 1) vec4 color; layout(location = 0) vec4 tint; } outs;
void main() {
  vec2 c = vec2(gl_VertexIndex & 1, gl_VertexIndex >> 1);
  gl_Position = vec4(mix(pc.rect.xy, pc.rect.zw, c), pc.z, 1.0);
  outs.color = pc.color;
  outs.tint = vec4(0.0, 0.0, 1.0, 1.0);
})");
  d.fragmentShader = shader(ShaderStage::Fragment, R"(#version 450
layout(location = 1) in vec4 color;
layout(location = 0) in vec4 tint;
layout(binding = 1) uniform Scale { vec4 scale; };
layout(location = 0) out vec4 o;
void main() { o = vec4(color.rg, tint.ba) * scale; })");
  d.topology = PrimitiveTopology::TriangleStrip;
  d.label = "block matched by location";
  PipelineHandle p = pipeline(d);
  ASSERT_TRUE(p);
  dev->beginPass(pass(t));
  dev->setPipeline(p);
  ResourceBinding b;
  b.binding = 1;
  b.kind = BindingKind::UniformBuffer;
  b.buffer = ub;
  dev->setBindings({&b, 1});
  RectPC pc{{-1, -1, 1, 1}, {1, 0, 0, 0}, 0.5f, 0};
  dev->pushConstants(&pc, sizeof pc);
  dev->draw(4);
  dev->endPass();
  // Swapped locations would give (0, 0, 0, 0); an unbound scale, black.
  expectRgba8Image(read(t), 4, 4, [](uint32_t, uint32_t) { return Px{255, 0, 255, 255}; });
  const std::vector<std::string> notes = dev->takeNotes();
  if (dev->info().backend == "gl") {
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_NE(notes[0].find("block matched by location: ran through GL_ARB_gl_spirv"), std::string::npos) << notes[0];
  } else {
    EXPECT_TRUE(notes.empty());
  }
}

INSTANTIATE_TEST_SUITE_P(Rhi, RhiConformanceTest, ::testing::ValuesIn(allBackends()), BackendName());

}  // namespace
}  // namespace parity::rhi
