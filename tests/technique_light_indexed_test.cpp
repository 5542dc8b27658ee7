// Light-indexed deferred rendering (Trebilco 2008): the packing schemes' unpacking against
// integer bit logic (CPU mirror and GPU shader), and every packing against the float forward
// reference where the overlaps fit, losing exactly the lights the packing drops where they do not.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <set>

#include <glm/glm.hpp>

#include "rhi/shader_compiler.h"
#include "scene/scene.h"
#include "techniques/frame.h"
#include "techniques/light_indexed/lidr_packing.h"
#include "tests/test_support.h"

using namespace parity;
using techniques::BitPackingLayout;
using techniques::ChannelBytes;
using techniques::UnpackedIndices;

namespace {

// Deterministic byte stream for the channels a test does not sweep.
uint8_t mixByte(uint32_t a, uint32_t b) {
  uint32_t x = a * 2654435761u ^ (b + 0x9e3779b9u) * 40503u;
  x ^= x >> 13;
  x *= 0x5bd1e995u;
  return static_cast<uint8_t>(x >> 24);
}

TEST(LidrPacking, TableRowsArePresent) {
  std::set<std::string> labels;
  for (const BitPackingLayout& row : techniques::bitPackingRows()) labels.insert(row.label());
  for (const char* want : {"1x255", "2x255", "4x255", "8x255", "2x15", "4x15", "8x15"})
    EXPECT_TRUE(labels.count(want)) << want;
  const BitPackingLayout* four = techniques::findBitPackingRow("4x255");
  ASSERT_NE(four, nullptr);
  EXPECT_EQ(four->chunkBits(), 2u);
  EXPECT_FLOAT_EQ(four->blendConstant(), 0.25f);  // the paper's CONSTANT_COLOR
}

// The paper's float unpacking equals integer shifts and masks for every byte value of every
// channel of every row (each channel swept through 0..255 with the others varying).
TEST(LidrPacking, BitUnpackEqualsIntegerLogicForEveryRow) {
  for (const BitPackingLayout& row : techniques::bitPackingRows()) {
    size_t checked = 0;
    for (uint32_t c = 0; c < row.channels; ++c)
      for (uint32_t v = 0; v < 256; ++v)
        for (uint32_t salt = 0; salt < 8; ++salt) {
          ChannelBytes bytes{};
          for (uint32_t k = 0; k < row.channels; ++k) bytes[k] = k == c ? static_cast<uint8_t>(v) : mixByte(v * 8 + salt, k);
          UnpackedIndices paper = techniques::unpackBitsPaper(row, bytes), exact = techniques::unpackBitsInteger(row, bytes);
          ASSERT_EQ(paper, exact) << row.label() << " channel " << c << " value " << v;
          ++checked;
        }
    EXPECT_GT(checked, 0u);
  }
}

// Packing n <= overlaps lights by the blend model and unpacking gives them back, oldest first
// after the empty slots; more than overlaps keeps the first overlaps (the stencil holds the rest).
TEST(LidrPacking, BitPackingRoundTrip) {
  for (const BitPackingLayout& row : techniques::bitPackingRows()) {
    for (uint32_t n = 0; n <= row.overlaps() + 2; ++n) {
      for (uint32_t trial = 0; trial < 200; ++trial) {
        std::vector<uint32_t> order;
        for (uint32_t i = 0; i < n; ++i) order.push_back(1 + mixByte(trial * 31 + i, n) % row.maxLights());
        UnpackedIndices got = techniques::unpackBitsPaper(row, techniques::simulateBitPacking(row, order));
        uint32_t kept = std::min(n, row.overlaps());
        for (uint32_t i = 0; i < row.overlaps(); ++i) {
          uint32_t slot = row.overlaps() - kept;
          uint32_t want = i < slot ? 0u : order[i - slot];
          ASSERT_EQ(got[i], want) << row.label() << " n=" << n << " slot " << i;
        }
      }
    }
  }
}

TEST(LidrPacking, MaxUnpackRules) {
  // Every red/green pair: Index1 = R; Index2 = 255 - G unless equal to R or R is the null light.
  for (uint32_t r = 0; r < 256; ++r)
    for (uint32_t g = 0; g < 256; ++g) {
      UnpackedIndices u = techniques::unpackMax({static_cast<uint8_t>(r), static_cast<uint8_t>(g), static_cast<uint8_t>(r),
                                                 static_cast<uint8_t>(g)});
      uint32_t second = (r != 0 && 255 - g != r) ? 255 - g : 0;
      ASSERT_EQ(u[0], r);
      ASSERT_EQ(u[1], second);
      ASSERT_EQ(u[2], r);
      ASSERT_EQ(u[3], second);
    }
  // 1 to 4 distinct lights come back as a set ("ignore if equal" removes the duplicates of 1 and 3).
  for (uint32_t n = 1; n <= 6; ++n) {
    std::vector<uint32_t> order;
    for (uint32_t i = 0; i < n; ++i) order.push_back(10 + 37 * i);
    UnpackedIndices u = techniques::unpackMax(techniques::simulateMaxPacking(order));
    std::multiset<uint32_t> got;
    for (uint32_t v : u)
      if (v) got.insert(v);
    if (n <= 4) {
      EXPECT_EQ(got, std::multiset<uint32_t>(order.begin(), order.end())) << n;
    } else {
      EXPECT_EQ(got.size(), 4u) << n;  // the extreme two of each pass; n - 4 lost
      EXPECT_TRUE(got.count(order[0]) && got.count(order[1])) << n;
    }
  }
}

// The shader (lidr_unpack.glsl) on the GPU: every row decodes two 256x256 RGBA8 textures in
// which each channel takes every byte value, bit-exactly as the CPU mirror and the integer logic.
class LidrGpu : public ::testing::TestWithParam<std::string> {};

TEST_P(LidrGpu, UnpackShaderIsBitExact) {
  auto device = test::makeDevice(GetParam());
  if (!device) return;
  constexpr uint32_t kSize = 256;
  std::vector<uint8_t> a(kSize * kSize * 4), b(kSize * kSize * 4);
  for (uint32_t y = 0; y < kSize; ++y)
    for (uint32_t x = 0; x < kSize; ++x) {
      uint8_t* pa = &a[(y * kSize + x) * 4];
      uint8_t* pb = &b[(y * kSize + x) * 4];
      pa[0] = static_cast<uint8_t>(x);
      pa[1] = static_cast<uint8_t>(y);
      pa[2] = static_cast<uint8_t>(x ^ y);
      pa[3] = mixByte(x, y);
      pb[0] = static_cast<uint8_t>(y);
      pb[1] = static_cast<uint8_t>(x);
      pb[2] = static_cast<uint8_t>(x + y);
      pb[3] = mixByte(y, x);
    }
  rhi::TextureDesc td;
  td.width = td.height = kSize;
  td.usage = rhi::TextureUsage_Sampled;
  td.initialData = a.data();
  rhi::TextureHandle ta = device->createTexture(td);
  td.initialData = b.data();
  rhi::TextureHandle tb = device->createTexture(td);

  const auto& rows = techniques::bitPackingRows();
  const uint32_t schemes = static_cast<uint32_t>(rows.size()) + 2;  // bit rows, then max, sort
  rhi::BufferDesc bd;
  bd.size = static_cast<size_t>(kSize) * kSize * schemes * 8 * sizeof(uint32_t);
  bd.usage = rhi::BufferUsage_Storage;
  rhi::BufferHandle out = device->createBuffer(bd);
  std::vector<uint32_t> rowParams;
  for (const BitPackingLayout& row : rows) {
    rowParams.push_back(row.channels);
    rowParams.push_back(row.indexBits);
  }
  rhi::BufferDesc pd;
  pd.size = rowParams.size() * sizeof(uint32_t);
  pd.usage = rhi::BufferUsage_Storage;
  pd.initialData = rowParams.data();
  rhi::BufferHandle params = device->createBuffer(pd);

  std::string source = R"(#version 450
#include "lidr_unpack.glsl"
layout(local_size_x = 16, local_size_y = 16) in;
layout(set = 0, binding = 0) uniform sampler2D packedA;
layout(set = 0, binding = 1) uniform sampler2D packedB;
layout(set = 0, binding = 2, std430) writeonly buffer Out { uint decoded[]; };
layout(set = 0, binding = 3, std430) readonly buffer Rows { uvec2 rows[]; };
void store(uint scheme, uint indices[LIDR_MAX_INDICES]) {
  uint base = ((scheme * 256u + gl_GlobalInvocationID.y) * 256u + gl_GlobalInvocationID.x) * 8u;
  for (uint i = 0u; i < 8u; ++i) decoded[base + i] = indices[i];
}
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  vec4 a = texelFetch(packedA, p, 0), b = texelFetch(packedB, p, 0);
  uint indices[LIDR_MAX_INDICES];
  uint rowCount = uint(rows.length());
  for (uint r = 0u; r < rowCount; ++r) {
    lidrUnpackBits(a, b, rows[r].x, rows[r].y, indices);
    store(r, indices);
  }
  lidrUnpackMax(a, indices);
  store(rowCount, indices);
  lidrUnpackSort(a, indices);
  store(rowCount + 1u, indices);
}
)";
  rhi::ShaderCompileOptions options;
  options.includeDirs.push_back(rhi::shaderDirectory() + "/light_indexed");
  rhi::CompiledShader compiled = rhi::compileGlslSource(source, "lidr_unpack_test.comp", rhi::ShaderStage::Compute, options);
  ASSERT_TRUE(compiled.ok()) << compiled.error;
  rhi::ShaderDesc sd;
  sd.stage = rhi::ShaderStage::Compute;
  sd.spirv = compiled.spirv;
  rhi::ShaderHandle cs = device->createShader(sd);
  rhi::ComputePipelineDesc cd;
  cd.computeShader = cs;
  rhi::ComputePipelineHandle pipeline = device->createComputePipeline(cd);
  ASSERT_TRUE(pipeline);
  rhi::ResourceBinding bindings[4];
  bindings[0].binding = 0;
  bindings[0].kind = rhi::BindingKind::SampledTexture;
  bindings[0].texture = ta;
  bindings[1].binding = 1;
  bindings[1].kind = rhi::BindingKind::SampledTexture;
  bindings[1].texture = tb;
  bindings[2].binding = 2;
  bindings[2].kind = rhi::BindingKind::StorageBuffer;
  bindings[2].buffer = out;
  bindings[3].binding = 3;
  bindings[3].kind = rhi::BindingKind::StorageBuffer;
  bindings[3].buffer = params;
  device->setComputePipeline(pipeline);
  device->setBindings(bindings);
  device->dispatch(kSize / 16, kSize / 16);
  device->submit();
  std::vector<uint8_t> raw = device->readBuffer(out, 0, bd.size);
  ASSERT_EQ(raw.size(), bd.size);
  const uint32_t* decoded = reinterpret_cast<const uint32_t*>(raw.data());

  for (uint32_t scheme = 0; scheme < schemes; ++scheme) {
    size_t mismatches = 0;
    for (uint32_t y = 0; y < kSize; ++y)
      for (uint32_t x = 0; x < kSize; ++x) {
        const uint8_t* pa = &a[(y * kSize + x) * 4];
        const uint8_t* pb = &b[(y * kSize + x) * 4];
        ChannelBytes bytes = {pa[0], pa[1], pa[2], pa[3], pb[0], pb[1], pb[2], pb[3]};
        UnpackedIndices want{};
        if (scheme < rows.size()) {
          ChannelBytes used{};
          std::copy(bytes.begin(), bytes.begin() + rows[scheme].channels, used.begin());
          want = techniques::unpackBitsInteger(rows[scheme], used);
          ASSERT_EQ(techniques::unpackBitsPaper(rows[scheme], used), want);
        } else if (scheme == rows.size()) {
          want = techniques::unpackMax({pa[0], pa[1], pa[2], pa[3]});
        } else {
          for (int c = 0; c < 4; ++c) want[c] = pa[c];
        }
        const uint32_t* got = decoded + ((static_cast<size_t>(scheme) * kSize + y) * kSize + x) * 8;
        for (uint32_t i = 0; i < 8; ++i)
          if (got[i] != want[i]) ++mismatches;
      }
    EXPECT_EQ(mismatches, 0u) << (scheme < rows.size() ? rows[scheme].label() : scheme == rows.size() ? "max" : "sort");
  }
  device->destroy(pipeline);
  device->destroy(cs);
  device->destroy(out);
  device->destroy(params);
  device->destroy(ta);
  device->destroy(tb);
  device->submit();
}

const techniques::TargetTexels* findTarget(const techniques::FrameResult& r, const std::string& name) {
  for (const auto& t : r.targets)
    if (t.name == name) return &t;
  return nullptr;
}

struct ErrorStats {
  double mean = 0, p99 = 0, max = 0;
  size_t samples = 0;
};

ErrorStats colourError(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, const std::vector<bool>& use) {
  const float* fa = reinterpret_cast<const float*>(a.data());
  const float* fb = reinterpret_cast<const float*>(b.data());
  std::vector<double> e;
  for (size_t p = 0; p < use.size(); ++p) {
    if (!use[p]) continue;
    for (int c = 0; c < 3; ++c) e.push_back(std::fabs(static_cast<double>(fa[p * 4 + c]) - fb[p * 4 + c]));
  }
  ErrorStats s;
  s.samples = e.size();
  if (e.empty()) return s;
  for (double x : e) s.mean += x;
  s.mean /= static_cast<double>(e.size());
  std::sort(e.begin(), e.end());
  s.p99 = e[std::min(e.size() - 1, static_cast<size_t>(0.99 * static_cast<double>(e.size())))];
  s.max = e.back();
  return s;
}

// Lights reaching each pixel's visible surface, counted on the CPU from the depth pre-pass (the
// light volume shader's test: inside the radius and, for a spot, inside the outer cone).
std::vector<std::vector<uint32_t>> cpuLightsPerPixel(const scene::Scene& s, const scene::Camera& camera, uint32_t w,
                                                     uint32_t h, const std::vector<uint8_t>& depthTexels) {
  glm::mat4 invViewProj = glm::inverse(camera.viewProjection(static_cast<float>(w) / static_cast<float>(h)));
  const float* depth = reinterpret_cast<const float*>(depthTexels.data());
  std::vector<std::vector<uint32_t>> out(static_cast<size_t>(w) * h);
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      float d = depth[y * w + x];
      if (d >= 1.0f) continue;
      glm::vec4 ndc((x + 0.5f) / w * 2.0f - 1.0f, (y + 0.5f) / h * 2.0f - 1.0f, d, 1.0f);
      glm::vec4 hp = invViewProj * ndc;
      glm::vec3 p = glm::vec3(hp) / hp.w;
      for (uint32_t l = 0; l < s.lights.size(); ++l) {
        const scene::Light& light = s.lights[l];
        glm::vec3 to = p - light.position;
        float dist = glm::length(to);
        if (!(dist < light.radius)) continue;
        if (light.type == scene::LightType::Spot && !(glm::dot(glm::normalize(light.direction), to / dist) > light.cosOuter))
          continue;
        out[y * w + x].push_back(l);
      }
    }
  return out;
}

struct LidrCase {
  std::string technique;
  uint32_t lightCount;
  scene::LightSize size;
};

class LidrTechniques : public ::testing::TestWithParam<std::string> {};

// Tolerances of the techniques issue, against the float forward reference.
constexpr double kMeanTolerance = 0.5 / 255.0, kP99Tolerance = 4.0 / 255.0;
// Pixels where the CPU and GPU disagree about a light at the very edge of its radius (the two
// reconstruct the surface point in different float orders); such a light adds ~0 there.
constexpr double kBoundaryFraction = 0.002;

TEST_P(LidrTechniques, EqualsForwardWithinCapacityAndDropsExactlyTheOverflow) {
  auto device = test::makeDevice(GetParam());
  if (!device) return;
  std::vector<LidrCase> cases;
  for (const char* t : {"lidr-sort", "lidr-max", "lidr-bits", "lidr-bits-1x255", "lidr-bits-2x255", "lidr-bits-8x255"})
    cases.push_back({t, 24, scene::LightSize::Small});
  for (const char* t : {"lidr-bits-2x15", "lidr-bits-4x15", "lidr-bits-8x15"}) cases.push_back({t, 15, scene::LightSize::Small});
  cases.push_back({"lidr-bits", 24, scene::LightSize::Big});  // heavy overlap: many pixels lose lights
  cases.push_back({"lidr-max", 24, scene::LightSize::Big});

  for (const LidrCase& c : cases) {
    SCOPED_TRACE(c.technique);
    techniques::FrameRequest request;
    request.sceneParams.lightCount = c.lightCount;
    request.sceneParams.lightSize = c.size;
    request.colorFormat = rhi::Format::RGBA32F;
    request.technique = "forward";
    techniques::FrameResult reference = techniques::renderFrameTexels(*device, request);
    ASSERT_TRUE(reference.ok) << reference.error;
    request.technique = c.technique;
    request.readTargets = true;
    techniques::FrameResult lidr = techniques::renderFrameTexels(*device, request);
    ASSERT_TRUE(lidr.ok) << lidr.error;
    const auto* depth = findTarget(lidr, "prepass.depth");
    const auto* count = findTarget(lidr, "lidr.count");
    const auto* dropped = findTarget(lidr, "lidr.dropped");
    ASSERT_TRUE(depth && count && dropped);

    scene::Scene s = scene::makeDefaultScene(request.sceneParams);
    auto lightsAt = cpuLightsPerPixel(s, s.cameras[0], request.width, request.height, depth->texels);
    // Which lights the packing loses, per pixel, from the CPU's overlap list.
    std::set<uint32_t> unplaced;
    if (c.technique == "lidr-sort") {
      techniques::ChannelSort sort = techniques::sortLightsIntoChannels(s.lights);
      unplaced.insert(sort.unplaced.begin(), sort.unplaced.end());
    }
    const BitPackingLayout* row = nullptr;
    if (c.technique.rfind("lidr-bits", 0) == 0)
      row = techniques::findBitPackingRow(c.technique == "lidr-bits" ? "4x255" : c.technique.substr(10));
    uint32_t capacity = c.technique == "lidr-sort" ? 4 : row ? row->overlaps() : 4;
    uint32_t maxLights = row ? row->maxLights() : 255;

    size_t pixels = lightsAt.size(), countMismatch = 0, droppedMismatch = 0, lostPixels = 0, gpuLostPixels = 0;
    uint32_t maxOverlap = 0;
    std::vector<bool> keep(pixels, false);
    for (size_t p = 0; p < pixels; ++p) {
      const auto& ls = lightsAt[p];
      uint32_t n = static_cast<uint32_t>(ls.size());
      maxOverlap = std::max(maxOverlap, n);
      uint32_t lost = 0;
      if (c.technique == "lidr-sort") {
        for (uint32_t l : ls) lost += unplaced.count(l) || l >= maxLights ? 1 : 0;
      } else {
        uint32_t indexable = 0;
        for (uint32_t l : ls) indexable += l < maxLights ? 1 : 0;
        lost = (n - indexable) + (indexable > capacity ? indexable - capacity : 0);
      }
      if (count->texels[p] != n) ++countMismatch;
      if (dropped->texels[p] != lost) ++droppedMismatch;
      if (lost) ++lostPixels;
      if (dropped->texels[p]) ++gpuLostPixels;
      keep[p] = lost == 0 && dropped->texels[p] == 0;
    }
    ErrorStats e = colourError(lidr.texels, reference.texels, keep);
    std::printf("%s %s %u %s lights: max overlap %u, capacity %u, pixels losing light %zu (GPU %zu), "
                "count mismatches %zu, dropped mismatches %zu; within capacity (%zu channels): mean %.3f/255, "
                "p99 %.3f/255, max %.3f/255\n",
                GetParam().c_str(), c.technique.c_str(), c.lightCount, c.size == scene::LightSize::Small ? "small" : "big",
                maxOverlap, capacity, lostPixels, gpuLostPixels, countMismatch, droppedMismatch, e.samples,
                e.mean * 255, e.p99 * 255, e.max * 255);
    EXPECT_LE(countMismatch, kBoundaryFraction * pixels);
    EXPECT_LE(droppedMismatch, kBoundaryFraction * pixels);
    // Small lights: most of the image is within capacity; big ones overflow most pixels.
    EXPECT_GT(e.samples, c.size == scene::LightSize::Small ? pixels : pixels / 10);
    EXPECT_LE(e.mean, kMeanTolerance);
    EXPECT_LE(e.p99, kP99Tolerance);
    // No single pixel within capacity may miss a light (a lost light is ~0.1 or more).
    EXPECT_LE(e.max, kP99Tolerance);
    // Where lights were lost the image only lacks light: never brighter than the reference.
    const float* fl = reinterpret_cast<const float*>(lidr.texels.data());
    const float* fr = reinterpret_cast<const float*>(reference.texels.data());
    size_t brighter = 0;
    for (size_t p = 0; p < pixels; ++p)
      if (!keep[p])
        for (int ch = 0; ch < 3; ++ch)
          if (fl[p * 4 + ch] > fr[p * 4 + ch] + kP99Tolerance) ++brighter;
    EXPECT_LE(brighter, kBoundaryFraction * pixels);
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, LidrGpu, ::testing::ValuesIn(test::allBackends()), test::BackendName());
INSTANTIATE_TEST_SUITE_P(Backends, LidrTechniques, ::testing::ValuesIn(test::allBackends()), test::BackendName());

}  // namespace
