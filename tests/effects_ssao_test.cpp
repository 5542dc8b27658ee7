// SSAO (Ferko 2012 §5.1-5.2) through the deferred-ssao technique: a flat floor alone is not
// occluded (the hemisphere correction removes self-occlusion), the corner between a floor and a
// wall is; on every backend and through the platform layers whose depth and normal reads differ.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <tuple>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"
#include "scene/scene_gpu.h"
#include "techniques/ssao/deferred_ssao.h"
#include "test_support.h"

using namespace parity;

namespace {

constexpr uint32_t kWidth = 160, kHeight = 90;

// A quad from four corners (counter-clockwise seen from the side `normal` points to), both
// windings so that it is visible from either side.
void addQuad(scene::Scene& s, const std::string& name, const glm::vec3 (&c)[4], glm::vec3 normal) {
  uint32_t base = static_cast<uint32_t>(s.vertices.size());
  for (int i = 0; i < 4; ++i) s.vertices.push_back({c[i], normal, glm::vec2(i == 1 || i == 2, i >= 2)});
  scene::Mesh m;
  m.name = name;
  m.firstIndex = static_cast<uint32_t>(s.indices.size());
  for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u, 0u, 2u, 1u, 0u, 3u, 2u}) s.indices.push_back(base + i);
  m.indexCount = 12;
  m.boundsMin = glm::min(glm::min(c[0], c[1]), glm::min(c[2], c[3]));
  m.boundsMax = glm::max(glm::max(c[0], c[1]), glm::max(c[2], c[3]));
  s.meshes.push_back(m);
}

scene::Scene makeScene(bool withWall) {
  scene::Scene s;
  s.name = withWall ? "corner" : "floor";
  s.materials.push_back(scene::Material{});
  const glm::vec3 floor[4] = {{-30, 0, 30}, {30, 0, 30}, {30, 0, -30}, {-30, 0, -30}};
  addQuad(s, "floor", floor, {0, 1, 0});
  if (withWall) {
    const glm::vec3 wall[4] = {{-30, 0, -1}, {30, 0, -1}, {30, 30, -1}, {-30, 30, -1}};
    addQuad(s, "wall", wall, {0, 0, 1});
  }
  s.ambient = glm::vec3(0.5f);
  s.directionalColor = glm::vec3(0.5f);
  scene::Camera cam;
  cam.name = "default";
  cam.position = glm::vec3(0, 2.5f, 4);
  cam.target = glm::vec3(0, 0, -1);
  s.cameras.push_back(cam);
  return s;
}

// The blurred occlusion target (1 = unoccluded), one byte per texel.
std::vector<uint8_t> occlusion(rhi::Device& dev, const scene::Scene& s, platforms::PlatformId platform) {
  scene::SceneGpu gpu(dev, s);
  techniques::DeferredSsao technique;
  techniques::RenderSettings settings;
  settings.width = kWidth;
  settings.height = kHeight;
  settings.platform = platform;
  technique.prepare(dev, settings);
  technique.render(dev, gpu, s.cameras[0]);
  dev.submit();
  std::vector<uint8_t> ao;
  for (const techniques::NamedTarget& t : technique.targets())
    if (t.name == "ssao") ao = dev.readTexture(t.texture);
  technique.release(dev);
  return ao;
}

class EffectsSsao : public ::testing::TestWithParam<std::tuple<std::string, platforms::PlatformId>> {};

TEST_P(EffectsSsao, FlatFloorIsUnoccludedCornerIsOccluded) {
  auto [backend, platform] = GetParam();
  auto dev = test::makeDevice(backend);
  if (!dev) return;
  std::vector<uint8_t> floor = occlusion(*dev, makeScene(false), platform);
  ASSERT_EQ(floor.size(), size_t{kWidth / 2} * (kHeight / 2));
  uint8_t floorMin = *std::min_element(floor.begin(), floor.end());
  EXPECT_GE(floorMin, 250) << "a flat floor occludes itself";

  std::vector<uint8_t> corner = occlusion(*dev, makeScene(true), platform);
  ASSERT_EQ(corner.size(), floor.size());
  uint8_t cornerMin = *std::min_element(corner.begin(), corner.end());
  size_t occluded = std::count_if(corner.begin(), corner.end(), [](uint8_t v) { return v < 240; });
  // About a quarter of the samples at the corner fall behind the wall, each O(d) <= 1: AO near 0.8.
  EXPECT_LT(cornerMin, 225) << "the corner between floor and wall is not occluded";
  // Occlusion stays near the corner: most of the floor and wall are open.
  EXPECT_GT(occluded, 0u);
  EXPECT_LT(occluded, corner.size() / 3);
}

INSTANTIATE_TEST_SUITE_P(Platforms, EffectsSsao,
                         ::testing::Combine(::testing::ValuesIn(test::allBackends()),
                                            ::testing::Values(platforms::PlatformId::Reference, platforms::PlatformId::Dx10,
                                                              platforms::PlatformId::Ps3, platforms::PlatformId::X360)),
                         [](const auto& info) {
                           return std::get<0>(info.param) + "_" + std::string(platforms::platformName(std::get<1>(info.param)));
                         });

}  // namespace
