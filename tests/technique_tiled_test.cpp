// Tiled deferred and tiled forward shading against the float forward reference with 1024 lights,
// and the per-tile light lists against a CPU recount.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/glm.hpp>

#include "scene/scene.h"
#include "scene/scene_gpu.h"
#include "techniques/frame.h"
#include "techniques/tiled/tiled.h"
#include "tests/test_support.h"

using namespace parity;

namespace {

class TiledTechniques : public ::testing::TestWithParam<std::string> {};

constexpr double kMeanTolerance = 0.5 / 255.0, kP99Tolerance = 4.0 / 255.0;

struct ErrorStats {
  double mean = 0, p99 = 0, max = 0;
};

ErrorStats colourError(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  const float* fa = reinterpret_cast<const float*>(a.data());
  const float* fb = reinterpret_cast<const float*>(b.data());
  std::vector<double> e;
  for (size_t p = 0; p < a.size() / 16; ++p)
    for (int c = 0; c < 3; ++c) e.push_back(std::fabs(static_cast<double>(fa[p * 4 + c]) - fb[p * 4 + c]));
  ErrorStats s;
  for (double x : e) s.mean += x;
  s.mean /= static_cast<double>(e.size());
  std::sort(e.begin(), e.end());
  s.p99 = e[static_cast<size_t>(0.99 * static_cast<double>(e.size()))];
  s.max = e.back();
  return s;
}

TEST_P(TiledTechniques, EqualForwardWith1024Lights) {
  auto device = test::makeDevice(GetParam());
  if (!device) return;
  for (scene::LightSize size : {scene::LightSize::Small, scene::LightSize::Big}) {
    techniques::FrameRequest request;
    request.sceneParams.lightCount = 1024;
    request.sceneParams.lightSize = size;
    request.colorFormat = rhi::Format::RGBA32F;
    request.technique = "forward";
    techniques::FrameResult reference = techniques::renderFrameTexels(*device, request);
    ASSERT_TRUE(reference.ok) << reference.error;
    for (const char* technique : {"tiled-deferred", "tiled-forward"}) {
      request.technique = technique;
      techniques::FrameResult tiled = techniques::renderFrameTexels(*device, request);
      ASSERT_TRUE(tiled.ok) << tiled.error;
      ErrorStats e = colourError(tiled.texels, reference.texels);
      std::printf("%s %s 1024 %s lights: mean %.4f/255, p99 %.4f/255, max %.4f/255\n", GetParam().c_str(), technique,
                  size == scene::LightSize::Small ? "small" : "big", e.mean * 255, e.p99 * 255, e.max * 255);
      EXPECT_LE(e.mean, kMeanTolerance) << technique;
      EXPECT_LE(e.p99, kP99Tolerance) << technique;
    }
  }
}

// Lights of `s` that reach a surface point of a tile (reconstructed from the depth pre-pass of the
// last render of `tiled`, tiled forward) but are missing from that tile's list.
size_t lightsMissingFromTheirTiles(rhi::Device& device, techniques::TiledShading& tiled, const scene::Scene& s,
                                   const std::vector<std::vector<uint32_t>>& lists, uint32_t w, uint32_t h) {
  rhi::TextureHandle depthTarget;
  for (const auto& t : tiled.targets())
    if (t.name == "prepass.depth") depthTarget = t.texture;  // tiled forward's float copy of depth
  std::vector<uint8_t> depthBytes = device.readTexture(depthTarget);
  const float* depth = reinterpret_cast<const float*>(depthBytes.data());
  glm::mat4 invViewProj = glm::inverse(s.cameras[0].viewProjection(static_cast<float>(w) / static_cast<float>(h)));
  size_t missing = 0;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      float d = depth[y * w + x];
      if (d >= 1.0f) continue;
      glm::vec4 hp = invViewProj * glm::vec4((x + 0.5f) / w * 2.0f - 1.0f, (y + 0.5f) / h * 2.0f - 1.0f, d, 1.0f);
      glm::vec3 p = glm::vec3(hp) / hp.w;
      const auto& list = lists[(y / 16) * tiled.tilesX() + x / 16];
      for (uint32_t l = 0; l < s.lights.size(); ++l)
        // A margin of 0.1% of the radius: points at the very rim, which get ~0 light, may be
        // reconstructed on either side of it.
        if (glm::length(p - s.lights[l].position) < s.lights[l].radius * 0.999f &&
            !std::binary_search(list.begin(), list.end(), l))
          ++missing;
    }
  return missing;
}

// The lists hold every light that reaches a pixel of the tile (CPU recount from the depth
// target) and are much shorter than the light count for small lights.
TEST_P(TiledTechniques, TileListsHoldEveryLightThatReachesTheTile) {
  auto device = test::makeDevice(GetParam());
  if (!device) return;
  scene::SceneParams params;
  params.lightCount = 1024;
  scene::Scene s = scene::makeDefaultScene(params);
  scene::SceneGpu gpu(*device, s);
  techniques::TiledShading tiled(techniques::TiledMode::Forward);
  techniques::RenderSettings settings;
  tiled.prepare(*device, settings);
  tiled.render(*device, gpu, s.cameras[0]);
  device->submit();
  std::vector<std::vector<uint32_t>> lists = tiled.readTileLists(*device);
  ASSERT_EQ(lists.size(), static_cast<size_t>(tiled.tilesX()) * tiled.tilesY());
  size_t listed = 0;
  for (const auto& list : lists) {
    EXPECT_TRUE(std::is_sorted(list.begin(), list.end()));
    listed += list.size();
  }
  double average = static_cast<double>(listed) / static_cast<double>(lists.size());
  std::printf("%s: %zu tiles, %.1f lights per tile on average of 1024\n", GetParam().c_str(), lists.size(), average);
  EXPECT_EQ(lightsMissingFromTheirTiles(*device, tiled, s, lists, settings.width, settings.height), 0u);
  EXPECT_LT(average, 1024.0 / 4);
  tiled.release(*device);
  device->submit();
}

// The port's path where the device has no compute shaders: the lists culled on the CPU, each
// tile's frustum against the lights' spheres. They differ from the compute pass's (which bounds
// the tile by the box of its surface points: tighter in depth, looser at the box's corners), but
// each holds every light that reaches a pixel of its tile, and the shading adds nothing for a
// light that reaches none: the image is the compute path's bit for bit, for both techniques and
// both light sizes.
TEST_P(TiledTechniques, CpuCulledListsHoldEveryLightOfTheTileAndGiveTheComputeImage) {
  auto device = test::makeDevice(GetParam());
  if (!device) return;
  if (!device->info().caps.compute) GTEST_SKIP() << "the host has no compute shaders to compare with";
  for (scene::LightSize size : {scene::LightSize::Small, scene::LightSize::Big}) {
    scene::SceneParams params;
    params.lightCount = 1024;
    params.lightSize = size;
    scene::Scene s = scene::makeDefaultScene(params);
    scene::SceneGpu gpu(*device, s);
    for (techniques::TiledMode mode : {techniques::TiledMode::Deferred, techniques::TiledMode::Forward}) {
      const std::string what = std::string(mode == techniques::TiledMode::Deferred ? "tiled-deferred" : "tiled-forward") +
                               (size == scene::LightSize::Small ? ", small lights" : ", big lights");
      std::vector<std::vector<uint32_t>> lists[2];
      std::vector<uint8_t> image[2];
      for (int cpu = 0; cpu < 2; ++cpu) {
        techniques::TiledShading tiled(mode);
        techniques::RenderSettings settings;
        settings.capabilities.compute = cpu == 0;
        EXPECT_EQ(tiled.portPaths(settings.capabilities).size(), size_t(cpu));
        tiled.prepare(*device, settings);
        tiled.render(*device, gpu, s.cameras[0]);
        device->submit();
        lists[cpu] = tiled.readTileLists(*device);
        for (const auto& t : tiled.targets())
          if (t.name == techniques::kOutputColor) image[cpu] = device->readTexture(t.texture);
        if (cpu == 1 && mode == techniques::TiledMode::Forward) {
          EXPECT_EQ(lightsMissingFromTheirTiles(*device, tiled, s, lists[1], settings.width, settings.height), 0u) << what;
        }
        tiled.release(*device);
        device->submit();
      }
      size_t entries[2] = {0, 0}, differing = 0;
      for (int cpu = 0; cpu < 2; ++cpu)
        for (const auto& list : lists[cpu]) {
          EXPECT_TRUE(std::is_sorted(list.begin(), list.end())) << what;
          entries[cpu] += list.size();
        }
      for (size_t t = 0; t < lists[0].size() && t < lists[1].size(); ++t) differing += lists[0][t] != lists[1][t];
      std::printf("%s %s: %zu entries in the compute lists, %zu in the CPU lists; %zu of %zu tiles differ\n",
                  GetParam().c_str(), what.c_str(), entries[0], entries[1], differing, lists[0].size());
      EXPECT_GT(differing, 0u) << what << ": both renders took the same path";
      ASSERT_FALSE(image[0].empty()) << what;
      EXPECT_TRUE(image[0] == image[1]) << what << ": the two paths' images differ";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, TiledTechniques, ::testing::ValuesIn(test::allBackends()), test::BackendName());

}  // namespace
