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
  rhi::TextureHandle depthTarget;
  for (const auto& t : tiled.targets())
    if (t.name == "prepass.depth") depthTarget = t.texture;
  std::vector<uint8_t> depthBytes = device->readTexture(depthTarget);
  const float* depth = reinterpret_cast<const float*>(depthBytes.data());
  const uint32_t w = settings.width, h = settings.height;
  glm::mat4 invViewProj = glm::inverse(s.cameras[0].viewProjection(static_cast<float>(w) / static_cast<float>(h)));
  ASSERT_EQ(lists.size(), static_cast<size_t>(tiled.tilesX()) * tiled.tilesY());
  size_t missing = 0, listed = 0;
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
  for (const auto& list : lists) {
    EXPECT_TRUE(std::is_sorted(list.begin(), list.end()));
    listed += list.size();
  }
  double average = static_cast<double>(listed) / static_cast<double>(lists.size());
  std::printf("%s: %zu tiles, %.1f lights per tile on average of 1024\n", GetParam().c_str(), lists.size(), average);
  EXPECT_EQ(missing, 0u);
  EXPECT_LT(average, 1024.0 / 4);
  tiled.release(*device);
  device->submit();
}

INSTANTIATE_TEST_SUITE_P(Backends, TiledTechniques, ::testing::ValuesIn(test::allBackends()), test::BackendName());

}  // namespace
