// Forward shading, multi-pass (thesis §3.1.3) against single-pass, and the bounding-volume tests
// behind its light lists (§3.1.1).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include <OpenImageIO/imagebuf.h>

#include <unistd.h>

#include <filesystem>

#include "harness/run/process.h"
#include "scene/culling.h"
#include "scene/scene_gpu.h"
#include "techniques/technique.h"
#include "techniques/frame.h"
#include "tests/test_support.h"

using namespace parity;

namespace {

const scene::Aabb kUnitBox{{0, 0, 0}, {1, 1, 1}};

TEST(Culling, DistanceSquaredPointAabb) {
  EXPECT_FLOAT_EQ(scene::distanceSquaredPointAabb({0.5f, 0.5f, 0.5f}, kUnitBox), 0.0f);  // inside
  EXPECT_FLOAT_EQ(scene::distanceSquaredPointAabb({3, 0.5f, 0.5f}, kUnitBox), 4.0f);     // 2 off +x
  EXPECT_FLOAT_EQ(scene::distanceSquaredPointAabb({-1, -2, 0.5f}, kUnitBox), 5.0f);      // edge: 1 + 4
  EXPECT_FLOAT_EQ(scene::distanceSquaredPointAabb({2, 2, 2}, kUnitBox), 3.0f);           // corner: 1+1+1
}

TEST(Culling, SphereAabb) {
  EXPECT_TRUE(scene::sphereIntersectsAabb({0.5f, 0.5f, 0.5f}, 0.1f, kUnitBox));  // centre inside
  EXPECT_TRUE(scene::sphereIntersectsAabb({3, 0.5f, 0.5f}, 2.01f, kUnitBox));
  EXPECT_FALSE(scene::sphereIntersectsAabb({3, 0.5f, 0.5f}, 1.99f, kUnitBox));
  EXPECT_FALSE(scene::sphereIntersectsAabb({3, 0.5f, 0.5f}, 2.0f, kUnitBox));  // touching: light is 0 there
  // Corner (1,1,1) is sqrt(3) = 1.732 from (2,2,2); the face centres are further.
  EXPECT_TRUE(scene::sphereIntersectsAabb({2, 2, 2}, 1.74f, kUnitBox));
  EXPECT_FALSE(scene::sphereIntersectsAabb({2, 2, 2}, 1.72f, kUnitBox));
}

TEST(Culling, ConeAabb) {
  const float cos45 = std::sqrt(0.5f);
  // A spot 3 above the box's top face, pointing down, 45 degree half-angle, long range: the cone's
  // footprint on the plane y = 1 is a disc of radius 3 around (0.5, 1, 0.5).
  glm::vec3 apex{0.5f, 4, 0.5f}, down{0, -1, 0};
  EXPECT_TRUE(scene::coneIntersectsAabb(apex, down, cos45, 10.0f, kUnitBox));
  // Pointing up, away from the box.
  EXPECT_FALSE(scene::coneIntersectsAabb(apex, {0, 1, 0}, cos45, 10.0f, kUnitBox));
  // Pointing down but the range (2.9) ends before the top face (3 away).
  EXPECT_FALSE(scene::coneIntersectsAabb(apex, down, cos45, 2.9f, kUnitBox));
  // Apex moved 5 along x: the nearest box point (1, 1, 0.5) is 4.5 sideways and 3 down, at
  // atan(4.5 / 3) = 56 degrees from the axis: outside a 45 degree cone ...
  EXPECT_FALSE(scene::coneIntersectsAabb({5.5f, 4, 0.5f}, down, cos45, 10.0f, kUnitBox));
  // ... inside a 60 degree one.
  EXPECT_TRUE(scene::coneIntersectsAabb({5.5f, 4, 0.5f}, down, 0.5f, 10.0f, kUnitBox));
  // A box straddling a narrow cone with all 8 corners outside it (the thesis's corner test
  // would reject it): a long thin box across the axis.
  scene::Aabb bar{{-5, -0.1f, -0.1f}, {5, 0.1f, 0.1f}};
  EXPECT_TRUE(scene::coneIntersectsAabb({0, 5, 0}, down, std::cos(0.1f), 10.0f, bar));
  // Apex inside the box: always touching.
  EXPECT_TRUE(scene::coneIntersectsAabb({0.5f, 0.5f, 0.5f}, {1, 0, 0}, cos45, 0.1f, kUnitBox));
}

TEST(Culling, FrustumAabb) {
  scene::Camera cam;
  cam.position = {0, 0, 0};
  cam.target = {0, 0, -1};
  cam.fovYDegrees = 90.0f;
  cam.nearPlane = 0.1f;
  cam.farPlane = 10.0f;
  scene::Frustum f = scene::frustumFromViewProjection(cam.viewProjection(1.0f));
  EXPECT_TRUE(scene::frustumIntersectsAabb(f, {{-0.5f, -0.5f, -3}, {0.5f, 0.5f, -2}}));   // ahead
  EXPECT_FALSE(scene::frustumIntersectsAabb(f, {{-0.5f, -0.5f, 2}, {0.5f, 0.5f, 3}}));    // behind
  EXPECT_FALSE(scene::frustumIntersectsAabb(f, {{-0.5f, -0.5f, -13}, {0.5f, 0.5f, -12}})); // past far
  EXPECT_FALSE(scene::frustumIntersectsAabb(f, {{3, -0.5f, -2}, {4, 0.5f, -1}}));         // right of x = -z
  EXPECT_TRUE(scene::frustumIntersectsAabb(f, {{1.5f, -0.5f, -2}, {4, 0.5f, -1}}));       // crosses it
  EXPECT_FALSE(scene::frustumIntersectsAabb(f, {{-0.5f, 3, -2}, {0.5f, 4, -1}}));         // above
}

// Every mesh a light's list leaves out receives none of its light: at each vertex and triangle
// centroid the windowed attenuation (0 at the radius) or the spot factor (0 outside the outer
// cone) is zero. And the lists are useful: small lights skip most meshes.
TEST(Culling, DefaultSceneLightListsLeaveOutOnlyUnlitMeshes) {
  for (scene::LightSize size : {scene::LightSize::Small, scene::LightSize::Big}) {
    scene::SceneParams params;
    params.lightSize = size;
    params.lightCount = 32;
    scene::Scene s = scene::makeDefaultScene(params);
    scene::LightLists lists = scene::buildLightLists(s, s.cameras[0].viewProjection(scene::kLightSizeAspect));
    ASSERT_EQ(lists.perLight.size(), s.lights.size());
    size_t listed = 0;
    for (size_t l = 0; l < s.lights.size(); ++l) {
      const scene::Light& light = s.lights[l];
      listed += lists.perLight[l].size();
      for (uint32_t m : lists.visible) {
        if (std::find(lists.perLight[l].begin(), lists.perLight[l].end(), m) != lists.perLight[l].end()) continue;
        const scene::Mesh& mesh = s.meshes[m];
        for (uint32_t i = mesh.firstIndex; i < mesh.firstIndex + mesh.indexCount; i += 3) {
          glm::vec3 a = s.vertices[s.indices[i]].position, b = s.vertices[s.indices[i + 1]].position,
                    c = s.vertices[s.indices[i + 2]].position;
          for (glm::vec3 p : {a, b, c, (a + b + c) / 3.0f}) {
            glm::vec3 toSurface = p - light.position;
            float d = glm::length(toSurface);
            bool lit = d < light.radius;
            if (lit && light.type == scene::LightType::Spot)
              lit = glm::dot(glm::normalize(light.direction), toSurface / d) > light.cosOuter;
            ASSERT_FALSE(lit) << "light " << l << " reaches '" << mesh.name << "' but its list leaves it out";
          }
        }
      }
    }
    if (size == scene::LightSize::Small) {
      EXPECT_LT(listed, lists.visible.size() * s.lights.size() / 2) << "lists too long";
    }
    std::printf("%s lights: %zu of %zu light x visible-mesh pairs drawn\n", size == scene::LightSize::Small ? "small" : "big",
                listed, lists.visible.size() * s.lights.size());
  }
}

class ForwardTechniques : public ::testing::TestWithParam<std::string> {};

struct Difference {
  double maxAbs = 0;
  size_t differing = 0;
};

Difference compareFloat(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  Difference d;
  size_t n = a.size() / 4;
  const float* fa = reinterpret_cast<const float*>(a.data());
  const float* fb = reinterpret_cast<const float*>(b.data());
  for (size_t i = 0; i < n; ++i) {
    double x = std::fabs(static_cast<double>(fa[i]) - fb[i]);
    if (fa[i] != fb[i]) ++d.differing;
    d.maxAbs = std::max(d.maxAbs, x);
  }
  return d;
}

Difference compareBytes(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  Difference d;
  for (size_t i = 0; i < a.size(); ++i) {
    double x = std::abs(static_cast<int>(a[i]) - static_cast<int>(b[i]));
    if (x > 0) ++d.differing;
    d.maxAbs = std::max(d.maxAbs, x);
  }
  return d;
}

// In RGBA32F the multi-pass sum is the single-pass shader's sum: the same terms computed by the
// same arithmetic (phong.glsl, parity_math.glsl), added in the same order (ambient, directional,
// then the lights in scene order), each addition rounded once to float, in the shader or in the
// blender; lights a list leaves out add exactly 0 in the single-pass shader. So the images are
// equal: measured bit-identical on Mesa 22.3.6 (llvmpipe and lavapipe), and required so there.
// Another driver's compiler may fuse the single-pass shader's `color += term` into one
// multiply-add (one rounding instead of two); with up to 25 terms of at most a few units that is
// below 1e-5, the tolerance used off Mesa.
// In RGBA8 every pass rounds to 1/255 (clamping at 1 cannot differ: every term is >= 0), so the
// bound is half a level per pass, 12.5 levels for 25 passes; measured: 1 level with small lights,
// 4 with big ones (where many passes touch each pixel).
constexpr double kOtherDriverFloatTolerance = 1e-5;
constexpr double kRgba8Tolerance = 12.5;

bool isMesa(const std::string& renderer) {
  return renderer.find("llvmpipe") != std::string::npos || renderer.find("lavapipe") != std::string::npos;
}

TEST_P(ForwardTechniques, MultiPassEqualsSinglePass) {
  auto device = test::makeDevice(GetParam());
  if (!device) return;
  for (scene::LightSize size : {scene::LightSize::Small, scene::LightSize::Big}) {
    for (const char* camera : {"default", "high", "close"}) {
      techniques::FrameRequest request;
      request.camera = camera;
      request.sceneParams.lightSize = size;
      request.sceneParams.lightCount = 24;
      request.colorFormat = rhi::Format::RGBA32F;
      request.technique = "forward";
      techniques::FrameResult single = techniques::renderFrameTexels(*device, request);
      request.technique = "forward-multipass";
      techniques::FrameResult multi = techniques::renderFrameTexels(*device, request);
      ASSERT_TRUE(single.ok) << single.error;
      ASSERT_TRUE(multi.ok) << multi.error;
      Difference d = compareFloat(single.texels, multi.texels);
      std::printf("%s %s/%s RGBA32F: %zu channels differ, max %.3g\n", GetParam().c_str(),
                  size == scene::LightSize::Small ? "small" : "big", camera, d.differing, d.maxAbs);
      if (isMesa(device->info().renderer)) EXPECT_EQ(d.differing, 0u) << camera;
      else EXPECT_LE(d.maxAbs, kOtherDriverFloatTolerance) << camera;

      request.colorFormat = rhi::Format::RGBA8;
      request.technique = "forward";
      single = techniques::renderFrameTexels(*device, request);
      request.technique = "forward-multipass";
      multi = techniques::renderFrameTexels(*device, request);
      ASSERT_TRUE(single.ok && multi.ok);
      Difference d8 = compareBytes(single.texels, multi.texels);
      std::printf("%s %s/%s RGBA8: %zu channels differ, max %g levels\n", GetParam().c_str(),
                  size == scene::LightSize::Small ? "small" : "big", camera, d8.differing, d8.maxAbs);
      EXPECT_LE(d8.maxAbs, kRgba8Tolerance) << camera;
    }
  }
}

// `parity render --passes DIR` writes every target of the frame: the 8-bit colour as PNG, depth
// (and float colour) as EXR, with the pixels of the frame.
TEST_P(ForwardTechniques, RenderDumpsPassTargets) {
  if (!test::makeDevice(GetParam())) return;  // skips when the backend is unavailable
  namespace fs = std::filesystem;
  fs::path dir = fs::temp_directory_path() / ("parity-passes-" + GetParam() + "-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);  // the output's folder must exist; --passes creates its own
  for (const char* format : {"rgba8", "rgba32f"}) {
    bool isFloat = std::string(format) == "rgba32f";
    fs::path out = dir / (std::string("final.") + (isFloat ? "exr" : "png"));
    fs::path passes = dir / format;
    harness::ProcessResult r = harness::runProcess({PARITY_BINARY, "render", "-b", GetParam(), "-t", "forward-multipass",
                                                    "--format", format, "-o", out.string(), "--passes", passes.string()},
                                                   120);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    fs::path color = passes / (std::string("color.") + (isFloat ? "exr" : "png"));
    ASSERT_TRUE(fs::is_regular_file(color)) << r.err;
    ASSERT_TRUE(fs::is_regular_file(passes / "depth.exr")) << r.err;
    OIIO::ImageBuf depth((passes / "depth.exr").string()), finalImage(out.string()), colorImage(color.string());
    ASSERT_TRUE(depth.read() && finalImage.read() && colorImage.read());
    EXPECT_EQ(depth.spec().nchannels, 1);
    EXPECT_EQ(depth.spec().width, 320);
    // Depth in [0, 1], not all cleared (the scene covers most of the image).
    float minDepth = 1.0f;
    for (int y = 0; y < 180; y += 9)
      for (int x = 0; x < 320; x += 8) {
        float d = depth.getchannel(x, y, 0, 0);
        EXPECT_GE(d, 0.0f);
        EXPECT_LE(d, 1.0f);
        minDepth = std::min(minDepth, d);
      }
    EXPECT_LT(minDepth, 1.0f);
    // The colour target is the final image.
    for (int y = 0; y < 180; y += 17)
      for (int x = 0; x < 320; x += 13)
        for (int c = 0; c < 3; ++c)
          ASSERT_EQ(colorImage.getchannel(x, y, 0, c), finalImage.getchannel(x, y, 0, c)) << x << "," << y;
  }
  fs::remove_all(dir);
}

// Forward's shading at chosen pixels against the thesis's equations evaluated here (§3.1.2: eq.
// 3.5 ambient, 3.9-3.10 Phong diffuse and specular, 3.11 windowed attenuation, 3.12 spot
// factor): a floor lit by one point light and one spot, seen from above, read back as RGBA32F.
// The floor is planar, so the fragment's interpolated position is the ray's hit on it.
TEST_P(ForwardTechniques, ShadingMatchesTheThesisEquationsAtChosenPixels) {
  auto device = test::makeDevice(GetParam());
  if (!device) return;
  scene::Scene s;
  s.name = "analytic";
  s.materials = {{"floor", {0.6f, 0.5f, 0.4f}, {0.5f, 0.5f, 0.5f}, 16.0f, -1}};
  const glm::vec3 up{0, 1, 0};
  for (glm::vec3 p : {glm::vec3(-20, 0, -20), glm::vec3(20, 0, -20), glm::vec3(20, 0, 20), glm::vec3(-20, 0, 20)})
    s.vertices.push_back({p, up, {0, 0}});
  s.indices = {0, 3, 2, 0, 2, 1};  // counter-clockwise seen from above
  s.meshes = {{"floor", 0, 6, 0, {-20, 0, -20}, {20, 0, 20}}};
  s.ambient = glm::vec3(0.05f);
  s.directionalColor = glm::vec3(0.0f);
  scene::Light point;
  point.position = {-1.0f, 1.0f, 0.0f};
  point.color = {1.0f, 0.8f, 0.6f};
  point.radius = 3.0f;
  scene::Light spot;
  spot.type = scene::LightType::Spot;
  spot.position = {1.5f, 2.0f, 0.5f};
  spot.direction = glm::normalize(glm::vec3(0.2f, -1.0f, 0.0f));
  spot.color = {0.4f, 0.7f, 1.0f};
  spot.radius = 4.0f;
  spot.cosOuter = std::cos(glm::radians(35.0f));
  spot.cosInner = std::cos(glm::radians(20.0f));
  s.lights = {point, spot};
  s.cameras = {{"above", {0.0f, 5.0f, 3.0f}, {0.0f, 0.0f, 0.0f}}};

  scene::SceneGpu gpu(*device, s);
  std::unique_ptr<techniques::Technique> forward = techniques::createTechnique("forward");
  techniques::RenderSettings settings;
  settings.colorFormat = rhi::Format::RGBA32F;
  forward->prepare(*device, settings);
  rhi::TextureHandle color = forward->render(*device, gpu, s.cameras[0]);
  device->submit();
  std::vector<uint8_t> bytes = device->readTexture(color);
  forward->release(*device);
  const uint32_t w = settings.width, h = settings.height;
  ASSERT_EQ(bytes.size(), size_t{w} * h * 16);

  const scene::Camera& cam = s.cameras[0];
  const glm::mat4 inverse = glm::inverse(cam.viewProjection(float(w) / float(h)));
  auto expected = [&](uint32_t px, uint32_t py, glm::vec3* hit) {
    // NDC y = -1 is row 0 (docs/ARCHITECTURE.md, conventions); depth 0..1.
    const glm::vec2 ndc{(px + 0.5f) / w * 2.0f - 1.0f, (py + 0.5f) / h * 2.0f - 1.0f};
    glm::vec4 a = inverse * glm::vec4(ndc, 0.0f, 1.0f), b = inverse * glm::vec4(ndc, 1.0f, 1.0f);
    glm::vec3 o = glm::vec3(a) / a.w, e = glm::vec3(b) / b.w;
    glm::vec3 P = o + (e - o) * (o.y / (o.y - e.y));
    *hit = P;
    const scene::Material& m = s.materials[0];
    glm::vec3 N = up, C = glm::normalize(cam.position - P);
    glm::vec3 c = m.diffuse * s.ambient;  // eq. 3.5
    for (const scene::Light& l : s.lights) {
      glm::vec3 toSurface = P - l.position;
      float d = glm::length(toSurface);
      if (d >= l.radius) continue;
      float x2 = (d / l.radius) * (d / l.radius), window = (1.0f - x2 * x2) * (1.0f - x2 * x2);
      float kd = l.attenuationK() * d;
      float A = window / (1.0f + kd * kd);  // eq. 3.11 with the window
      glm::vec3 L = toSurface / d;
      float F = l.type == scene::LightType::Spot
                    ? std::clamp((l.cosOuter - glm::dot(l.direction, L)) / (l.cosOuter - l.cosInner), 0.0f, 1.0f)
                    : 1.0f;  // eq. 3.12
      float D = std::clamp(glm::dot(N, -L), 0.0f, 1.0f);  // eq. 3.9
      glm::vec3 R = L - 2.0f * glm::dot(N, L) * N;
      float S = D > 0.0f ? std::pow(std::clamp(glm::dot(R, C), 0.0f, 1.0f), m.specularPower) : 0.0f;  // eq. 3.10
      c += (m.diffuse * D + m.specular * S) * l.color * (A * F);
    }
    return c;
  };
  // Pixels under the point light, in its falloff, under the spot's inner cone, in its penumbra,
  // in the specular highlight's neighbourhood and outside both lights.
  size_t lit = 0;
  for (uint32_t py = 10; py < h; py += 17)
    for (uint32_t px = 7; px < w; px += 23) {
      glm::vec3 P;
      glm::vec3 want = expected(px, py, &P);
      float got[4];
      std::memcpy(got, bytes.data() + (size_t{py} * w + px) * 16, 16);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(got[c], want[c], 2e-4 + 2e-4 * want[c]) << "pixel " << px << "," << py << " channel " << c << " at ("
                                                            << P.x << ", " << P.z << ")";
      lit += want.r > s.materials[0].diffuse.r * s.ambient.r + 0.01f;
    }
  EXPECT_GT(lit, 20u) << "the chosen pixels must include lit ones";
}

// Every light of the default scene lights pixels the camera sees, so that "a light went
// missing" always shows: removing any one of them changes forward's image (RGBA8, the goldens'
// format). scene::placeLights draws a light again when its volume reaches no visible surface
// facing it.
TEST_P(ForwardTechniques, RemovingAnyLightOfTheDefaultSceneChangesTheImage) {
  auto device = test::makeDevice(GetParam());
  if (!device) return;
  scene::Scene full;
  std::string error;
  ASSERT_TRUE(scene::makeScene("default", {}, &full, &error)) << error;
  ASSERT_EQ(full.lights.size(), 24u);
  std::unique_ptr<techniques::Technique> forward = techniques::createTechnique("forward");
  techniques::RenderSettings settings;
  forward->prepare(*device, settings);
  auto render = [&](const scene::Scene& s) {
    scene::SceneGpu gpu(*device, s);
    rhi::TextureHandle color = forward->render(*device, gpu, s.cameras[0]);
    device->submit();
    return device->readTexture(color);
  };
  const std::vector<uint8_t> all = render(full);
  for (size_t i = 0; i < full.lights.size(); ++i) {
    scene::Scene without = full;
    without.lights.erase(without.lights.begin() + static_cast<std::ptrdiff_t>(i));
    const std::vector<uint8_t> image = render(without);
    size_t changed = 0;
    for (size_t p = 0; p + 3 < all.size(); p += 4)
      changed += all[p] != image[p] || all[p + 1] != image[p + 1] || all[p + 2] != image[p + 2];
    EXPECT_GT(changed, 0u) << "light " << i << " lights no visible pixel";
  }
  forward->release(*device);
}

INSTANTIATE_TEST_SUITE_P(Backends, ForwardTechniques, ::testing::ValuesIn(test::allBackends()), test::BackendName());

}  // namespace
