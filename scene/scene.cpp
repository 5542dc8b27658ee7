#include "scene/scene.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace parity::scene {

namespace {

// PCG32 (O'Neill): the same sequence on every platform and standard library, unlike the
// std:: distributions.
class Random {
 public:
  explicit Random(uint64_t seed) : state_(seed * 6364136223846793005ull + 1442695040888963407ull) { next(); }
  uint32_t next() {
    uint64_t old = state_;
    state_ = old * 6364136223846793005ull + 1442695040888963407ull;
    uint32_t xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = static_cast<uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32 - rot) & 31));
  }
  float uniform(float lo, float hi) { return lo + (hi - lo) * static_cast<float>(next() >> 8) * (1.0f / 16777216.0f); }

 private:
  uint64_t state_;
};

glm::vec3 hueToRgb(float h) {
  float r = std::fabs(h * 6.0f - 3.0f) - 1.0f;
  float g = 2.0f - std::fabs(h * 6.0f - 2.0f);
  float b = 2.0f - std::fabs(h * 6.0f - 4.0f);
  return glm::clamp(glm::vec3(r, g, b), 0.0f, 1.0f);
}

class Builder {
 public:
  explicit Builder(Scene& s) : s_(s) {}

  // A rectangle centred at c spanning ±u, ±v; it faces n = u × v (counter-clockwise seen from n).
  void quad(glm::vec3 c, glm::vec3 u, glm::vec3 v, glm::vec2 uvScale = {1, 1}) {
    glm::vec3 n = glm::normalize(glm::cross(u, v));
    uint32_t base = static_cast<uint32_t>(s_.vertices.size());
    s_.vertices.push_back({c - u - v, n, {0, 0}});
    s_.vertices.push_back({c + u - v, n, {uvScale.x, 0}});
    s_.vertices.push_back({c + u + v, n, {uvScale.x, uvScale.y}});
    s_.vertices.push_back({c - u + v, n, {0, uvScale.y}});
    for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) s_.indices.push_back(base + i);
  }

  void box(glm::vec3 c, glm::vec3 h) {
    glm::vec3 X{h.x, 0, 0}, Y{0, h.y, 0}, Z{0, 0, h.z};
    quad(c + Z, X, Y);    // +z
    quad(c - Z, -X, Y);   // -z
    quad(c + X, -Z, Y);   // +x
    quad(c - X, Z, Y);    // -x
    quad(c + Y, X, -Z);   // +y
    quad(c - Y, X, Z);    // -y
  }

  void sphere(glm::vec3 c, float r, int slices = 32, int stacks = 16) {
    uint32_t base = static_cast<uint32_t>(s_.vertices.size());
    const float pi = 3.14159265358979f;
    for (int i = 0; i <= stacks; ++i) {
      float phi = pi * static_cast<float>(i) / stacks;  // 0 at the top
      for (int j = 0; j <= slices; ++j) {
        float theta = 2.0f * pi * static_cast<float>(j) / slices;
        glm::vec3 n{std::sin(phi) * std::cos(theta), std::cos(phi), -std::sin(phi) * std::sin(theta)};
        s_.vertices.push_back({c + r * n, n, {static_cast<float>(j) / slices, static_cast<float>(i) / stacks}});
      }
    }
    for (int i = 0; i < stacks; ++i) {
      for (int j = 0; j < slices; ++j) {
        uint32_t a = base + i * (slices + 1) + j, b = a + slices + 1;
        // a: (i, j), b: (i+1, j); counter-clockwise seen from outside.
        for (uint32_t k : {a, b, b + 1, a, b + 1, a + 1}) s_.indices.push_back(k);
      }
    }
  }

  // Starts a mesh: everything emitted until the next begin() belongs to it.
  void begin(const std::string& name, int material) {
    finish();
    open_ = Mesh{name, static_cast<uint32_t>(s_.indices.size()), 0, material};
    openVertex_ = static_cast<uint32_t>(s_.vertices.size());
    hasOpen_ = true;
  }
  void finish() {
    if (!hasOpen_) return;
    open_.indexCount = static_cast<uint32_t>(s_.indices.size()) - open_.firstIndex;
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (size_t i = openVertex_; i < s_.vertices.size(); ++i) {
      lo = glm::min(lo, s_.vertices[i].position);
      hi = glm::max(hi, s_.vertices[i].position);
    }
    open_.boundsMin = lo;
    open_.boundsMax = hi;
    s_.meshes.push_back(open_);
    hasOpen_ = false;
  }

 private:
  Scene& s_;
  Mesh open_;
  uint32_t openVertex_ = 0;
  bool hasOpen_ = false;
};

Texture checkerTexture() {
  Texture t{"checker", 64, 64, {}};
  t.rgba8.resize(64 * 64 * 4);
  for (uint32_t y = 0; y < 64; ++y)
    for (uint32_t x = 0; x < 64; ++x) {
      bool light = ((x / 8) + (y / 8)) % 2 == 0;
      uint8_t v = light ? 230 : 150;
      uint8_t* p = &t.rgba8[(y * 64 + x) * 4];
      p[0] = v;
      p[1] = v;
      p[2] = static_cast<uint8_t>(v - 10);
      p[3] = 255;
    }
  return t;
}

}  // namespace

glm::mat4 Camera::viewProjection(float aspect) const {
  glm::mat4 proj = glm::perspectiveRH_ZO(glm::radians(fovYDegrees), aspect, nearPlane, farPlane);
  proj[1][1] = -proj[1][1];  // up -> NDC y = -1 -> memory row 0 (rhi.h conventions)
  return proj * glm::lookAtRH(position, target, up);
}

const Camera* Scene::camera(const std::string& cameraName) const {
  for (const Camera& c : cameras)
    if (c.name == cameraName) return &c;
  return nullptr;
}

Scene makeDefaultScene(const SceneParams& params) {
  Scene s;
  s.name = "default";
  s.textures.push_back(checkerTexture());
  s.materials = {
      {"floor", {0.8f, 0.8f, 0.8f}, {0.3f, 0.3f, 0.3f}, 24.0f, 0},
      {"wall", {0.7f, 0.68f, 0.62f}, {0.05f, 0.05f, 0.05f}, 8.0f, -1},
      {"red plastic", {0.8f, 0.15f, 0.12f}, {0.6f, 0.6f, 0.6f}, 64.0f, -1},
      {"green matte", {0.2f, 0.65f, 0.25f}, {0.02f, 0.02f, 0.02f}, 4.0f, -1},
      {"blue metal", {0.15f, 0.25f, 0.7f}, {0.8f, 0.85f, 0.9f}, 128.0f, -1},
      {"gold", {0.75f, 0.6f, 0.2f}, {0.9f, 0.8f, 0.4f}, 48.0f, -1},
  };
  Builder b(s);
  const glm::vec3 X{1, 0, 0}, Y{0, 1, 0}, Z{0, 0, 1};
  b.begin("floor", 0);
  b.quad({0, 0, 0}, 10.0f * X, -10.0f * Z, {5, 5});
  b.begin("back wall", 1);
  b.quad({0, 4, -10}, 10.0f * X, 4.0f * Y);
  b.begin("left wall", 1);
  b.quad({-10, 4, 0}, -10.0f * Z, 4.0f * Y);
  b.begin("right wall", 1);
  b.quad({10, 4, 0}, 10.0f * Z, 4.0f * Y);
  b.begin("box tall", 2);
  b.box({-4.0f, 2.0f, -4.0f}, {1.0f, 2.0f, 1.0f});
  b.begin("box wide", 3);
  b.box({3.5f, 0.75f, -2.5f}, {2.0f, 0.75f, 1.2f});
  b.begin("box small", 5);
  b.box({-1.0f, 0.5f, 2.5f}, {0.5f, 0.5f, 0.5f});
  b.begin("sphere blue", 4);
  b.sphere({0.5f, 1.5f, -1.0f}, 1.5f);
  b.begin("sphere red", 2);
  b.sphere({-5.5f, 1.0f, 3.0f}, 1.0f);
  b.begin("sphere gold", 5);
  b.sphere({5.0f, 2.3f, -2.5f}, 0.8f);
  b.begin("sphere green", 3);
  b.sphere({3.0f, 0.6f, 3.5f}, 0.6f, 24, 12);
  b.finish();

  Random rng(params.seed);
  for (uint32_t i = 0; i < params.lightCount; ++i) {
    Light l;
    l.position = {rng.uniform(-9.0f, 9.0f), rng.uniform(0.2f, 2.0f), rng.uniform(-9.0f, 9.0f)};
    l.color = hueToRgb(rng.uniform(0.0f, 1.0f)) * rng.uniform(0.8f, 1.5f);
    l.radius = params.lightSize == LightSize::Small ? rng.uniform(2.0f, 4.0f) : rng.uniform(8.0f, 16.0f);
    s.lights.push_back(l);
  }

  s.cameras = {
      {"default", {0.0f, 5.0f, 13.0f}, {0.0f, 1.0f, -1.0f}},
      {"high", {6.0f, 12.0f, 9.0f}, {0.0f, 0.0f, -2.0f}},
      {"grazing", {-9.0f, 0.15f, 9.5f}, {4.0f, 0.05f, -6.0f}},
      {"side", {9.5f, 3.0f, 6.0f}, {-2.0f, 1.0f, -3.0f}},
      {"close", {1.0f, 2.0f, 3.5f}, {0.5f, 1.5f, -1.0f}},
  };
  return s;
}

std::vector<std::string> sceneNames() { return {"default"}; }

bool makeScene(const std::string& name, const SceneParams& params, Scene* out, std::string* error) {
  if (name == "default") {
    *out = makeDefaultScene(params);
    return true;
  }
  *error = "unknown scene '" + name + "' (known: default)";
  return false;
}

}  // namespace parity::scene
