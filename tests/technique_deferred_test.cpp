// Deferred shading (thesis §3.1.4) against the reference, forward single-pass shading in float:
// on the reference platform, on every console platform (with bounds derived from what their
// target formats keep), and with the camera inside a light's volume.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "platforms/common/platform.h"
#include "scene/scene.h"
#include "scene/scene_gpu.h"
#include "techniques/deferred/deferred.h"
#include "techniques/frame.h"
#include "tests/test_support.h"

using namespace parity;

namespace {

// Absolute error of the RGB channels of two RGBA32F images, in 1/255 units.
struct ErrorStats {
  double mean = 0, p99 = 0, max = 0;
};

ErrorStats rgbError(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  ErrorStats s;
  size_t n = std::min(a.size(), b.size()) / 16;
  std::vector<float> fa(n * 4), fb(n * 4);
  std::memcpy(fa.data(), a.data(), n * 16);
  std::memcpy(fb.data(), b.data(), n * 16);
  std::vector<double> errors;
  errors.reserve(n * 3);
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) errors.push_back(std::fabs(double(fa[i * 4 + c]) - fb[i * 4 + c]) * 255.0);
  if (errors.empty()) return s;
  for (double e : errors) s.mean += e;
  s.mean /= double(errors.size());
  std::sort(errors.begin(), errors.end());
  s.p99 = errors[std::min(errors.size() - 1, size_t(double(errors.size()) * 0.99))];
  s.max = errors.back();
  return s;
}

techniques::FrameResult render(rhi::Device& device, const std::string& technique, const std::string& camera,
                               platforms::PlatformId platform = platforms::PlatformId::Reference,
                               scene::LightSize size = scene::LightSize::Small) {
  techniques::FrameRequest r;
  r.technique = technique;
  r.camera = camera;
  r.colorFormat = rhi::Format::RGBA32F;
  r.platform = platform;
  // Host pixel centres on x360 (HALFPIXELOFFSET true): these tests measure what the platforms'
  // target formats do; the D3D9 centres are tests/platform_pixel_center_test.cpp's.
  r.platformParams.halfPixelOffset = true;
  r.sceneParams.lightSize = size;
  return techniques::renderFrameTexels(device, r);
}

const char* const kCameras[] = {"default", "high", "grazing", "side", "close"};

class DeferredShadingTest : public ::testing::TestWithParam<std::string> {};

// The bound: mean <= 0.5/255 and 99th percentile <= 4/255 on the default scene. Deferred
// shading evaluates the same expressions (phong.glsl, deferred_light.glsl); what differs is the
// position (reconstructed from D32F depth through the inverse view-projection instead of
// interpolated), the normal (half-sphere encoded and decoded) and the order of the sums (the
// blender adds the lights one by one in fp32). All cameras, small and big lights.
// Tightened to what these sources allow with margin: the measured figures are printed.
TEST_P(DeferredShadingTest, AgreesWithForwardOnReference) {
  auto device = test::makeDevice(GetParam());
  if (!device) return;
  for (scene::LightSize size : {scene::LightSize::Small, scene::LightSize::Big}) {
    for (const char* camera : kCameras) {
      techniques::FrameResult forward = render(*device, "forward", camera, platforms::PlatformId::Reference, size);
      techniques::FrameResult deferred = render(*device, "deferred", camera, platforms::PlatformId::Reference, size);
      ASSERT_TRUE(forward.ok) << forward.error;
      ASSERT_TRUE(deferred.ok) << deferred.error;
      ErrorStats e = rgbError(forward.texels, deferred.texels);
      std::printf("%s deferred vs forward, reference, %s lights, camera %s: mean %.4f/255, p99 %.4f/255, max %.3f/255\n",
                  GetParam().c_str(), size == scene::LightSize::Small ? "small" : "big", camera, e.mean, e.p99, e.max);
      EXPECT_LE(e.mean, 0.05) << camera;
      EXPECT_LE(e.p99, 0.5) << camera;
    }
  }
}

// Every platform renders it, and its error against the reference follows from what its formats
// keep (platforms/*_layer.cpp):
//  * diffuse and specular colours in 8 bits (dx10, ps3, x360): half a level of the colour, times
//    the light arriving at the pixel. The default scene's lights have intensities 1-2 per
//    channel and the windowed attenuation is <= 1, ambient and directional add 0.2: where two of
//    the brightest lights overlap near their centres the light is <= 4, so <= 2/255;
//  * light accumulation in 16-bit float: 2^-11 of the running sum per blended light, < 0.1/255
//    for sums below 2 and the few lights that overlap;
//  * normals through the platform's Rg16 path (16 bits, or the x360 resolve path's precision) and
//    depth in 24 bits: angle and position errors near 1e-4, below 0.1/255 of shading.
// So max <= 2/255 (measured 0.70/255); the mean and 99th percentile stay within the issue's
// reference bound (0.5/255, 4/255), tightened to 0.1/255 and 0.5/255 (measured 0.05 and 0.15).
TEST_P(DeferredShadingTest, RendersOnEveryPlatform) {
  auto device = test::makeDevice(GetParam());
  if (!device) return;
  techniques::FrameResult forward = render(*device, "forward", "default");
  ASSERT_TRUE(forward.ok) << forward.error;
  for (platforms::PlatformId p : {platforms::PlatformId::Reference, platforms::PlatformId::Dx10,
                                  platforms::PlatformId::Ps3, platforms::PlatformId::X360}) {
    techniques::FrameResult deferred = render(*device, "deferred", "default", p);
    ASSERT_TRUE(deferred.ok) << platforms::platformName(p) << ": " << deferred.error;
    ErrorStats e = rgbError(forward.texels, deferred.texels);
    std::printf("%s deferred vs forward, platform %s: mean %.4f/255, p99 %.4f/255, max %.3f/255\n",
                GetParam().c_str(), std::string(platforms::platformName(p)).c_str(), e.mean, e.p99, e.max);
    EXPECT_LE(e.mean, 0.1) << platforms::platformName(p);
    EXPECT_LE(e.p99, 0.5) << platforms::platformName(p);
    EXPECT_LE(e.max, 2.0) << platforms::platformName(p);
  }
}

// A tiny scene rendered by a technique directly (renderFrameTexels builds its scenes by name).
std::vector<uint8_t> renderScene(rhi::Device& device, const std::string& name, const scene::Scene& s,
                                 uint32_t* insideCount = nullptr) {
  std::unique_ptr<techniques::Technique> technique = techniques::createTechnique(name);
  EXPECT_TRUE(technique) << name;
  if (!technique) return {};
  scene::SceneGpu gpu(device, s);
  techniques::RenderSettings settings;
  settings.colorFormat = rhi::Format::RGBA32F;
  technique->prepare(device, settings);
  rhi::TextureHandle color = technique->render(device, gpu, s.cameras[0]);
  device.submit();
  std::vector<uint8_t> texels = device.readTexture(color);
  if (insideCount)
    if (auto* d = dynamic_cast<techniques::DeferredShading*>(technique.get())) *insideCount = d->lightsDrawnFromInside();
  technique->release(device);
  device.submit();
  return texels;
}

// The camera inside a point light's sphere and inside a spot light's cone: their volumes' front
// faces lie behind the near plane, so they are drawn with back faces and an inverted depth test.
// The light must still reach the pixels, as in forward shading.
TEST_P(DeferredShadingTest, CameraInsideLightVolume) {
  auto device = test::makeDevice(GetParam());
  if (!device) return;
  scene::SceneParams params;
  params.lightCount = 0;
  for (scene::LightType type : {scene::LightType::Point, scene::LightType::Spot}) {
    scene::Scene s = scene::makeDefaultScene(params);
    const scene::Camera& camera = s.cameras[0];  // at (0, 5, 13), looking at (0, 1, -1)
    scene::Light light;
    light.type = type;
    light.position = camera.position + glm::vec3(0.0f, 0.5f, 0.5f);  // just behind the camera
    light.color = glm::vec3(3.0f, 2.4f, 1.6f);
    light.radius = 14.0f;
    light.direction = glm::normalize(camera.target - camera.position);
    light.cosOuter = std::cos(0.6f);
    light.cosInner = std::cos(0.4f);
    s.lights.push_back(light);
    ASSERT_TRUE(techniques::cameraInsideLightVolume(light, camera, 320.0f / 180.0f));

    uint32_t inside = 0;
    std::vector<uint8_t> forward = renderScene(*device, "forward", s);
    std::vector<uint8_t> deferred = renderScene(*device, "deferred", s, &inside);
    s.lights.clear();
    std::vector<uint8_t> unlit = renderScene(*device, "forward", s);
    ASSERT_EQ(forward.size(), size_t(320 * 180 * 16));
    ASSERT_EQ(deferred.size(), forward.size());
    EXPECT_EQ(inside, 1u) << "the light was not drawn from inside its volume";
    ErrorStats e = rgbError(forward, deferred);
    ErrorStats lightContribution = rgbError(forward, unlit);
    const char* kind = type == scene::LightType::Point ? "point" : "spot";
    std::printf("%s camera inside a %s light: light adds mean %.2f/255; deferred vs forward mean %.4f/255, p99 "
                "%.4f/255, max %.3f/255\n",
                GetParam().c_str(), kind, lightContribution.mean, e.mean, e.p99, e.max);
    EXPECT_GT(lightContribution.mean, 2.0) << kind << ": the test light must light the scene";
    EXPECT_LE(e.mean, 0.05) << kind;
    EXPECT_LE(e.p99, 0.5) << kind;
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, DeferredShadingTest, ::testing::ValuesIn(test::allBackends()), test::BackendName());

}  // namespace
