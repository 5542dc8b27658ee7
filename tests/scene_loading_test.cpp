// Scenes from files (glTF 2.0 and OBJ + MTL): tiny files written here with hand-computed vertex
// counts and bounds, the errors for unusable files, and (when ../shared is present) the shared
// models. Also the light size classes of the thesis §4, measured at the default camera.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace fs = std::filesystem;
using namespace parity;

namespace {

class SceneLoading : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("parity-scene-loading-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& content) {
    fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << content;
    return p.string();
  }
  // A 2x2 RGBA8 PNG: red, green / blue, white (row 0 first).
  std::string writePng(const std::string& name) {
    fs::path p = dir_ / name;
    const uint8_t texels[16] = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255};
    auto out = OIIO::ImageOutput::create(p.string());
    EXPECT_TRUE(out);
    OIIO::ImageSpec spec(2, 2, 4, OIIO::TypeDesc::UINT8);
    EXPECT_TRUE(out->open(p.string(), spec));
    EXPECT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, texels));
    out->close();
    return p.string();
  }
  fs::path dir_;
};

// Binary data of the test glTF: a unit quad in the z = 0 plane (4 positions, 4 normals +z,
// 4 uvs) and 6 uint16 indices.
std::string quadBin() {
  const float positions[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  const float normals[12] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  const float uvs[8] = {0, 1, 1, 1, 1, 0, 0, 0};
  const uint16_t indices[6] = {0, 1, 2, 0, 2, 3};
  std::string bin;
  bin.append(reinterpret_cast<const char*>(positions), sizeof(positions));  // 0..48
  bin.append(reinterpret_cast<const char*>(normals), sizeof(normals));      // 48..96
  bin.append(reinterpret_cast<const char*>(uvs), sizeof(uvs));              // 96..128
  bin.append(reinterpret_cast<const char*>(indices), sizeof(indices));      // 128..140
  return bin;  // 140 bytes
}

// The quad under a parent node translated by (1, 2, 3) and a child node scaled by 2: world
// positions (1,2,3) (3,2,3) (3,4,3) (1,4,3). `bufferUri` empty: the GLB's own chunk.
std::string quadGltf(const std::string& bufferUri, const std::string& imageUri = "") {
  std::string buffer = bufferUri.empty() ? R"({"byteLength": 140})"
                                         : R"({"byteLength": 140, "uri": ")" + bufferUri + R"("})";
  std::string material = R"({"name": "tinted", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.25, 1.0, 1.0])";
  std::string textures;
  if (!imageUri.empty()) {
    material += R"(, "baseColorTexture": {"index": 0})";
    textures = R"(, "textures": [{"source": 0}], "images": [{"uri": ")" + imageUri + R"("}])";
  }
  material += "}}";
  return R"({
  "asset": {"version": "2.0"},
  "scene": 0,
  "scenes": [{"nodes": [0]}],
  "nodes": [{"translation": [1, 2, 3], "children": [1]}, {"scale": [2, 2, 2], "mesh": 0}],
  "meshes": [{"name": "quad", "primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                                               "indices": 3, "material": 0}]}],
  "materials": [)" + material + R"(],
  "buffers": [)" + buffer + R"(],
  "bufferViews": [
    {"buffer": 0, "byteOffset": 0, "byteLength": 48},
    {"buffer": 0, "byteOffset": 48, "byteLength": 48},
    {"buffer": 0, "byteOffset": 96, "byteLength": 32},
    {"buffer": 0, "byteOffset": 128, "byteLength": 12}],
  "accessors": [
    {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
    {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
    {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
    {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}])" + textures + "\n}\n";
}

std::string glb(const std::string& json, const std::string& bin) {
  std::string j = json;
  while (j.size() % 4) j += ' ';
  std::string b = bin;
  while (b.size() % 4) b += '\0';
  auto u32 = [](uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  std::string out = "glTF" + u32(2) + u32(static_cast<uint32_t>(12 + 8 + j.size() + 8 + b.size()));
  out += u32(static_cast<uint32_t>(j.size())) + "JSON" + j;
  out += u32(static_cast<uint32_t>(b.size())) + std::string("BIN\0", 4) + b;
  return out;
}

void expectVec(glm::vec3 got, glm::vec3 want) {
  EXPECT_NEAR(got.x, want.x, 1e-6f);
  EXPECT_NEAR(got.y, want.y, 1e-6f);
  EXPECT_NEAR(got.z, want.z, 1e-6f);
}

void expectQuadScene(const scene::Scene& s) {
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_EQ(s.vertices.size(), 4u);
  EXPECT_EQ(s.indices.size(), 6u);
  expectVec(s.meshes[0].boundsMin, {1, 2, 3});
  expectVec(s.meshes[0].boundsMax, {3, 4, 3});
  expectVec(s.vertices[2].position, {3, 4, 3});
  expectVec(s.vertices[0].normal, {0, 0, 1});  // scale 2 must not change the unit normal
  const scene::Material& m = s.materials.at(static_cast<size_t>(s.meshes[0].material));
  expectVec(m.diffuse, {0.5f, 0.25f, 1.0f});
  expectVec(m.specular, {0.2f, 0.2f, 0.2f});  // the default specular: glTF has none
  EXPECT_FALSE(s.cameras.empty());
  EXPECT_EQ(s.cameras[0].name, "default");
}

TEST_F(SceneLoading, GltfBakesNodeTransformsAndReadsMaterial) {
  write("quad.bin", quadBin());
  std::string path = write("quad.gltf", quadGltf("quad.bin"));
  scene::Scene s;
  std::string error;
  scene::SceneParams params;
  params.lightCount = 5;
  ASSERT_TRUE(scene::loadSceneFile(path, params, &s, &error)) << error;
  expectQuadScene(s);
  EXPECT_EQ(s.lights.size(), 5u);
  EXPECT_EQ(s.materials[static_cast<size_t>(s.meshes[0].material)].diffuseTexture, -1);
  // makeScene takes a path too.
  scene::Scene viaName;
  ASSERT_TRUE(scene::makeScene(path, params, &viaName, &error)) << error;
  EXPECT_EQ(viaName.vertices.size(), 4u);
}

TEST_F(SceneLoading, GlbIsTheSameScene) {
  std::string path = write("quad.glb", glb(quadGltf(""), quadBin()));
  scene::Scene s;
  std::string error;
  ASSERT_TRUE(scene::loadSceneFile(path, {}, &s, &error)) << error;
  expectQuadScene(s);
}

TEST_F(SceneLoading, GltfBaseColourTexture) {
  write("quad.bin", quadBin());
  writePng("colours.png");
  std::string path = write("quad.gltf", quadGltf("quad.bin", "colours.png"));
  scene::Scene s;
  std::string error;
  ASSERT_TRUE(scene::loadSceneFile(path, {}, &s, &error)) << error;
  int t = s.materials.at(static_cast<size_t>(s.meshes[0].material)).diffuseTexture;
  ASSERT_GE(t, 0);
  const scene::Texture& tex = s.textures[static_cast<size_t>(t)];
  ASSERT_EQ(tex.width, 2u);
  ASSERT_EQ(tex.height, 2u);
  const uint8_t want[16] = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255};
  EXPECT_EQ(std::memcmp(tex.rgba8.data(), want, 16), 0);
}

// Errors: one line naming the file and the reason; never a crash.
void expectError(const std::string& path, const std::string& reasonPart) {
  scene::Scene s;
  std::string error;
  EXPECT_FALSE(scene::loadSceneFile(path, {}, &s, &error));
  EXPECT_NE(error.find(path), std::string::npos) << error;
  EXPECT_NE(error.find(reasonPart), std::string::npos) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;
}

TEST_F(SceneLoading, MissingBuffer) {
  std::string path = write("quad.gltf", quadGltf("absent.bin"));
  expectError(path, "absent.bin");
}

TEST_F(SceneLoading, TruncatedBuffer) {
  write("quad.bin", quadBin().substr(0, 100));
  std::string path = write("quad.gltf", quadGltf("quad.bin"));
  scene::Scene s;
  std::string error;
  EXPECT_FALSE(scene::loadSceneFile(path, {}, &s, &error));
  EXPECT_NE(error.find(path), std::string::npos) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;
}

TEST_F(SceneLoading, TruncatedGlb) {
  std::string full = glb(quadGltf(""), quadBin());
  for (size_t keep : {size_t{0}, size_t{10}, size_t{40}, full.size() / 2, full.size() - 8}) {
    std::string path = write("cut" + std::to_string(keep) + ".glb", full.substr(0, keep));
    scene::Scene s;
    std::string error;
    EXPECT_FALSE(scene::loadSceneFile(path, {}, &s, &error)) << keep;
    EXPECT_NE(error.find(path), std::string::npos) << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  }
}

TEST_F(SceneLoading, MissingTexture) {
  write("quad.bin", quadBin());
  std::string path = write("quad.gltf", quadGltf("quad.bin", "absent.png"));
  expectError(path, "absent.png");
}

TEST_F(SceneLoading, GarbageAndUnknownFiles) {
  expectError(write("bad.gltf", "{ not json"), "");
  expectError(write("bad.txt", "hello"), "unknown scene file type");
  expectError((dir_ / "nothing.obj").string(), "not found");
  expectError(write("empty.obj", "# nothing\n"), "no triangles");
}

// OBJ: a quad written as two triangles with v/vt/vn (4 distinct corners: 4 vertices) using
// material "red", and a quad face with positions only (triangulated: 4 vertices, 6 indices,
// normals computed) using material "shiny" with a texture.
TEST_F(SceneLoading, ObjWithMtl) {
  writePng("colours.png");
  write("test.mtl",
        "newmtl red\nKd 0.9 0.1 0.1\nKs 0.5 0.5 0.5\nNs 40\n"
        "newmtl shiny\nKd 1 1 1\nKs 0.9 0.8 0.7\nNs 120\nmap_Kd colours.png\n");
  std::string path = write("test.obj",
                           "mtllib test.mtl\n"
                           "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 0 1 0\n"
                           "v 0 0 -1\nv 0 0 -3\nv 0 2 -3\nv 0 2 -1\n"
                           "vt 0 0\nvt 1 1\nvn 0 0 1\n"
                           "o first\nusemtl red\nf 1/1/1 2/2/1 3/1/1\nf 1/1/1 3/1/1 4/2/1\n"
                           "o second\nusemtl shiny\nf 5 6 7 8\n");
  scene::Scene s;
  std::string error;
  ASSERT_TRUE(scene::loadSceneFile(path, {}, &s, &error)) << error;
  ASSERT_EQ(s.meshes.size(), 2u);
  EXPECT_EQ(s.vertices.size(), 8u);
  EXPECT_EQ(s.indices.size(), 12u);
  expectVec(s.meshes[0].boundsMin, {0, 0, 0});
  expectVec(s.meshes[0].boundsMax, {2, 1, 0});
  expectVec(s.meshes[1].boundsMin, {0, 0, -3});
  expectVec(s.meshes[1].boundsMax, {0, 2, -1});
  const scene::Material& red = s.materials.at(static_cast<size_t>(s.meshes[0].material));
  expectVec(red.diffuse, {0.9f, 0.1f, 0.1f});
  expectVec(red.specular, {0.5f, 0.5f, 0.5f});
  EXPECT_FLOAT_EQ(red.specularPower, 40.0f);
  EXPECT_EQ(red.diffuseTexture, -1);
  const scene::Material& shiny = s.materials.at(static_cast<size_t>(s.meshes[1].material));
  EXPECT_FLOAT_EQ(shiny.specularPower, 120.0f);
  ASSERT_GE(shiny.diffuseTexture, 0);
  EXPECT_EQ(s.textures[static_cast<size_t>(shiny.diffuseTexture)].width, 2u);
  // OBJ's vt v = 0 is the image's bottom row: flipped to this project's v = 0 = row 0.
  EXPECT_FLOAT_EQ(s.vertices[0].uv.y, 1.0f);
  // Computed normal of the x = 0 quad: (v6 - v5) x (v7 - v5) = (0,0,-2) x (0,2,-2) = (4,0,0).
  expectVec(s.vertices[4].normal, {1, 0, 0});
}

TEST_F(SceneLoading, ObjErrors) {
  write("tex.mtl", "newmtl m\nKd 1 1 1\nmap_Kd absent.png\n");
  expectError(write("tex.obj", "mtllib tex.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n"), "absent.png");
  scene::Scene s;
  std::string error;
  EXPECT_FALSE(scene::loadSceneFile(write("range.obj", "v 0 0 0\nv 1 0 0\nf 1 2 7\n"), {}, &s, &error));
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;
}

// The shared models, when ../shared is present: triangle counts from their README.
TEST(SceneAssets, SharedModelsLoad) {
  if (!fs::is_directory(scene::sharedAssetsDirectory() + "/models"))
    GTEST_SKIP() << "shared assets not present at " << scene::sharedAssetsDirectory() << " (they are optional)";
  struct Expect {
    const char* name;
    size_t triangles;
    bool textured;
  };
  for (const Expect& e : {Expect{"gltf-box", 12, false}, Expect{"gltf-box-textured", 12, true},
                          Expect{"gltf-duck", 4212, true}, Expect{"gltf-avocado", 682, true},
                          Expect{"gltf-water-bottle", 4510, true}, Expect{"bunny", 69451, false},
                          Expect{"dragon", 100000, false}, Expect{"sponza", 66454, false}}) {
    if (!fs::is_regular_file(scene::assetScenePath(e.name))) {
      ADD_FAILURE() << e.name << ": " << scene::assetScenePath(e.name) << " missing from the shared assets";
      continue;
    }
    scene::Scene s;
    std::string error;
    ASSERT_TRUE(scene::makeScene(e.name, {}, &s, &error)) << error;
    EXPECT_EQ(s.indices.size() / 3, e.triangles) << e.name;
    EXPECT_EQ(s.name, e.name);
    EXPECT_EQ(s.lights.size(), scene::SceneParams{}.lightCount) << e.name;
    bool anyTexture = false;
    for (const scene::Mesh& m : s.meshes) anyTexture |= s.materials[static_cast<size_t>(m.material)].diffuseTexture >= 0;
    EXPECT_EQ(anyTexture, e.textured) << e.name;
  }
  std::vector<std::string> names = scene::sceneNames();
  EXPECT_NE(std::find(names.begin(), names.end(), "sponza"), names.end());
}

// Thesis §4: small lights cover 0.25-5% of the screen, big ones 20-100%, measured here on a
// finer grid (640x360) than the one placement uses, at the default camera and the default
// image aspect. Some of the lights are spots.
TEST(LightSizes, CoverageMatchesTheThesisClasses) {
  for (scene::LightSize size : {scene::LightSize::Small, scene::LightSize::Big}) {
    for (uint32_t seed : {1u, 2u, 7u}) {
      scene::SceneParams params;
      params.lightSize = size;
      params.seed = seed;
      params.lightCount = 24;
      scene::Scene s = scene::makeDefaultScene(params);
      ASSERT_EQ(s.lights.size(), 24u);
      scene::CoverageRange range = scene::coverageRange(size);
      size_t spots = 0;
      for (const scene::Light& l : s.lights) {
        float c = scene::sphereScreenCoverage(s.cameras[0], scene::kLightSizeAspect, l.position, l.radius, 640, 360);
        EXPECT_GE(c, range.lo) << "seed " << seed << " radius " << l.radius;
        EXPECT_LE(c, range.hi) << "seed " << seed << " radius " << l.radius;
        if (l.type == scene::LightType::Spot) {
          ++spots;
          EXPECT_LT(l.cosOuter, l.cosInner);
          EXPECT_NEAR(glm::length(l.direction), 1.0f, 1e-5f);
        }
      }
      EXPECT_EQ(spots, 8u);
    }
  }
  // The classes differ by more than an order of magnitude in radius at the same position.
  scene::SceneParams small, big;
  big.lightSize = scene::LightSize::Big;
  float rs = scene::makeDefaultScene(small).lights[0].radius, rb = scene::makeDefaultScene(big).lights[0].radius;
  EXPECT_GT(rb, 2.0f * rs);
}

// Sponza is an interior: from around its bounds only the outer walls show, so its default
// camera is the one inside (the bounds view stays as "outside"); a model one looks at from
// outside (the bunny) keeps the bounds view as its default.
TEST(SceneAssets, AnEnclosedModelsDefaultCameraIsInside) {
  if (!fs::is_directory(scene::sharedAssetsDirectory() + "/models"))
    GTEST_SKIP() << "shared assets not present at " << scene::sharedAssetsDirectory() << " (they are optional)";
  auto camera = [](const scene::Scene& s, const std::string& name) {
    for (const scene::Camera& c : s.cameras)
      if (c.name == name) return c;
    ADD_FAILURE() << s.name << " has no camera " << name;
    return scene::Camera{};
  };
  std::string error;
  scene::Scene sponza, bunny;
  ASSERT_TRUE(scene::makeScene("sponza", {}, &sponza, &error)) << error;
  ASSERT_TRUE(scene::makeScene("bunny", {}, &bunny, &error)) << error;
  EXPECT_GE(scene::enclosure(sponza, camera(sponza, "inside").position), 0.9f);
  EXPECT_EQ(sponza.cameras.front().name, "default");
  EXPECT_EQ(camera(sponza, "default").position, camera(sponza, "inside").position);
  EXPECT_NE(camera(sponza, "default").position, camera(sponza, "outside").position);
  EXPECT_LT(scene::enclosure(bunny, camera(bunny, "inside").position), 0.9f);
  EXPECT_EQ(camera(bunny, "default").position, camera(bunny, "outside").position);
  std::vector<std::string> names;
  for (const scene::Camera& c : sponza.cameras) names.push_back(c.name);
  EXPECT_EQ(names, scene::cameraNames("sponza")) << "parity list names the cameras a file scene has";
}

TEST(LightSizes, CoverageOfKnownSpheres) {
  scene::Camera cam;
  cam.position = {0, 0, 0};
  cam.target = {0, 0, -1};
  cam.fovYDegrees = 90.0f;
  // Camera inside: everything.
  EXPECT_FLOAT_EQ(scene::sphereScreenCoverage(cam, 1.0f, {0, 0, -0.5f}, 1.0f), 1.0f);
  // Behind the camera: nothing.
  EXPECT_FLOAT_EQ(scene::sphereScreenCoverage(cam, 1.0f, {0, 0, 5}, 1.0f), 0.0f);
  // A sphere of radius r at distance d subtends a cone of half-angle asin(r/d); with a 90 degree
  // square view at distance 10 and r = 1, the disc's projected radius is tan(asin(0.1)) = 0.1005
  // of the half-width: area pi * 0.1005^2 / 4 = 0.7935% of the image.
  float c = scene::sphereScreenCoverage(cam, 1.0f, {0, 0, -10}, 1.0f, 1024, 1024);
  EXPECT_NEAR(c, 0.007935f, 0.0002f);
}

}  // namespace

// makeScene builds the default scene once per process and parameters: asked again, with the
// same parameters or after others, it gives what makeDefaultScene gives for those parameters.
TEST(DefaultScene, BuiltOncePerParametersAndTheSameAsMadeAnew) {
  auto lightsOf = [](const scene::Scene& s) {
    std::vector<float> v;
    for (const scene::Light& l : s.lights) v.insert(v.end(), {l.position.x, l.position.y, l.position.z, l.radius, l.color.r});
    return v;
  };
  std::vector<scene::SceneParams> params(4);
  params[1].seed = 2;
  params[2].lightCount = 5;
  params[3].lightSize = scene::LightSize::Big;
  for (int round = 0; round < 2; ++round)
    for (const scene::SceneParams& p : params) {
      SCOPED_TRACE("round " + std::to_string(round) + ", seed " + std::to_string(p.seed) + ", lights " + std::to_string(p.lightCount));
      scene::Scene made;
      std::string error;
      ASSERT_TRUE(scene::makeScene("default", p, &made, &error)) << error;
      EXPECT_EQ(made.lights.size(), p.lightCount);
      EXPECT_EQ(lightsOf(made), lightsOf(scene::makeDefaultScene(p)));
    }
}
