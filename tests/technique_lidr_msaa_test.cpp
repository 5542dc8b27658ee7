// Light-indexed deferred rendering (Trebilco 2008), "MSAA Technique 2 - Light Volume Front
// Faces" with the transparency path it enables, and "Constraining Lights to Surfaces".
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"
#include "scene/scene_gpu.h"
#include "techniques/frame.h"
#include "techniques/light_indexed/light_indexed.h"
#include "tests/test_support.h"

using namespace parity;
using techniques::LightIndexedDeferred;

namespace {

constexpr uint32_t kWidth = 160, kHeight = 90;
// The tolerances of the other LIDR tests, against the float forward reference.
constexpr double kMeanTolerance = 0.5 / 255.0, kP99Tolerance = 4.0 / 255.0;

struct Frame {
  std::vector<float> color;    // RGBA32F
  std::vector<float> dropped;  // per pixel, averaged over the samples
  std::vector<float> depth;    // farthest sample (MSAA) or the surface (single-sample)
};

std::vector<float> asFloats(const std::vector<uint8_t>& bytes) {
  std::vector<float> f(bytes.size() / sizeof(float));
  std::memcpy(f.data(), bytes.data(), f.size() * sizeof(float));
  return f;
}

Frame render(rhi::Device& device, const scene::Scene& s, LightIndexedDeferred& technique, uint32_t w = kWidth,
             uint32_t h = kHeight) {
  scene::SceneGpu gpu(device, s);
  techniques::RenderSettings settings;
  settings.width = w;
  settings.height = h;
  settings.colorFormat = rhi::Format::RGBA32F;
  technique.prepare(device, settings);
  rhi::TextureHandle color = technique.render(device, gpu, s.cameras[0]);
  device.submit();
  Frame f;
  f.color = asFloats(device.readTexture(color));
  for (const techniques::NamedTarget& t : technique.targets()) {
    if (t.name == "lidr.dropped")
      f.dropped = test::redChannel(device.readTexture(t.texture), device.describe(t.texture)->format);
    if (t.name == "prepass.depth") f.depth = asFloats(device.readTexture(t.texture));
  }
  technique.release(device);
  return f;
}

LightIndexedDeferred msaaTechnique() {
  return LightIndexedDeferred(techniques::LidrPacking::Bits, *techniques::findBitPackingRow("8x255"),
                              techniques::LidrVolumes::FrontFacesMsaa);
}

// A quad facing +z at depth z, centred at (cx, 1).
void addQuad(scene::Scene& s, float cx, float z, float half, int material, const std::string& name) {
  uint32_t base = static_cast<uint32_t>(s.vertices.size());
  const glm::vec2 c[4] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  for (glm::vec2 p : c)
    s.vertices.push_back({glm::vec3(cx + p.x * half, 1.0f + p.y * half, z), glm::vec3(0, 0, 1), (p + 1.0f) * 0.5f});
  scene::Mesh m;
  m.name = name;
  m.firstIndex = static_cast<uint32_t>(s.indices.size());
  for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) s.indices.push_back(base + i);
  m.indexCount = 6;
  m.material = material;
  m.boundsMin = glm::vec3(cx - half, 1.0f - half, z);
  m.boundsMax = glm::vec3(cx + half, 1.0f + half, z);
  s.meshes.push_back(m);
}

scene::Scene baseScene() {
  scene::Scene s;
  s.name = "lidr-msaa";
  s.ambient = glm::vec3(0.05f);
  s.directionalColor = glm::vec3(0.1f);
  s.directionalDir = glm::vec3(0.2f, -0.3f, -1.0f);
  scene::Camera cam;
  cam.name = "default";
  cam.position = glm::vec3(0, 1, 4);
  cam.target = glm::vec3(0, 1, 0);
  s.cameras.push_back(cam);
  return s;
}

scene::Light pointLight(glm::vec3 position, float radius, glm::vec3 color) {
  scene::Light l;
  l.position = position;
  l.radius = radius;
  l.color = color;
  return l;
}

// An opaque wall at z = -6 and a translucent quad (opacity 0.5) at z = -1. Light 0 sits just in
// front of the quad and reaches it but not the wall (5 units behind, radius 1.5): only the
// front-face volumes put it in the wall pixels' light index. Light 1 lights the wall.
scene::Scene translucentScene(bool withQuadLight) {
  scene::Scene s = baseScene();
  s.ambient = glm::vec3(0.3f);
  scene::Material wall;
  wall.diffuse = glm::vec3(0.8f, 0.8f, 0.1f);  // little blue: the blue glass stands out
  s.materials.push_back(wall);
  scene::Material glass;
  glass.diffuse = glm::vec3(0.3f, 0.6f, 0.9f);
  glass.opacity = 0.5f;
  s.materials.push_back(glass);
  addQuad(s, 0.0f, -6.0f, 40.0f, 0, "wall");
  addQuad(s, 0.3f, -1.0f, 1.2f, 1, "glass");
  s.lights.push_back(pointLight(glm::vec3(1.5f, 1.0f, -5.2f), 2.0f, glm::vec3(1.5f, 1.2f, 1.0f)));
  if (withQuadLight) s.lights.push_back(pointLight(glm::vec3(0.2f, 1.1f, -0.4f), 1.5f, glm::vec3(1.8f, 1.6f, 1.2f)));
  return s;
}

struct ErrorStats {
  double mean = 0, p99 = 0, max = 0;
  size_t samples = 0;
};

ErrorStats colourError(const std::vector<float>& a, const std::vector<float>& b, const std::vector<bool>& use) {
  std::vector<double> e;
  for (size_t p = 0; p < use.size(); ++p)
    if (use[p])
      for (int c = 0; c < 3; ++c) e.push_back(std::fabs(static_cast<double>(a[p * 4 + c]) - b[p * 4 + c]));
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

class LidrMsaa : public ::testing::TestWithParam<std::string> {};

// The translucent quad is lit by the light in front of it through the single-sample light index
// texture, every pixel (edges included) as the same MSAA passes lighting every surface with every
// light, and the quad's edges are antialiased.
TEST_P(LidrMsaa, TranslucentSurfaceGetsTheLightsOfItsVolume) {
  auto device = test::makeDevice(GetParam());
  if (!device) return;
  scene::Scene s = translucentScene(true);
  LightIndexedDeferred lidr = msaaTechnique();
  EXPECT_EQ(lidr.name(), "lidr-msaa");
  Frame indexed = render(*device, s, lidr);
  LightIndexedDeferred everyLight = msaaTechnique();
  everyLight.setShadeEveryLight(true);
  Frame reference = render(*device, s, everyLight);
  LightIndexedDeferred unlitQuad = msaaTechnique();
  scene::Scene withoutLight = translucentScene(false);
  Frame without = render(*device, withoutLight, unlitQuad);
  const size_t pixels = size_t{kWidth} * kHeight;
  ASSERT_EQ(indexed.color.size(), pixels * 4);
  ASSERT_EQ(reference.color.size(), pixels * 4);
  ASSERT_EQ(indexed.dropped.size(), pixels);

  size_t droppedPixels = std::count_if(indexed.dropped.begin(), indexed.dropped.end(), [](float v) { return v != 0.0f; });
  EXPECT_EQ(droppedPixels, 0u);
  ErrorStats e = colourError(indexed.color, reference.color, std::vector<bool>(pixels, true));
  // The quad light's contribution, seen through the index texture.
  size_t litByQuadLight = 0, partial = 0;
  for (size_t p = 0; p < pixels; ++p) {
    if (indexed.color[p * 4 + 2] - without.color[p * 4 + 2] > 0.05f) ++litByQuadLight;
  }
  // Antialiasing: along the quad's vertical edges some pixels lie strictly between the quad's
  // and the wall's colour in the wall-only region (resolved partial coverage).
  for (uint32_t y = 0; y < kHeight; ++y)
    for (uint32_t x = 1; x + 1 < kWidth; ++x) {
      size_t p = size_t{y} * kWidth + x;
      float l = reference.color[(p - 1) * 4 + 2], c = reference.color[p * 4 + 2], r = reference.color[(p + 1) * 4 + 2];
      if (std::fabs(l - r) > 0.05f && c > std::min(l, r) + 0.01f && c < std::max(l, r) - 0.01f) ++partial;
    }
  std::printf("%s lidr-msaa translucent: vs every-light MSAA mean %.4f/255 p99 %.4f/255 max %.4f/255; "
              "pixels lit by the quad light %zu, antialiased edge pixels %zu\n",
              GetParam().c_str(), e.mean * 255, e.p99 * 255, e.max * 255, litByQuadLight, partial);
  EXPECT_LE(e.mean, kMeanTolerance);
  EXPECT_LE(e.p99, kP99Tolerance);
  EXPECT_LE(e.max, kP99Tolerance);
  EXPECT_GT(litByQuadLight, pixels / 50);
  EXPECT_GT(partial, 10u);
}

// The default scene: MSAA front-face LIDR against single-sample forward where all samples of a
// pixel see the same plane (edges differ by design: they are antialiased), and against its own
// every-light shading everywhere the packing kept every light.
TEST_P(LidrMsaa, EqualsForwardAwayFromEdges) {
  auto device = test::makeDevice(GetParam());
  if (!device) return;
  techniques::FrameRequest request;
  request.width = kWidth;
  request.height = kHeight;
  request.sceneParams.lightCount = 24;
  request.sceneParams.lightSize = scene::LightSize::Small;
  request.colorFormat = rhi::Format::RGBA32F;
  request.technique = "forward";
  techniques::FrameResult forward = techniques::renderFrameTexels(*device, request);
  ASSERT_TRUE(forward.ok) << forward.error;
  scene::Scene s = scene::makeDefaultScene(request.sceneParams);
  LightIndexedDeferred lidr = msaaTechnique();
  Frame indexed = render(*device, s, lidr);
  LightIndexedDeferred everyLight = msaaTechnique();
  everyLight.setShadeEveryLight(true);
  Frame reference = render(*device, s, everyLight);
  std::vector<float> fwd = asFloats(forward.texels);
  const size_t pixels = size_t{kWidth} * kHeight;
  ASSERT_EQ(indexed.depth.size(), pixels);
  ASSERT_EQ(fwd.size(), pixels * 4);

  // Interior: the farthest-sample depth is planar over the 3x3 neighbourhood (window-space depth
  // is affine on a plane), so no edge crosses it.
  std::vector<bool> interior(pixels, false), kept(pixels, false);
  size_t interiorCount = 0, droppedPixels = 0;
  for (uint32_t y = 1; y + 1 < kHeight; ++y)
    for (uint32_t x = 1; x + 1 < kWidth; ++x) {
      size_t p = size_t{y} * kWidth + x;
      auto d = [&](int dx, int dy) { return static_cast<double>(indexed.depth[p + dy * static_cast<int>(kWidth) + dx]); };
      bool planar = true;
      for (auto [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}, std::pair{1, 1}, std::pair{1, -1}})
        planar = planar && std::fabs(d(dx, dy) + d(-dx, -dy) - 2 * d(0, 0)) < 2e-6;
      bool lost = indexed.dropped[p] != 0.0f;
      droppedPixels += lost ? 1 : 0;
      interior[p] = planar && !lost && d(0, 0) < 1.0;
      kept[p] = !lost;
      interiorCount += interior[p] ? 1 : 0;
    }
  ErrorStats vsForward = colourError(indexed.color, fwd, interior);
  ErrorStats vsEvery = colourError(indexed.color, reference.color, kept);
  std::printf("%s lidr-msaa default scene: interior pixels %zu of %zu, losing light %zu; vs forward mean %.4f/255 "
              "p99 %.4f/255; vs every-light MSAA mean %.4f/255 p99 %.4f/255 max %.4f/255\n",
              GetParam().c_str(), interiorCount, pixels, droppedPixels, vsForward.mean * 255, vsForward.p99 * 255,
              vsEvery.mean * 255, vsEvery.p99 * 255, vsEvery.max * 255);
  EXPECT_GT(interiorCount, pixels / 4);
  EXPECT_LE(vsForward.mean, kMeanTolerance);
  EXPECT_LE(vsForward.p99, kP99Tolerance);
  EXPECT_LE(vsEvery.mean, kMeanTolerance);
  EXPECT_LE(vsEvery.p99, kP99Tolerance);
  EXPECT_LE(vsEvery.max, kP99Tolerance);
}

// Constraining lights to surfaces: two side-by-side walls under one light; the left wall's table
// nulls it. The light must not reach the left wall and must still light the right one, with
// both volume techniques.
TEST_P(LidrMsaa, SurfaceLightTableExcludesLight) {
  auto device = test::makeDevice(GetParam());
  if (!device) return;
  scene::Scene s = baseScene();
  s.directionalColor = glm::vec3(0.0f);
  scene::Material m;
  m.diffuse = glm::vec3(0.8f);
  s.materials.push_back(m);
  addQuad(s, -1.0f, -1.0f, 1.0f, 0, "left");
  addQuad(s, 1.0f, -1.0f, 1.0f, 0, "right");
  s.lights.push_back(pointLight(glm::vec3(0.0f, 1.0f, -0.5f), 3.0f, glm::vec3(2.0f)));
  for (techniques::LidrVolumes volumes : {techniques::LidrVolumes::SurfaceInside, techniques::LidrVolumes::FrontFacesMsaa}) {
    SCOPED_TRACE(volumes == techniques::LidrVolumes::SurfaceInside ? "single-sample" : "msaa");
    auto make = [&] {
      return LightIndexedDeferred(techniques::LidrPacking::Bits, *techniques::findBitPackingRow("4x255"), volumes);
    };
    LightIndexedDeferred all = make();
    Frame unconstrained = render(*device, s, all);
    LightIndexedDeferred constrained = make();
    techniques::SurfaceLightTables tables;
    tables.excluded = {{0}};  // table 0: without light 0
    tables.meshTable = {0, techniques::SurfaceLightTables::kAllLights};
    constrained.setSurfaceLightTables(tables);
    Frame split = render(*device, s, constrained);
    // Pixel columns well inside each wall, on the row through the light.
    const uint32_t y = kHeight / 2;
    double ambientOnly = 0.8 * 0.05;
    size_t leftChecked = 0, rightChecked = 0;
    for (uint32_t x = 0; x < kWidth; ++x) {
      size_t p = size_t{y} * kWidth + x;
      float before = unconstrained.color[p * 4], after = split.color[p * 4];
      if (x > kWidth * 35 / 100 && x < kWidth * 47 / 100) {  // left wall, near the light
        EXPECT_GT(before, ambientOnly + 0.03) << "x " << x;  // the light reaches it unconstrained
        EXPECT_NEAR(after, ambientOnly, 1e-4) << "x " << x;
        ++leftChecked;
      }
      if (x > kWidth * 53 / 100 && x < kWidth * 65 / 100) {  // right wall, near the light: unchanged, lit
        EXPECT_GT(after, ambientOnly + 0.03) << "x " << x;
        EXPECT_EQ(after, before) << "x " << x;
        ++rightChecked;
      }
    }
    EXPECT_GT(leftChecked, 10u);
    EXPECT_GT(rightChecked, 10u);
  }
}

// The technique declines the table rows it unpacks but does not render.
TEST_P(LidrMsaa, UnrenderedRowsAreRejected) {
  auto device = test::makeDevice(GetParam());
  if (!device) return;
  for (const char* row : {"16x255", "16x15", "1x65535", "8x65535"}) {
    LightIndexedDeferred t(techniques::LidrPacking::Bits, *techniques::findBitPackingRow(row));
    techniques::RenderSettings settings;
    EXPECT_THROW(t.prepare(*device, settings), techniques::TechniqueError) << row;
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, LidrMsaa, ::testing::ValuesIn(test::allBackends()), test::BackendName());

}  // namespace
