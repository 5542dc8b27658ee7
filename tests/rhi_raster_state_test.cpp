// Conformance of the rasterisation state in rhi::RasterState and the adjacency topologies, on
// every backend. Expected values are worked out from the Vulkan specification's formulas (which
// rhi.h adopts), never taken from a backend: the depth a bias must produce for the format, the
// pixels a point or a line through pixel centres covers, the vertices a geometry shader receives
// for each adjacency primitive.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "rhi/rhi.h"
#include "tests/test_support.h"

namespace parity::rhi {
namespace {

using parity::test::allBackends;
using parity::test::BackendName;

constexpr uint32_t kSize = 16;

// A triangle strip covering a rectangle (NDC), its depth varying linearly from zLeft at NDC x = -1
// to zRight at NDC x = +1 (so the depth slope is the same everywhere and lies along x only).
const char* kRectVs = R"(#version 450
layout(push_constant) uniform PC { vec4 rect; float zLeft; float zRight; } pc;
void main() {
  vec2 c = vec2(gl_VertexIndex & 1, gl_VertexIndex >> 1);
  vec2 p = mix(pc.rect.xy, pc.rect.zw, c);
  gl_Position = vec4(p, mix(pc.zLeft, pc.zRight, (p.x + 1.0) * 0.5), 1.0);
  gl_PointSize = 1.0;
})";

struct RectPC {
  float rect[4];
  float zLeft, zRight;
};

const char* kWhiteFs = R"(#version 450
layout(location = 0) out vec4 o;
void main() { o = vec4(1.0); })";

// Vertices at given pixel positions (push constants), one per gl_VertexIndex.
const char* kPixelVs = R"(#version 450
layout(push_constant) uniform PC { vec2 px[3]; } pc;
void main() {
  gl_Position = vec4(pc.px[gl_VertexIndex] / 8.0 - 1.0, 0.5, 1.0);  // 16x16 target
  gl_PointSize = 1.0;
})";

class RhiRasterStateTest : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    dev = parity::test::makeDevice(GetParam());
    if (!dev) GTEST_SKIP() << "backend " << GetParam() << " unavailable";
  }
  void TearDown() override { dev.reset(); }

  TextureHandle texture(Format f) {
    TextureDesc d;
    d.format = f;
    d.width = d.height = kSize;
    d.label = "raster state";
    TextureHandle t = dev->createTexture(d);
    EXPECT_TRUE(t);
    return t;
  }
  PipelineDesc desc(const char* vs, const char* fs = kWhiteFs) {
    PipelineDesc d;
    d.vertexShader = parity::test::makeShader(*dev, ShaderStage::Vertex, vs);
    d.fragmentShader = parity::test::makeShader(*dev, ShaderStage::Fragment, fs);
    d.colorTargetCount = 1;
    d.colorTargets[0].format = Format::RGBA8;
    d.label = "raster state";
    return d;
  }
  PipelineHandle pipeline(const PipelineDesc& d) {
    PipelineHandle p = dev->createPipeline(d);
    EXPECT_TRUE(p) << "createPipeline";
    return p;
  }

  // Draws the rectangle (full target unless given) with `bias` into a fresh depth target of
  // `format` and returns its depth readback.
  std::vector<float> biasedDepths(Format format, const DepthBias& bias, float zLeft, float zRight,
                                  bool depthClamp = false, Viewport viewport = {}) {
    TextureHandle color = texture(Format::RGBA8), depth = texture(format);
    PipelineDesc d = desc(kRectVs);
    d.topology = PrimitiveTopology::TriangleStrip;
    d.depthStencilFormat = format;
    d.depthStencil.depthWrite = true;
    d.raster.depthBias = bias;
    d.raster.depthClampEnabled = depthClamp;
    PipelineHandle p = pipeline(d);
    PassDesc pass;
    pass.colors[0].texture = color;
    pass.depthStencil.texture = depth;
    pass.depthStencil.clearDepth = 0.0f;
    dev->beginPass(pass);
    dev->setPipeline(p);
    dev->setViewport(viewport);
    RectPC pc{{-1, -1, 1, 1}, zLeft, zRight};
    dev->pushConstants(&pc, sizeof pc);
    dev->draw(4);
    dev->endPass();
    std::vector<uint8_t> bytes = dev->readTexture(depth, ReadbackRegion{0, 0, TextureAspect::Depth});
    std::vector<float> out(kSize * kSize);
    EXPECT_EQ(bytes.size(), out.size() * 4);
    if (bytes.size() == out.size() * 4) std::memcpy(out.data(), bytes.data(), bytes.size());
    return out;
  }

  // The pixels (x, y) lit by a draw of the vertices at pixel positions `px` (x, y pairs).
  std::set<std::pair<uint32_t, uint32_t>> litPixels(const PipelineDesc& d, const std::vector<float>& px) {
    TextureHandle color = texture(Format::RGBA8);
    PipelineHandle p = pipeline(d);
    PassDesc pass;
    pass.colors[0].texture = color;
    dev->beginPass(pass);
    dev->setPipeline(p);
    float pc[6] = {};  // vec2 px[3]: 8-byte stride in push constants (std430)
    std::memcpy(pc, px.data(), px.size() * sizeof(float));
    dev->pushConstants(pc, sizeof pc);
    dev->draw(static_cast<uint32_t>(px.size() / 2));
    dev->endPass();
    return lit(color);
  }
  // The pixels (x, y) of an RGBA8 target whose red channel is not 0.
  std::set<std::pair<uint32_t, uint32_t>> lit(TextureHandle color) {
    std::vector<uint8_t> rgba = dev->readTexture(color);
    std::set<std::pair<uint32_t, uint32_t>> out;
    for (uint32_t y = 0; y < kSize; ++y)
      for (uint32_t x = 0; x < kSize; ++x)
        if (rgba[(size_t(y) * kSize + x) * 4] != 0) out.insert({x, y});
    return out;
  }

  std::unique_ptr<Device> dev;
};

// ---------------------------------------------------------------------------------------------
// Depth bias
// ---------------------------------------------------------------------------------------------
TEST_P(RhiRasterStateTest, DepthBiasConstantD24S8) {
  // D24: r is one step, 1 / (2^24 - 1), or up to twice that (VK-GL-CTS's depth_bias cases accept
  // 2^-24 and 2^-23; Mesa takes twice). z = 0.2 is 3355443.05 steps (0.2f is 0.20000000298), so
  // 4096 units store round(3355443.05 + 4096) = 3359539 or, at 2r, 3363635, read back as
  // q / (2^24 - 1); -4096 units 3351347 or 3347251.
  auto steps = [](float depth) { return static_cast<long>(std::lround(double(depth) * 16777215.0)); };
  auto oneOf = [](long q, long a, long b) { return q == a || q == b; };
  std::vector<float> d = biasedDepths(Format::D24S8, {4096, 0, 0}, 0.2f, 0.2f);
  const long q = steps(d[0]);
  EXPECT_TRUE(oneOf(q, 3359539, 3363635)) << q;
  for (uint32_t i = 0; i < d.size(); ++i) ASSERT_EQ(steps(d[i]), q) << "pixel " << i % kSize << ", " << i / kSize;
  d = biasedDepths(Format::D24S8, {-4096, 0, 0}, 0.2f, 0.2f);
  EXPECT_EQ(steps(d[0]), q == 3359539 ? 3351347 : 3347251) << "the same r for a negative factor";
}

TEST_P(RhiRasterStateTest, DepthBiasConstantD32F) {
  // D32F: r = 2^(e - 23) with e the exponent of the primitive's largest depth. For z = 0.375
  // (1.5 * 2^-2) r = 2^-25, so 1024 units add 2^-15; for z = 0.75 (1.5 * 2^-1) r = 2^-24.
  std::vector<float> d = biasedDepths(Format::D32F, {1024, 0, 0}, 0.375f, 0.375f);
  for (uint32_t i = 0; i < d.size(); ++i)
    ASSERT_EQ(d[i], 0.375f + std::ldexp(1.0f, -15)) << "pixel " << i % kSize << ", " << i / kSize;
  d = biasedDepths(Format::D32F, {1024, 0, 0}, 0.75f, 0.75f);
  EXPECT_EQ(d[0], 0.75f + std::ldexp(1.0f, -14));
}

TEST_P(RhiRasterStateTest, DepthBiasSlopeAndClamp) {
  // Depth 0 at the left edge to 0.5 at the right, 16 pixels: dz/dx = 1/32, dz/dy = 0, so the
  // maximum slope m is 1/32 whichever of the spec's two formulas the device uses. Pixel x's
  // centre has z = (x + 0.5) / 32; slope factor 2 adds 2m = 1/16 (D32F, no constant: r plays no
  // part). All values are exact in binary.
  std::vector<float> d = biasedDepths(Format::D32F, {0, 2, 0}, 0.0f, 0.5f);
  for (uint32_t y = 0; y < kSize; ++y)
    for (uint32_t x = 0; x < kSize; ++x)
      ASSERT_EQ(d[y * kSize + x], (x + 0.5f) / 32.0f + 1.0f / 16.0f) << "pixel " << x << ", " << y;
  if (std::find(dev->info().features.begin(), dev->info().features.end(), "depthBiasClamp") == dev->info().features.end())
    GTEST_SKIP() << "no depthBiasClamp on " << dev->info().renderer;
  // Clamp 1/64 caps the offset: min(1/16, 1/64). A negative clamp bounds a negative bias.
  d = biasedDepths(Format::D32F, {0, 2, 1.0f / 64}, 0.0f, 0.5f);
  for (uint32_t x = 0; x < kSize; ++x) EXPECT_EQ(d[x], (x + 0.5f) / 32.0f + 1.0f / 64.0f) << "pixel " << x;
  d = biasedDepths(Format::D32F, {0, -2, -1.0f / 64}, 0.25f, 0.75f);
  for (uint32_t x = 0; x < kSize; ++x) EXPECT_EQ(d[x], 0.25f + (x + 0.5f) / 32.0f - 1.0f / 64.0f) << "pixel " << x;
}

// ---------------------------------------------------------------------------------------------
// Depth clamp
// ---------------------------------------------------------------------------------------------
TEST_P(RhiRasterStateTest, DepthClamp) {
  // Viewport depth range [0.25, 0.75]: z = 1.5 maps to 1.0 and z = -0.5 to 0.0, both outside.
  // Without depth clamp the rectangle is clipped away (the depth keeps its clear value 0); with
  // it, nothing is clipped in z and depths are clamped to the range.
  Viewport vp;
  vp.minDepth = 0.25f;
  vp.maxDepth = 0.75f;
  std::vector<float> clipped = biasedDepths(Format::D32F, {}, 1.5f, 1.5f, false, vp);
  for (uint32_t i = 0; i < clipped.size(); ++i) ASSERT_EQ(clipped[i], 0.0f) << "pixel " << i;
  std::vector<float> far = biasedDepths(Format::D32F, {}, 1.5f, 1.5f, true, vp);
  for (uint32_t i = 0; i < far.size(); ++i) ASSERT_EQ(far[i], 0.75f) << "pixel " << i;
  std::vector<float> near = biasedDepths(Format::D32F, {}, -0.5f, -0.5f, true, vp);
  for (uint32_t i = 0; i < near.size(); ++i) ASSERT_EQ(near[i], 0.25f) << "pixel " << i;
}

// ---------------------------------------------------------------------------------------------
// Polygon modes
// ---------------------------------------------------------------------------------------------
TEST_P(RhiRasterStateTest, PolygonModePoint) {
  // A triangle drawn as points: its three vertices, at pixel centres, light exactly their pixels.
  PipelineDesc d = desc(kPixelVs);
  d.raster.polygonMode = PolygonMode::Point;
  std::set<std::pair<uint32_t, uint32_t>> want{{2, 1}, {12, 1}, {2, 9}};
  EXPECT_EQ(litPixels(d, {2.5f, 1.5f, 12.5f, 1.5f, 2.5f, 9.5f}), want);
}

TEST_P(RhiRasterStateTest, PolygonModeLine) {
  // A right isosceles triangle with vertices at pixel centres (2,2), (12,2), (2,12) drawn as
  // lines: the horizontal, vertical and 45-degree edges pass through pixel centres, which every
  // line rule Vulkan and GL allow lights, and lie at least 0.7 px from any other centre. The
  // interior stays unlit.
  PipelineDesc d = desc(kPixelVs);
  d.raster.polygonMode = PolygonMode::Line;
  std::set<std::pair<uint32_t, uint32_t>> lit = litPixels(d, {2.5f, 2.5f, 12.5f, 2.5f, 2.5f, 12.5f});
  std::set<std::pair<uint32_t, uint32_t>> want;
  for (uint32_t k = 0; k <= 10; ++k) want.insert({{2 + k, 2}, {2, 2 + k}, {12 - k, 2 + k}});
  // Where a line ends is the one thing the rules differ on (GL's diamond exit leaves a line's
  // last pixel to the next line, Bresenham and rectangle rules may light it): the vertices' pixels
  // are checked by neither set.
  for (auto v : {std::pair<uint32_t, uint32_t>{2, 2}, {12, 2}, {2, 12}}) {
    want.erase(v);
    lit.erase(v);
  }
  EXPECT_EQ(lit, want);
}

// ---------------------------------------------------------------------------------------------
// Adjacency topologies
// ---------------------------------------------------------------------------------------------
// The geometry shader writes, for primitive p, one point at pixel (j, p) per input vertex j whose
// red channel is that vertex's gl_VertexIndex / 255: the image lists the vertices each primitive
// received, in the order the shader saw them.
std::string adjacencyGs(const char* layout, int vertices) {
  return std::string("#version 450\nlayout(") + layout + ") in;\n" +
         "layout(points, max_vertices = " + std::to_string(vertices) + ") out;\n" +
         "layout(location = 0) flat in int vIndex[];\n"
         "layout(location = 0) flat out int gIndex;\n"
         "void main() {\n"
         "  for (int j = 0; j < " + std::to_string(vertices) + "; ++j) {\n"
         "    gl_Position = vec4((vec2(j, gl_PrimitiveIDIn) + 0.5) / 8.0 - 1.0, 0.5, 1.0);\n"
         "    gl_PointSize = 1.0;\n"
         "    gIndex = vIndex[j];\n"
         "    EmitVertex();\n"
         "  }\n"
         "}\n";
}

const char* kIndexVs = R"(#version 450
layout(location = 0) flat out int vIndex;
void main() { vIndex = gl_VertexIndex; gl_Position = vec4(0.0, 0.0, 0.5, 1.0); })";

const char* kIndexFs = R"(#version 450
layout(location = 0) flat in int gIndex;
layout(location = 0) out vec4 o;
void main() { o = vec4(float(gIndex + 1) / 255.0, 0.0, 0.0, 1.0); })";

struct AdjacencyCase {
  PrimitiveTopology topology;
  const char* layout;
  int verticesPerPrimitive;
  uint32_t vertexCount;
  std::vector<std::vector<int>> primitives;  // the vertex indices each primitive receives, in order
};

TEST_P(RhiRasterStateTest, AdjacencyTopologies) {
  // The vertex order of each primitive is the specifications' table: lists take 4 or 6 vertices
  // at a time, a line strip slides by one. A triangle strip of 8 vertices is two triangles, the
  // first 0, 2, 4 with edge neighbours 1, 6, 3, the second (odd: winding swapped) 4, 2, 6 with
  // neighbours 0, 5, 7, listed as (vertex, neighbour) pairs. Which vertex of an odd triangle comes
  // first differs between the GL tables (2i + 2) and Mesa on both APIs (2i), so for strips the
  // check fixes the triangle, its winding and each edge's neighbour but not the starting pair.
  const AdjacencyCase cases[] = {
      {PrimitiveTopology::LinesWithAdjacency, "lines_adjacency", 4, 8, {{0, 1, 2, 3}, {4, 5, 6, 7}}},
      {PrimitiveTopology::LineStripWithAdjacency, "lines_adjacency", 4, 6, {{0, 1, 2, 3}, {1, 2, 3, 4}, {2, 3, 4, 5}}},
      {PrimitiveTopology::TrianglesWithAdjacency, "triangles_adjacency", 6, 12, {{0, 1, 2, 3, 4, 5}, {6, 7, 8, 9, 10, 11}}},
      {PrimitiveTopology::TriangleStripWithAdjacency, "triangles_adjacency", 6, 8, {{0, 1, 2, 6, 4, 3}, {4, 0, 2, 5, 6, 7}}},
  };
  for (const AdjacencyCase& c : cases) {
    SCOPED_TRACE(c.layout + std::string(" topology ") + std::to_string(int(c.topology)));
    PipelineDesc d = desc(kIndexVs, kIndexFs);
    d.geometryShader = parity::test::makeShader(*dev, ShaderStage::Geometry, adjacencyGs(c.layout, c.verticesPerPrimitive));
    d.topology = c.topology;
    TextureHandle color = texture(Format::RGBA8);
    PipelineHandle p = pipeline(d);
    PassDesc pass;
    pass.colors[0].texture = color;
    dev->beginPass(pass);
    dev->setPipeline(p);
    dev->draw(c.vertexCount);
    dev->endPass();
    std::vector<uint8_t> rgba = dev->readTexture(color);
    auto received = [&](uint32_t primitive) {
      std::vector<int> v;
      for (uint32_t x = 0; x < kSize; ++x) v.push_back(rgba[(size_t(primitive) * kSize + x) * 4] - 1);
      return v;
    };
    for (uint32_t y = 0; y < kSize; ++y) {
      std::vector<int> got = received(y), want(kSize, -1);
      if (y < c.primitives.size()) std::copy(c.primitives[y].begin(), c.primitives[y].end(), want.begin());
      const bool anyStart = c.topology == PrimitiveTopology::TriangleStripWithAdjacency && y < c.primitives.size();
      for (int shift = 2; anyStart && got != want && shift < 6; shift += 2) {
        std::vector<int> rotated = got;
        std::rotate(rotated.begin(), rotated.begin() + shift, rotated.begin() + 6);
        if (rotated == want) got = rotated;
      }
      EXPECT_EQ(got, want) << "primitive " << y;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Viewport indices
// ---------------------------------------------------------------------------------------------
// A geometry shader selects the viewport (gl_ViewportIndex). setViewport and setScissor set every
// index a shader may select alike, as glViewport and glScissor do: any index draws the same.
const char* kViewportIndexVs = R"(#version 450
layout(push_constant) uniform PC { int viewportIndex; } pc;
void main() {
  gl_Position = vec4(vec2(gl_VertexIndex & 1, gl_VertexIndex >> 1) * 2.0 - 1.0, 0.5, 1.0);
})";

const char* kViewportIndexGs = R"(#version 450
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;
layout(push_constant) uniform PC { int viewportIndex; } pc;
void main() {
  for (int i = 0; i < 3; ++i) {
    gl_Position = gl_in[i].gl_Position;
    gl_ViewportIndex = pc.viewportIndex;
    EmitVertex();
  }
})";

TEST_P(RhiRasterStateTest, ViewportAndScissorHoldAtEveryViewportIndex) {
  const uint32_t viewports = dev->info().caps.viewports;
  ASSERT_GE(viewports, 1u);
  ASSERT_LE(viewports, kMaxViewports);
  if (viewports == 1) GTEST_SKIP() << dev->info().renderer << " has one viewport";
  PipelineDesc d = desc(kViewportIndexVs);
  d.geometryShader = parity::test::makeShader(*dev, ShaderStage::Geometry, kViewportIndexGs);
  d.topology = PrimitiveTopology::TriangleStrip;
  d.raster.scissorEnabled = true;
  PipelineHandle p = pipeline(d);
  // The left half is the viewport, the lower half (rows 0-7) the scissor: the full-viewport
  // rectangle lights the quarter x < 8, y < 8 whichever index the shader picks.
  std::set<std::pair<uint32_t, uint32_t>> want;
  for (uint32_t y = 0; y < 8; ++y)
    for (uint32_t x = 0; x < 8; ++x) want.insert({x, y});
  for (int32_t index : {0, 1, static_cast<int32_t>(viewports) - 1}) {
    SCOPED_TRACE("gl_ViewportIndex " + std::to_string(index));
    TextureHandle color = texture(Format::RGBA8);
    PassDesc pass;
    pass.colors[0].texture = color;
    dev->beginPass(pass);
    dev->setPipeline(p);
    dev->setViewport(Viewport{0, 0, 8, kSize});
    dev->setScissor(Rect{0, 0, kSize, 8});
    dev->pushConstants(&index, sizeof index);
    dev->draw(4);
    dev->endPass();
    EXPECT_EQ(lit(color), want);
  }
}

// Each vertex's index as a flat value: the provoking vertex's reaches every fragment.
const char* kFlatIndexVs = R"(#version 450
layout(location = 0) flat out int vertexIndex;
void main() {
  const vec2 corners[3] = vec2[](vec2(-1.0, -1.0), vec2(3.0, -1.0), vec2(-1.0, 3.0));
  gl_Position = vec4(corners[gl_VertexIndex], 0.5, 1.0);
  vertexIndex = gl_VertexIndex;
})";
const char* kFlatIndexFs = R"(#version 450
layout(location = 0) flat in int vertexIndex;
layout(location = 0) out vec4 o;
void main() { o = vec4(float(vertexIndex + 1) / 4.0, 0.0, 0.0, 1.0); })";

TEST_P(RhiRasterStateTest, FlatInputsTakeTheProvokingVertexValues) {
  for (ProvokingVertex provoking : {ProvokingVertex::First, ProvokingVertex::Last}) {
    const bool last = provoking == ProvokingVertex::Last;
    SCOPED_TRACE(last ? "last" : "first");
    const auto& features = dev->info().features;
    if (last && std::find(features.begin(), features.end(), "provokingVertexLast") == features.end()) {
      // Without the feature the pipeline is refused, never drawn with the first vertex's values.
      PipelineDesc d = desc(kFlatIndexVs, kFlatIndexFs);
      d.raster.provokingVertex = provoking;
      EXPECT_FALSE(dev->createPipeline(d));
      continue;
    }
    PipelineDesc d = desc(kFlatIndexVs, kFlatIndexFs);
    d.raster.provokingVertex = provoking;
    PipelineHandle p = pipeline(d);
    TextureHandle color = texture(Format::RGBA8);
    PassDesc pass;
    pass.colors[0].texture = color;
    dev->beginPass(pass);
    dev->setPipeline(p);
    dev->draw(3);
    dev->endPass();
    const std::vector<uint8_t> rgba = dev->readTexture(color);
    ASSERT_EQ(rgba.size(), size_t(kSize) * kSize * 4);
    const int want = last ? 191 : 64;  // (2 + 1) / 4 or (0 + 1) / 4 of 255, rounded
    for (size_t i = 0; i < rgba.size(); i += 4) ASSERT_NEAR(rgba[i], want, 1) << "pixel " << i / 4;
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, RhiRasterStateTest, ::testing::ValuesIn(allBackends()), BackendName());

}  // namespace
}  // namespace parity::rhi
