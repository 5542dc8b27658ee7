// SSAO (Ferko 2012 §5.1-5.2) through the deferred-ssao technique: a flat floor alone is not
// occluded (the hemisphere correction removes self-occlusion), the corner between a floor and a
// wall is, and the occlusion darkens the ambient term only, as in Ferko's pipeline; on every
// backend and through the platform layers whose depth and normal reads differ.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"
#include "scene/scene_gpu.h"
#include "techniques/deferred/deferred.h"
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

// The final colour (RGBA8) of `technique` and, when it is deferred-ssao, its blurred occlusion.
struct Rendered {
  std::vector<uint8_t> color, occlusion;
};
Rendered renderWith(rhi::Device& dev, techniques::Technique& technique, const scene::Scene& s,
                    platforms::PlatformId platform) {
  scene::SceneGpu gpu(dev, s);
  techniques::RenderSettings settings;
  settings.width = kWidth;
  settings.height = kHeight;
  settings.platform = platform;
  technique.prepare(dev, settings);
  rhi::TextureHandle color = technique.render(dev, gpu, s.cameras[0]);
  dev.submit();
  Rendered r;
  r.color = dev.readTexture(color);
  for (const techniques::NamedTarget& t : technique.targets())
    if (t.name == "ssao") r.occlusion = dev.readTexture(t.texture);
  technique.release(dev);
  return r;
}

// The corner scene with a point light close to the corner, so that the occluded pixels are also
// brightly lit by direct light.
scene::Scene litCorner(glm::vec3 ambient) {
  scene::Scene s = makeScene(true);
  s.ambient = ambient;
  scene::Light light;
  light.position = glm::vec3(0.0f, 1.2f, 0.0f);
  light.color = glm::vec3(1.5f);
  light.radius = 8.0f;
  s.lights.push_back(light);
  return s;
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

// Without ambient light there is nothing for the occlusion to take away: deferred-ssao must
// equal deferred byte for byte, although the corner is occluded and lit by direct light there
// (multiplying the whole lit image by the occlusion would darken it).
TEST_P(EffectsSsao, DirectLightIsNotOccluded) {
  auto [backend, platform] = GetParam();
  auto dev = test::makeDevice(backend);
  if (!dev) return;
  const scene::Scene s = litCorner(glm::vec3(0.0f));
  techniques::DeferredSsao ssao;
  techniques::DeferredShading deferred;
  Rendered withAo = renderWith(*dev, ssao, s, platform);
  Rendered plain = renderWith(*dev, deferred, s, platform);
  ASSERT_EQ(withAo.color.size(), size_t{kWidth} * kHeight * 4);
  ASSERT_EQ(plain.color.size(), withAo.color.size());
  ASSERT_EQ(withAo.occlusion.size(), size_t{kWidth / 2} * (kHeight / 2));

  // The occluded texels (the corner) see direct light: the comparison below is not vacuous.
  size_t occludedLit = 0, occluded = 0;
  for (uint32_t y = 0; y < kHeight / 2; ++y)
    for (uint32_t x = 0; x < kWidth / 2; ++x) {
      if (withAo.occlusion[size_t{y} * (kWidth / 2) + x] >= 225) continue;
      ++occluded;
      size_t full = (size_t{y} * 2 * kWidth + x * 2) * 4;
      occludedLit += plain.color[full + 1] > 40;
    }
  EXPECT_GT(occluded, 0u) << "the corner must be occluded for this test to say anything";
  EXPECT_GT(occludedLit, occluded / 2) << "the occluded corner must be lit by the point light";

  size_t differing = 0;
  std::string first;
  for (size_t i = 0; i < plain.color.size(); ++i)
    if (plain.color[i] != withAo.color[i]) {
      if (first.empty())
        first = "pixel " + std::to_string(i / 4 % kWidth) + "," + std::to_string(i / 4 / kWidth) + " channel " +
                std::to_string(i % 4) + ": deferred " + std::to_string(plain.color[i]) + ", deferred-ssao " +
                std::to_string(withAo.color[i]);
      ++differing;
    }
  EXPECT_EQ(differing, 0u) << "direct light darkened by ambient occlusion, first " << first;
}

// With ambient light the occlusion darkens the corner, by at most the ambient share of the
// pixel (diffuse 0.8 x ambient 0.5 = 0.4, 102 of 255), however bright the direct light is there.
TEST_P(EffectsSsao, OcclusionTakesOnlyTheAmbientShare) {
  auto [backend, platform] = GetParam();
  auto dev = test::makeDevice(backend);
  if (!dev) return;
  const scene::Scene s = litCorner(glm::vec3(0.5f));
  techniques::DeferredSsao ssao;
  techniques::DeferredShading deferred;
  Rendered withAo = renderWith(*dev, ssao, s, platform);
  Rendered plain = renderWith(*dev, deferred, s, platform);
  ASSERT_EQ(withAo.color.size(), size_t{kWidth} * kHeight * 4);
  ASSERT_EQ(plain.color.size(), withAo.color.size());
  const int ambientShare = static_cast<int>(std::ceil(0.8f * 0.5f * 255.0f));
  int darkest = 0, brightened = 0, overShare = 0;
  for (size_t i = 0; i < plain.color.size(); ++i) {
    if (i % 4 == 3) continue;
    int darkening = int(plain.color[i]) - int(withAo.color[i]);
    darkest = std::max(darkest, darkening);
    brightened += darkening < 0;
    overShare += darkening > ambientShare + 1;
  }
  EXPECT_GE(darkest, 10) << "the occlusion must darken the ambient light in the corner";
  EXPECT_EQ(brightened, 0) << "ambient occlusion brightened a pixel";
  EXPECT_EQ(overShare, 0) << "the occlusion took more than the ambient share of a pixel";
}

INSTANTIATE_TEST_SUITE_P(Platforms, EffectsSsao,
                         ::testing::Combine(::testing::ValuesIn(test::allBackends()),
                                            ::testing::Values(platforms::PlatformId::Reference, platforms::PlatformId::Dx10,
                                                              platforms::PlatformId::Ps3, platforms::PlatformId::X360)),
                         [](const auto& info) {
                           return std::get<0>(info.param) + "_" + std::string(platforms::platformName(std::get<1>(info.param)));
                         });

}  // namespace
