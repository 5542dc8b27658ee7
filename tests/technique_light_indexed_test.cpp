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

// A deterministic 32-bit stream, for indices of up to 16 bits.
uint32_t mixWord(uint32_t a, uint32_t b) {
  uint32_t x = a * 2654435761u ^ (b + 0x9e3779b9u) * 40503u;
  x ^= x >> 15;
  x *= 0x2c1b3c6du;
  x ^= x >> 12;
  x *= 0x297a2d39u;
  return x ^ (x >> 15);
}

TEST(LidrPacking, TableRowsArePresent) {
  std::set<std::string> labels;
  for (const BitPackingLayout& row : techniques::bitPackingRows()) labels.insert(row.label());
  // Every row of the paper's table.
  for (const char* want : {"2x15", "4x15", "8x15", "16x15", "1x255", "2x255", "4x255", "8x255", "16x255", "1x65535",
                           "2x65535", "4x65535", "8x65535"})
    EXPECT_TRUE(labels.count(want)) << want;
  EXPECT_EQ(labels.size(), 13u);
  const BitPackingLayout* four = techniques::findBitPackingRow("4x255");
  ASSERT_NE(four, nullptr);
  EXPECT_EQ(four->chunkBits(), 2u);
  EXPECT_FLOAT_EQ(four->blendConstant(), 0.25f);  // the paper's CONSTANT_COLOR
  // The table's "Details" column: surfaces and the split of the index.
  struct Detail {
    const char* label;
    uint32_t targets, chunkBits, chunks;
  };
  for (const Detail& d : {Detail{"2x15", 1, 4, 1}, Detail{"4x15", 1, 2, 2}, Detail{"8x15", 1, 1, 4}, Detail{"16x15", 2, 1, 4},
                          Detail{"1x255", 1, 8, 1}, Detail{"2x255", 1, 4, 2}, Detail{"4x255", 1, 2, 4},
                          Detail{"8x255", 2, 1, 8}, Detail{"16x255", 4, 1, 8}, Detail{"1x65535", 1, 8, 2},
                          Detail{"2x65535", 1, 4, 4}, Detail{"4x65535", 2, 2, 8}, Detail{"8x65535", 4, 1, 16}}) {
    const BitPackingLayout* row = techniques::findBitPackingRow(d.label);
    ASSERT_NE(row, nullptr) << d.label;
    EXPECT_EQ(row->targets(), d.targets) << d.label;
    EXPECT_EQ(row->chunkBits(), d.chunkBits) << d.label;
    EXPECT_EQ(row->channels, d.chunks) << d.label;
  }
}

// The channels a row uses, as indices into ChannelBytes.
std::vector<uint32_t> usedChannels(const BitPackingLayout& row) {
  std::vector<uint32_t> used;
  for (uint32_t g = 0; g < row.groups; ++g)
    for (uint32_t c = 0; c < row.channels; ++c) used.push_back(g * row.targetsPerGroup() * 4 + c);
  return used;
}

// The paper's float unpacking equals integer shifts and masks for every byte value of every
// channel of every row (each channel swept through 0..255 with the others varying).
TEST(LidrPacking, BitUnpackEqualsIntegerLogicForEveryRow) {
  for (const BitPackingLayout& row : techniques::bitPackingRows()) {
    size_t checked = 0;
    std::vector<uint32_t> used = usedChannels(row);
    for (uint32_t c : used)
      for (uint32_t v = 0; v < 256; ++v)
        for (uint32_t salt = 0; salt < 8; ++salt) {
          ChannelBytes bytes{};
          for (uint32_t k : used) bytes[k] = k == c ? static_cast<uint8_t>(v) : mixByte(v * 8 + salt, k);
          UnpackedIndices paper = techniques::unpackBitsPaper(row, bytes), exact = techniques::unpackBitsInteger(row, bytes);
          ASSERT_EQ(paper, exact) << row.label() << " channel " << c << " value " << v;
          ++checked;
        }
    EXPECT_EQ(checked, used.size() * 256 * 8) << row.label();
  }
}

// Every index of every row, alone in a pixel, comes back through the blend model and the paper's
// unpacking (all 65535 of the 16-bit rows: both table coordinates).
TEST(LidrPacking, EveryIndexOfEveryRowRoundTrips) {
  for (const BitPackingLayout& row : techniques::bitPackingRows()) {
    uint32_t slot = row.overlapsPerGroup() - 1;  // the newest slot of group 1
    for (uint32_t index = 1; index <= row.maxLights(); ++index) {
      UnpackedIndices got = techniques::unpackBitsPaper(row, techniques::simulateBitPacking(row, {index}));
      for (uint32_t i = 0; i < techniques::kMaxUnpackedIndices; ++i)
        ASSERT_EQ(got[i], i == slot ? index : 0u) << row.label() << " index " << index << " slot " << i;
    }
  }
}

// Packing n lights by the blend model and unpacking gives them back: group 1 takes the first
// overlapsPerGroup() (oldest last in the group's slots after the empty ones), group 2 the next;
// more than overlaps() keeps the first overlaps() (the stencil holds the rest).
TEST(LidrPacking, BitPackingRoundTrip) {
  for (const BitPackingLayout& row : techniques::bitPackingRows()) {
    const uint32_t perGroup = row.overlapsPerGroup();
    for (uint32_t n = 0; n <= row.overlaps() + 2; ++n) {
      for (uint32_t trial = 0; trial < 200; ++trial) {
        std::vector<uint32_t> order;
        for (uint32_t i = 0; i < n; ++i) order.push_back(1 + mixWord(trial * 31 + i, n) % row.maxLights());
        UnpackedIndices got = techniques::unpackBitsPaper(row, techniques::simulateBitPacking(row, order));
        for (uint32_t g = 0; g < row.groups; ++g) {
          uint32_t first = g * perGroup;
          uint32_t kept = n > first ? std::min(n - first, perGroup) : 0;
          for (uint32_t i = 0; i < perGroup; ++i) {
            uint32_t empty = perGroup - kept;
            uint32_t want = i < empty ? 0u : order[first + i - empty];
            ASSERT_EQ(got[first + i], want) << row.label() << " n=" << n << " group " << g << " slot " << i;
          }
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

// The shader (lidr_unpack.glsl) on the GPU: every row decodes four 256x256 RGBA8 textures in
// which each channel takes every byte value, bit-exactly as the CPU mirror and the integer logic
// (lidrUnpackBitsRows for every row; lidrUnpackBits, which the techniques use, for the rows of
// one group and up to 8 index bits).
class LidrGpu : public ::testing::TestWithParam<std::string> {};

TEST_P(LidrGpu, UnpackShaderIsBitExact) {
  auto device = test::makeDevice(GetParam());
  if (!device) return;
  constexpr uint32_t kSize = 256, kTargets = 4;
  // Texture t, channel c: every byte value along x or y, the others mixed.
  auto byteAt = [](uint32_t t, uint32_t c, uint32_t x, uint32_t y) -> uint8_t {
    switch ((t * 4 + c) % 6) {
      case 0: return static_cast<uint8_t>(x);
      case 1: return static_cast<uint8_t>(y);
      case 2: return static_cast<uint8_t>(x ^ y);
      case 3: return static_cast<uint8_t>(x + y);
      case 4: return mixByte(x + 256 * t, y + c);
      default: return mixByte(y + 256 * c, x + t);
    }
  };
  std::vector<std::vector<uint8_t>> texels(kTargets, std::vector<uint8_t>(kSize * kSize * 4));
  std::vector<rhi::TextureHandle> textures;
  for (uint32_t t = 0; t < kTargets; ++t) {
    for (uint32_t y = 0; y < kSize; ++y)
      for (uint32_t x = 0; x < kSize; ++x)
        for (uint32_t c = 0; c < 4; ++c) texels[t][(y * kSize + x) * 4 + c] = byteAt(t, c, x, y);
    rhi::TextureDesc td;
    td.width = td.height = kSize;
    td.usage = rhi::TextureUsage_Sampled;
    td.initialData = texels[t].data();
    textures.push_back(device->createTexture(td));
  }

  const auto& rows = techniques::bitPackingRows();
  // Schemes: every row through lidrUnpackBitsRows, the same rows through lidrUnpackBits where it
  // applies (zeros stored otherwise), then max and sort.
  const uint32_t rowCount = static_cast<uint32_t>(rows.size());
  const uint32_t schemes = 2 * rowCount + 2;
  constexpr uint32_t kSlots = techniques::kMaxUnpackedIndices;
  rhi::BufferDesc bd;
  bd.size = static_cast<size_t>(kSize) * kSize * schemes * kSlots * sizeof(uint32_t);
  bd.usage = rhi::BufferUsage_Storage;
  rhi::BufferHandle out = device->createBuffer(bd);
  std::vector<uint32_t> rowParams;
  for (const BitPackingLayout& row : rows) {
    rowParams.push_back(row.channels);
    rowParams.push_back(row.indexBits);
    rowParams.push_back(row.groups);
    rowParams.push_back(0);
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
layout(set = 0, binding = 3, std430) readonly buffer Rows { uvec4 rows[]; };
layout(set = 0, binding = 4) uniform sampler2D packedC;
layout(set = 0, binding = 5) uniform sampler2D packedD;
void store(uint scheme, uint indices[LIDR_MAX_INDICES]) {
  uint base = ((scheme * 256u + gl_GlobalInvocationID.y) * 256u + gl_GlobalInvocationID.x) * LIDR_MAX_INDICES;
  for (uint i = 0u; i < LIDR_MAX_INDICES; ++i) decoded[base + i] = indices[i];
}
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  vec4 packed[4];
  packed[0] = texelFetch(packedA, p, 0);
  packed[1] = texelFetch(packedB, p, 0);
  packed[2] = texelFetch(packedC, p, 0);
  packed[3] = texelFetch(packedD, p, 0);
  uint indices[LIDR_MAX_INDICES];
  uint rowCount = uint(rows.length());
  for (uint r = 0u; r < rowCount; ++r) {
    lidrUnpackBitsRows(packed, rows[r].x, rows[r].y, rows[r].z, indices);
    store(r, indices);
    for (uint i = 0u; i < LIDR_MAX_INDICES; ++i) indices[i] = 0u;
    if (rows[r].z == 1u && rows[r].y <= 8u) lidrUnpackBits(packed[0], packed[1], rows[r].x, rows[r].y, indices);
    store(rowCount + r, indices);
  }
  lidrUnpackMax(packed[0], indices);
  store(2u * rowCount, indices);
  lidrUnpackSort(packed[0], indices);
  store(2u * rowCount + 1u, indices);
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
  rhi::ResourceBinding bindings[6];
  const uint32_t textureBindings[kTargets] = {0, 1, 4, 5};
  for (uint32_t t = 0; t < kTargets; ++t) {
    bindings[t].binding = textureBindings[t];
    bindings[t].kind = rhi::BindingKind::SampledTexture;
    bindings[t].texture = textures[t];
  }
  bindings[4].binding = 2;
  bindings[4].kind = rhi::BindingKind::StorageBuffer;
  bindings[4].buffer = out;
  bindings[5].binding = 3;
  bindings[5].kind = rhi::BindingKind::StorageBuffer;
  bindings[5].buffer = params;
  device->setComputePipeline(pipeline);
  device->setBindings(bindings);
  device->dispatch(kSize / 16, kSize / 16);
  device->submit();
  std::vector<uint8_t> raw = device->readBuffer(out, 0, bd.size);
  ASSERT_EQ(raw.size(), bd.size);
  const uint32_t* decoded = reinterpret_cast<const uint32_t*>(raw.data());

  for (uint32_t scheme = 0; scheme < schemes; ++scheme) {
    const BitPackingLayout* row = scheme < 2 * rowCount ? &rows[scheme % rowCount] : nullptr;
    const bool plainBits = row && scheme >= rowCount;
    if (plainBits && (row->groups != 1 || row->indexBits > 8)) continue;  // not lidrUnpackBits' rows
    std::string label = row ? (plainBits ? "lidrUnpackBits " : "lidrUnpackBitsRows ") + row->label()
                            : scheme == 2 * rowCount ? "max" : "sort";
    size_t mismatches = 0, nonZero = 0;
    for (uint32_t y = 0; y < kSize; ++y)
      for (uint32_t x = 0; x < kSize; ++x) {
        ChannelBytes bytes{};
        for (uint32_t k = 0; k < 16; ++k) bytes[k] = texels[k / 4][(y * kSize + x) * 4 + k % 4];
        UnpackedIndices want{};
        if (row) {
          ChannelBytes used{};
          for (uint32_t k : usedChannels(*row)) used[k] = bytes[k];
          want = techniques::unpackBitsInteger(*row, used);
          ASSERT_EQ(techniques::unpackBitsPaper(*row, used), want) << label;
        } else if (scheme == 2 * rowCount) {
          want = techniques::unpackMax({bytes[0], bytes[1], bytes[2], bytes[3]});
        } else {
          for (int c = 0; c < 4; ++c) want[c] = bytes[c];
        }
        const uint32_t* got = decoded + ((static_cast<size_t>(scheme) * kSize + y) * kSize + x) * kSlots;
        for (uint32_t i = 0; i < kSlots; ++i) {
          if (got[i] != want[i]) ++mismatches;
          if (got[i] != 0) ++nonZero;
        }
      }
    EXPECT_EQ(mismatches, 0u) << label;
    EXPECT_GT(nonZero, 0u) << label;
  }
  device->destroy(pipeline);
  device->destroy(cs);
  device->destroy(out);
  device->destroy(params);
  for (rhi::TextureHandle t : textures) device->destroy(t);
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

// `parity bench` renders without the harness's diagnostic passes (RenderSettings::diagnostics):
// the overlap count is then skipped, the image is the same bit for bit and the lost-light
// target reads zero rather than a stale count.
TEST_P(LidrTechniques, WithoutDiagnosticsTheImageIsUnchangedAndNothingIsCounted) {
  auto device = test::makeDevice(GetParam());
  if (!device) return;
  for (const char* t : {"lidr-bits-1x255", "lidr-sort", "lidr-msaa"}) {
    SCOPED_TRACE(t);
    techniques::FrameRequest request;
    request.technique = t;
    request.sceneParams.lightCount = 24;
    request.readTargets = true;
    techniques::FrameResult with = techniques::renderFrameTexels(*device, request);
    request.diagnostics = false;
    techniques::FrameResult without = techniques::renderFrameTexels(*device, request);
    ASSERT_TRUE(with.ok && without.ok) << with.error << without.error;
    EXPECT_EQ(with.texels, without.texels);
    const auto* countWith = findTarget(with, "lidr.count");
    const auto* countWithout = findTarget(without, "lidr.count");
    ASSERT_TRUE(countWith && countWithout);
    EXPECT_GT(std::count_if(countWith->texels.begin(), countWith->texels.end(), [](uint8_t v) { return v != 0; }), 0);
    EXPECT_EQ(std::count_if(countWithout->texels.begin(), countWithout->texels.end(), [](uint8_t v) { return v != 0; }), 0);
  }
}

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
    // Counts are k / 255 in whatever format the platform stores them.
    auto counts = [](const techniques::TargetTexels& t) {
      std::vector<uint32_t> k;
      for (float v : test::redChannel(t.texels, t.format)) k.push_back(uint32_t(std::lround(v * 255.0f)));
      return k;
    };
    const std::vector<uint32_t> countAt = counts(*count), droppedAt = counts(*dropped);

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
      if (countAt[p] != n) ++countMismatch;
      if (droppedAt[p] != lost) ++droppedMismatch;
      if (lost) ++lostPixels;
      if (droppedAt[p]) ++gpuLostPixels;
      keep[p] = lost == 0 && droppedAt[p] == 0;
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
