// Tangent-space normal maps (scene::Material::normalTexture, shaders/include/normal_mapping.glsl):
// the brightness of a normal-mapped plane against the value computed by hand, forward and
// deferred shading agreeing on a normal-mapped scene, and the loaders picking the maps up
// (glTF normalTexture, OBJ norm / bump).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <unistd.h>

#include "harness/io/image_io.h"
#include "scene/scene.h"
#include "scene/scene_gpu.h"
#include "techniques/technique.h"
#include "tests/test_support.h"

using namespace parity;

namespace {

namespace fs = std::filesystem;

constexpr uint32_t kWidth = 160, kHeight = 90;
constexpr float kPi = 3.14159265358979f;

// One RGBA8 texel of a tangent-space normal (n * 0.5 + 0.5, rounded), as a map stores it.
std::array<uint8_t, 4> encodeNormal(glm::vec3 n) {
  auto byte = [](float c) { return static_cast<uint8_t>(std::lround((c * 0.5f + 0.5f) * 255.0f)); };
  return {byte(n.x), byte(n.y), byte(n.z), 255};
}

scene::Texture constantTexture(const std::string& name, std::array<uint8_t, 4> texel) {
  scene::Texture t{name, 4, 4, {}};
  for (int i = 0; i < 16; ++i) t.rgba8.insert(t.rgba8.end(), texel.begin(), texel.end());
  return t;
}

// The plane y = 0 (8 x 8 units, normal +y) seen from straight above, with u along +x and v along
// +z: the camera's "up" is -z, so v = 0 is the image's top row, as in a texture. Lit only by the
// directional light (no ambient, no local lights), diffuse white, no specular: a pixel's value is
// max(0, N . -L).
scene::Scene normalMappedPlane(glm::vec3 tangentSpaceNormal, glm::vec3 directionToLight) {
  scene::Scene s;
  s.name = "normal-mapped plane";
  const float h = 4.0f;
  s.vertices = {{{-h, 0, -h}, {0, 1, 0}, {0, 0}},
                {{-h, 0, h}, {0, 1, 0}, {0, 1}},
                {{h, 0, h}, {0, 1, 0}, {1, 1}},
                {{h, 0, -h}, {0, 1, 0}, {1, 0}}};
  s.indices = {0, 1, 2, 0, 2, 3};
  s.meshes = {{"plane", 0, 6, 0, {-h, 0, -h}, {h, 0, h}}};
  scene::Material m;
  m.name = "normal mapped";
  m.diffuse = glm::vec3(1.0f);
  m.specular = glm::vec3(0.0f);
  m.specularPower = 1.0f;
  m.normalTexture = 0;
  s.materials = {m};
  s.textures = {constantTexture("tilted normals", encodeNormal(tangentSpaceNormal))};
  s.ambient = glm::vec3(0.0f);
  s.directionalDir = -directionToLight;
  s.directionalColor = glm::vec3(1.0f);
  scene::Camera c;
  c.name = "default";
  c.position = {0.0f, 3.0f, 0.0f};
  c.target = {0.0f, 0.0f, 0.0f};
  c.up = {0.0f, 0.0f, -1.0f};
  s.cameras = {c};
  return s;
}

// One RGBA32F frame of `scene` (its first camera) on the reference platform.
std::vector<float> renderScene(rhi::Device& device, const std::string& technique, const scene::Scene& s) {
  std::unique_ptr<techniques::Technique> t = techniques::createTechnique(technique);
  EXPECT_TRUE(t) << technique;
  if (!t) return {};
  scene::SceneGpu gpu(device, s);
  techniques::RenderSettings settings;
  settings.width = kWidth;
  settings.height = kHeight;
  settings.colorFormat = rhi::Format::RGBA32F;
  t->prepare(device, settings);
  rhi::TextureHandle color = t->render(device, gpu, s.cameras[0]);
  device.submit();
  std::vector<uint8_t> bytes = device.readTexture(color);
  t->release(device);
  device.submit();
  std::vector<float> f(bytes.size() / 4);
  std::memcpy(f.data(), bytes.data(), f.size() * 4);
  EXPECT_EQ(f.size(), size_t(kWidth) * kHeight * 4) << technique;
  return f;
}

// Every technique whose geometry pass shades or stores normals.
const char* const kTechniques[] = {"forward",        "forward-multipass", "deferred",       "light-prepass",
                                   "inferred",       "tiled-forward",     "tiled-deferred", "lidr-bits"};

class NormalMapTest : public ::testing::TestWithParam<std::string> {};

// A normal map tilting the normal by 30 degrees, lit at 45 degrees from the vertical: towards the
// light N . -L = cos 15 degrees = 0.9659, away from it cos 75 degrees = 0.2588; the unmapped
// plane would give cos 45 degrees = 0.7071. Tilts along the map's x (+u, world +x) and y (towards
// the top row, -v, world -z) check both axes and their signs. The map's 8-bit texels move the
// tilt by 0.12 degrees (0.0006 in brightness): the tolerance.
TEST_P(NormalMapTest, TiltedNormalsGiveTheHandComputedBrightness) {
  auto device = test::makeDevice(GetParam());
  if (!device) return;
  const float tilt = 30.0f * kPi / 180.0f, elevation = 45.0f * kPi / 180.0f;
  const float towards = std::cos(15.0f * kPi / 180.0f), away = std::cos(75.0f * kPi / 180.0f);
  struct Case {
    const char* what;
    glm::vec3 mapNormal, toLight;
    float expected;
  };
  const Case cases[] = {
      {"map +x, light at +x", {std::sin(tilt), 0, std::cos(tilt)}, {std::cos(elevation), std::sin(elevation), 0}, towards},
      {"map +x, light at -x", {std::sin(tilt), 0, std::cos(tilt)}, {-std::cos(elevation), std::sin(elevation), 0}, away},
      {"map +y, light at -z", {0, std::sin(tilt), std::cos(tilt)}, {0, std::sin(elevation), -std::cos(elevation)}, towards},
      {"map +y, light at +z", {0, std::sin(tilt), std::cos(tilt)}, {0, std::sin(elevation), std::cos(elevation)}, away},
  };
  for (const char* technique : kTechniques) {
    for (const Case& c : cases) {
      scene::Scene s = normalMappedPlane(c.mapNormal, glm::normalize(c.toLight));
      std::vector<float> image = renderScene(*device, technique, s);
      if (image.empty()) continue;
      // The middle half of the image: all plane (it fills the view), away from the border.
      float lo = 1e9f, hi = -1e9f;
      for (uint32_t y = kHeight / 4; y < kHeight * 3 / 4; ++y)
        for (uint32_t x = kWidth / 4; x < kWidth * 3 / 4; ++x)
          for (int ch = 0; ch < 3; ++ch) {
            float v = image[(size_t(y) * kWidth + x) * 4 + ch];
            lo = std::min(lo, v);
            hi = std::max(hi, v);
          }
      EXPECT_NEAR(lo, c.expected, 2e-3) << technique << ", " << c.what;
      EXPECT_NEAR(hi, c.expected, 2e-3) << technique << ", " << c.what;
    }
  }
}

// A bumpy procedural normal map (ripples along u and v) on every material of the default scene.
scene::Scene bumpyDefaultScene() {
  scene::Scene s = scene::makeDefaultScene({});
  scene::Texture t{"ripples", 64, 64, {}};
  for (uint32_t y = 0; y < t.height; ++y)
    for (uint32_t x = 0; x < t.width; ++x) {
      float a = 2.0f * kPi * float(x) / float(t.width), b = 2.0f * kPi * float(y) / float(t.height);
      glm::vec3 n = glm::normalize(glm::vec3(0.5f * std::sin(4.0f * a), 0.5f * std::cos(3.0f * b), 1.0f));
      std::array<uint8_t, 4> texel = encodeNormal(n);
      t.rgba8.insert(t.rgba8.end(), texel.begin(), texel.end());
    }
  int index = static_cast<int>(s.textures.size());
  s.textures.push_back(std::move(t));
  for (scene::Material& m : s.materials) m.normalTexture = index;
  return s;
}

struct ErrorStats {
  double mean = 0, p99 = 0, max = 0;
};

// Absolute RGB error in 1/255 units.
ErrorStats rgbError(const std::vector<float>& a, const std::vector<float>& b) {
  ErrorStats s;
  std::vector<double> errors;
  for (size_t i = 0; i + 3 < std::min(a.size(), b.size()); i += 4)
    for (int c = 0; c < 3; ++c) errors.push_back(std::fabs(double(a[i + c]) - b[i + c]) * 255.0);
  if (errors.empty()) return s;
  for (double e : errors) s.mean += e;
  s.mean /= double(errors.size());
  std::sort(errors.begin(), errors.end());
  s.p99 = errors[std::min(errors.size() - 1, size_t(double(errors.size()) * 0.99))];
  s.max = errors.back();
  return s;
}

// Deferred shading stores the mapped normal in its G-buffer; with the bounds the deferred tests
// use against forward (technique_deferred_test.cpp) the two agree, while the map itself changes
// the image far beyond them.
TEST_P(NormalMapTest, ForwardAndDeferredAgreeOnANormalMappedScene) {
  auto device = test::makeDevice(GetParam());
  if (!device) return;
  scene::Scene bumpy = bumpyDefaultScene();
  std::vector<float> forward = renderScene(*device, "forward", bumpy);
  std::vector<float> deferred = renderScene(*device, "deferred", bumpy);
  ErrorStats e = rgbError(forward, deferred);
  EXPECT_LE(e.mean, 0.05);
  EXPECT_LE(e.p99, 0.5);

  std::vector<float> flat = renderScene(*device, "forward", scene::makeDefaultScene({}));
  ErrorStats mapped = rgbError(forward, flat);
  EXPECT_GE(mapped.mean, 1.0) << "the normal map changes the image";
  EXPECT_GE(mapped.max, 20.0) << "the normal map changes the image";
}

INSTANTIATE_TEST_SUITE_P(Backends, NormalMapTest, ::testing::ValuesIn(test::allBackends()), test::BackendName());

// The mean tangent-space normal of a map: a normal map's points up (+z, blue), a height map's
// grey texels decode to about (0, 0, 0).
glm::vec3 meanNormal(const scene::Texture& t) {
  glm::dvec3 sum(0.0);
  for (size_t i = 0; i + 3 < t.rgba8.size(); i += 4)
    sum += glm::dvec3(t.rgba8[i], t.rgba8[i + 1], t.rgba8[i + 2]) / 255.0 * 2.0 - 1.0;
  return glm::vec3(sum / double(t.rgba8.size() / 4));
}

TEST(NormalMapLoading, GltfNormalTangentTestLoadsItsNormalMap) {
  const std::string path = scene::assetScenePath("gltf-normal-tangent-test");
  if (path.empty() || !fs::exists(path)) GTEST_SKIP() << "shared asset not present: " << path;
  scene::Scene s;
  std::string error;
  ASSERT_TRUE(scene::loadSceneFile(path, {}, &s, &error)) << error;
  int mapped = 0;
  for (const scene::Material& m : s.materials) {
    if (m.normalTexture < 0) continue;
    ++mapped;
    ASSERT_LT(size_t(m.normalTexture), s.textures.size()) << m.name;
    const scene::Texture& t = s.textures[size_t(m.normalTexture)];
    EXPECT_GT(t.width, 1u);
    EXPECT_NE(m.normalTexture, m.diffuseTexture) << "its own texture, not the base colour";
    EXPECT_GT(meanNormal(t).z, 0.5f) << t.name << ": a tangent-space normal map points mostly along +z";
  }
  EXPECT_GE(mapped, 1) << "no material got the sample's normalTexture";
}

// OBJ: `norm` names a normal map, used as it is; `bump` a grey height map, converted to normals
// (a ramp rising to the right tilts them to -x).
TEST(NormalMapLoading, ObjNormAndBumpMaps) {
  const fs::path dir = fs::temp_directory_path() / ("parity-normal-map-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  auto writePng = [&](const std::string& name, uint32_t w, uint32_t h, auto texelOf) {
    std::vector<uint8_t> texels;
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x) {
        std::array<uint8_t, 4> t = texelOf(x, y);
        texels.insert(texels.end(), t.begin(), t.end());
      }
    std::string error;
    ASSERT_TRUE(harness::writeImage((dir / name).string(), harness::imageFromTexels(texels, rhi::Format::RGBA8, w, h), &error))
        << error;
  };
  const std::array<uint8_t, 4> tilted = encodeNormal(glm::normalize(glm::vec3(0.5f, 0.0f, 1.0f)));
  writePng("normals.png", 4, 4, [&](uint32_t, uint32_t) { return tilted; });
  // A ramp that wraps only at the edges: interior texels see a constant slope of 8 / 255 per texel.
  writePng("height.png", 16, 4, [](uint32_t x, uint32_t) {
    uint8_t v = static_cast<uint8_t>(x * 8);
    return std::array<uint8_t, 4>{v, v, v, 255};
  });
  std::ofstream(dir / "maps.mtl") << "newmtl normal\nKd 1 1 1\nnorm normals.png\n"
                                     "newmtl bumpy\nKd 1 1 1\nbump height.png\n"
                                     "newmtl plain\nKd 1 1 1\n";
  std::ofstream(dir / "maps.obj") << "mtllib maps.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
                                     "usemtl normal\nf 1/1 2/2 3/3\nusemtl bumpy\nf 1/1 3/3 4/3\nusemtl plain\nf 2/2 3/3 4/3\n";
  scene::Scene s;
  std::string error;
  bool loaded = scene::loadSceneFile((dir / "maps.obj").string(), {}, &s, &error);
  fs::remove_all(dir);
  ASSERT_TRUE(loaded) << error;
  const char* const names[3] = {"normal", "bumpy", "plain"};
  const scene::Material* byName[3] = {};
  for (const scene::Material& m : s.materials)
    for (int i = 0; i < 3; ++i)
      if (m.name == names[i]) byName[i] = &m;
  ASSERT_TRUE(byName[0] && byName[1] && byName[2]);
  EXPECT_EQ(byName[2]->normalTexture, -1);

  ASSERT_GE(byName[0]->normalTexture, 0);
  const scene::Texture& normals = s.textures[size_t(byName[0]->normalTexture)];
  EXPECT_EQ(std::vector<uint8_t>(normals.rgba8.begin(), normals.rgba8.begin() + 4),
            std::vector<uint8_t>(tilted.begin(), tilted.end()))
      << "a normal map is kept as it is";

  ASSERT_GE(byName[1]->normalTexture, 0);
  const scene::Texture& bump = s.textures[size_t(byName[1]->normalTexture)];
  ASSERT_EQ(bump.width, 16u);
  // Interior texel (x = 8): slope 8 / 255 per texel, times the heuristic strength 8.
  const uint8_t* texel = &bump.rgba8[(1 * 16 + 8) * 4];
  glm::vec3 expected = glm::normalize(glm::vec3(-8.0f / 255.0f * 8.0f, 0.0f, 1.0f));
  EXPECT_NEAR(texel[0] / 255.0f * 2.0f - 1.0f, expected.x, 0.01f);
  EXPECT_NEAR(texel[1] / 255.0f * 2.0f - 1.0f, 0.0f, 0.01f);
  EXPECT_NEAR(texel[2] / 255.0f * 2.0f - 1.0f, expected.z, 0.01f);
}

}  // namespace
