// Order-independent transparency: the stencil-routed A-buffer (Ferko 2012 §4.1) equals the
// depth-peeling reference within 8-bit tolerance for 1 to 4 layers (its sample count), with the
// translucent meshes submitted out of depth order.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <string>
#include <tuple>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"
#include "scene/scene_gpu.h"
#include "techniques/abuffer/abuffer.h"
#include "test_support.h"

using namespace parity;

namespace {

constexpr uint32_t kWidth = 160, kHeight = 90;

// A quad facing +z at depth z, larger than the view. Translucent meshes are drawn with both faces,
// so a translucent quad gets one winding: with both, each pixel would hold two coplanar
// fragments, which the A-buffer keeps as two layers and depth peeling as one.
void addWall(scene::Scene& s, float z, float half, int material, bool bothWindings) {
  uint32_t base = static_cast<uint32_t>(s.vertices.size());
  const glm::vec2 c[4] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  for (glm::vec2 p : c) s.vertices.push_back({glm::vec3(p.x * half, 1.0f + p.y * half, z), glm::vec3(0, 0, 1), (p + 1.0f) * 0.5f});
  scene::Mesh m;
  m.name = "wall";
  m.firstIndex = static_cast<uint32_t>(s.indices.size());
  for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u, 0u, 2u, 1u, 0u, 3u, 2u}) s.indices.push_back(base + i);
  m.indexCount = bothWindings ? 12 : 6;
  m.material = material;
  m.boundsMin = glm::vec3(-half, 1.0f - half, z);
  m.boundsMax = glm::vec3(half, 1.0f + half, z);
  s.meshes.push_back(m);
}

scene::Scene makeScene(uint32_t layers) {
  scene::Scene s;
  s.name = "layers";
  scene::Material opaque;
  opaque.diffuse = glm::vec3(0.9f, 0.9f, 0.2f);
  s.materials.push_back(opaque);
  const glm::vec3 colors[4] = {{0.9f, 0.1f, 0.1f}, {0.1f, 0.9f, 0.1f}, {0.1f, 0.1f, 0.9f}, {0.9f, 0.9f, 0.9f}};
  const float opacities[4] = {0.5f, 0.3f, 0.6f, 0.4f};
  for (int i = 0; i < 4; ++i) {
    scene::Material m;
    m.diffuse = colors[i];
    m.opacity = opacities[i];
    s.materials.push_back(m);
  }
  addWall(s, -6.0f, 40.0f, 0, true);  // opaque background
  // Submitted out of depth order: z = -1, -4, -2, -3.
  const float depths[4] = {-1.0f, -4.0f, -2.0f, -3.0f};
  for (uint32_t i = 0; i < layers; ++i) addWall(s, depths[i], 30.0f, static_cast<int>(1 + i), false);
  s.ambient = glm::vec3(0.5f);
  s.directionalColor = glm::vec3(0.5f);
  s.directionalDir = glm::vec3(0.2f, -0.3f, -1.0f);
  scene::Camera cam;
  cam.name = "default";
  cam.position = glm::vec3(0, 1, 4);
  cam.target = glm::vec3(0, 1, 0);
  s.cameras.push_back(cam);
  return s;
}

std::vector<uint8_t> render(rhi::Device& dev, const scene::Scene& s, techniques::TransparencyMode mode) {
  scene::SceneGpu gpu(dev, s);
  techniques::OrderIndependentTransparency technique(mode);
  techniques::RenderSettings settings;
  settings.width = kWidth;
  settings.height = kHeight;
  technique.prepare(dev, settings);
  rhi::TextureHandle color = technique.render(dev, gpu, s.cameras[0]);
  dev.submit();
  std::vector<uint8_t> texels = dev.readTexture(color);
  technique.release(dev);
  return texels;
}

class EffectsAbuffer : public ::testing::TestWithParam<std::tuple<std::string, uint32_t>> {};

TEST_P(EffectsAbuffer, EqualsDepthPeeling) {
  auto [backend, layers] = GetParam();
  auto dev = test::makeDevice(backend);
  if (!dev) return;
  scene::Scene s = makeScene(layers);
  std::vector<uint8_t> abuffer = render(*dev, s, techniques::TransparencyMode::StencilRouted);
  std::vector<uint8_t> peeled = render(*dev, s, techniques::TransparencyMode::DepthPeeling);
  std::vector<uint8_t> opaqueOnly = render(*dev, makeScene(0), techniques::TransparencyMode::DepthPeeling);
  ASSERT_EQ(abuffer.size(), size_t{kWidth} * kHeight * 4);
  ASSERT_EQ(peeled.size(), abuffer.size());
  int maxDiff = 0, maxFromOpaque = 0;
  for (size_t i = 0; i < abuffer.size(); ++i) {
    maxDiff = std::max(maxDiff, std::abs(int(abuffer[i]) - int(peeled[i])));
    maxFromOpaque = std::max(maxFromOpaque, std::abs(int(abuffer[i]) - int(opaqueOnly[i])));
  }
  EXPECT_LE(maxDiff, 1) << "the A-buffer differs from depth peeling by more than one 8-bit step";
  EXPECT_GT(maxFromOpaque, 20) << "the translucent layers left no visible trace";
}

INSTANTIATE_TEST_SUITE_P(Layers, EffectsAbuffer,
                         ::testing::Combine(::testing::ValuesIn(test::allBackends()), ::testing::Values(1u, 2u, 3u, 4u)),
                         [](const auto& info) {
                           return std::get<0>(info.param) + "_" + std::to_string(std::get<1>(info.param)) + "layers";
                         });

}  // namespace
