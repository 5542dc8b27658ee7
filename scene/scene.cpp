#include "scene/scene.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <mutex>
#include <tuple>
#include <vector>

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

CoverageRange coverageRange(LightSize size) {
  return size == LightSize::Small ? CoverageRange{0.0025f, 0.05f} : CoverageRange{0.20f, 1.0f};
}

namespace {

// Unit directions through the pixel centres of a grid, as Camera::viewProjection projects them
// (row 0 at the top).
struct RayGrid {
  glm::vec3 origin;
  std::vector<glm::vec3> dirs;
  RayGrid(const Camera& camera, float aspect, uint32_t w, uint32_t h) : origin(camera.position) {
    glm::vec3 f = glm::normalize(camera.target - camera.position);
    glm::vec3 r = glm::normalize(glm::cross(f, camera.up));
    glm::vec3 u = glm::cross(r, f);
    float t = std::tan(glm::radians(camera.fovYDegrees) * 0.5f);
    dirs.reserve(static_cast<size_t>(w) * h);
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x) {
        float nx = 2.0f * (static_cast<float>(x) + 0.5f) / static_cast<float>(w) - 1.0f;
        float ny = 1.0f - 2.0f * (static_cast<float>(y) + 0.5f) / static_cast<float>(h);
        dirs.push_back(glm::normalize(f + r * (nx * t * aspect) + u * (ny * t)));
      }
  }
  float coverage(glm::vec3 center, float radius) const {
    glm::vec3 oc = center - origin;
    float oc2 = glm::dot(oc, oc), r2 = radius * radius;
    if (oc2 <= r2) return 1.0f;
    size_t hits = 0;
    for (const glm::vec3& d : dirs) {
      float b = glm::dot(oc, d);
      if (b > 0.0f && oc2 - b * b < r2) ++hits;
    }
    return static_cast<float>(hits) / static_cast<float>(dirs.size());
  }
  // "coverage(center, radius) >= target" for many radii at one centre, with the same answers in
  // one pass over the grid instead of one per radius: the fraction reaches the target exactly when
  // at least `needed` rays hit, i.e. when the needed-th smallest of the rays' squared distances
  // from the centre (as coverage() computes them) is below radius².
  struct Reach {
    float oc2 = 0.0f, target = 0.0f, neededMiss2 = 0.0f;
    bool reachable = true;  // false: fewer rays point at the centre than the target needs
    bool atRadius(float radius) const {
      float r2 = radius * radius;
      if (oc2 <= r2) return 1.0f >= target;
      return reachable && neededMiss2 < r2;
    }
  };
  Reach reach(glm::vec3 center, float target) const {
    Reach r;
    glm::vec3 oc = center - origin;
    r.oc2 = glm::dot(oc, oc);
    r.target = target;
    std::vector<float> miss2;
    miss2.reserve(dirs.size());
    for (const glm::vec3& d : dirs) {
      float b = glm::dot(oc, d);
      if (b > 0.0f) miss2.push_back(r.oc2 - b * b);
    }
    // The fewest hits whose fraction (computed as coverage() computes it) reaches the target.
    const float n = static_cast<float>(dirs.size());
    size_t needed = static_cast<size_t>(std::max(0.0f, target * n - 2.0f));
    while (needed <= dirs.size() && static_cast<float>(needed) / n < target) ++needed;
    if (needed == 0) {
      r.neededMiss2 = -std::numeric_limits<float>::infinity();
    } else if (needed > miss2.size()) {
      r.reachable = false;
    } else {
      std::nth_element(miss2.begin(), miss2.begin() + static_cast<std::ptrdiff_t>(needed - 1), miss2.end());
      r.neededMiss2 = miss2[needed - 1];
    }
    return r;
  }
};

}  // namespace

RayCaster::RayCaster(const Scene& s) {
  for (const Mesh& mesh : s.meshes) {
    meshes_.push_back({mesh.boundsMin, mesh.boundsMax, triangles_.size(), 0});
    for (size_t i = mesh.firstIndex; i + 2 < size_t(mesh.firstIndex) + mesh.indexCount; i += 3) {
      const glm::vec3 a = s.vertices[s.indices[i]].position;
      triangles_.push_back({a, s.vertices[s.indices[i + 1]].position - a, s.vertices[s.indices[i + 2]].position - a});
    }
    meshes_.back().end = triangles_.size();
  }
}

float RayCaster::firstHit(glm::vec3 origin, glm::vec3 d, glm::vec3* normalOut) const {
  float best = std::numeric_limits<float>::infinity();
  glm::vec3 normal{0.0f};
  for (const MeshRange& mesh : meshes_) {
    // Slab test against the mesh's bounds first: most rays miss most meshes.
    float t0 = 0.0f, t1 = best;
    for (int a = 0; a < 3 && t0 <= t1; ++a) {
      const float inv = 1.0f / d[a];
      float n = (mesh.lo[a] - origin[a]) * inv, f = (mesh.hi[a] - origin[a]) * inv;
      if (n > f) std::swap(n, f);
      t0 = std::max(t0, n);
      t1 = std::min(t1, f);
    }
    if (t0 > t1) continue;
    for (size_t i = mesh.begin; i < mesh.end; ++i) {  // Möller-Trumbore
      const Triangle& tri = triangles_[i];
      const glm::vec3 p = glm::cross(d, tri.e2);
      const float det = glm::dot(tri.e1, p);
      if (std::fabs(det) < 1e-12f) continue;
      const glm::vec3 t = origin - tri.a;
      const float u = glm::dot(t, p) / det;
      if (u < 0.0f || u > 1.0f) continue;
      const glm::vec3 q = glm::cross(t, tri.e1);
      const float v = glm::dot(d, q) / det;
      if (v < 0.0f || u + v > 1.0f) continue;
      const float dist = glm::dot(tri.e2, q) / det;
      if (dist > 1e-4f && dist < best) {
        best = dist;
        normal = glm::normalize(glm::cross(tri.e1, tri.e2));
      }
    }
  }
  if (normalOut) *normalOut = glm::dot(normal, d) > 0.0f ? -normal : normal;  // the side facing the ray
  return best;
}

float enclosure(const Scene& s, glm::vec3 point) {
  const RayCaster caster(s);
  // 48 directions: 16 around the horizon at each of three elevations (-30, 0, +30 degrees).
  size_t hits = 0, rays = 0;
  for (int e = -1; e <= 1; ++e)
    for (int k = 0; k < 16; ++k, ++rays) {
      const float az = float(k) * 6.28318531f / 16.0f, el = float(e) * 0.523598776f;
      const glm::vec3 d{std::cos(el) * std::cos(az), std::sin(el), std::cos(el) * std::sin(az)};
      hits += std::isfinite(caster.firstHit(point, d, nullptr));
    }
  return float(hits) / float(rays);
}

float sphereScreenCoverage(const Camera& camera, float aspect, glm::vec3 center, float radius, uint32_t gridWidth,
                           uint32_t gridHeight) {
  return RayGrid(camera, aspect, gridWidth, gridHeight).coverage(center, radius);
}

namespace {

// The surface points the camera sees through a grid of pixel centres (first hit of each ray
// against the scene's triangles), with the side of the surface facing the camera.
struct VisibleSurface {
  std::vector<glm::vec3> points, normals;
  VisibleSurface(const Scene& s, const RayGrid& grid) {
    const RayCaster caster(s);
    for (const glm::vec3& d : grid.dirs) {
      glm::vec3 normal;
      const float t = caster.firstHit(grid.origin, d, &normal);
      if (!std::isfinite(t)) continue;
      points.push_back(grid.origin + d * t);
      normals.push_back(normal);
    }
  }
  // Visible points the light reaches (inside its radius and cone, on a surface facing it).
  size_t litBy(const Light& l) const {
    size_t lit = 0;
    for (size_t i = 0; i < points.size(); ++i) {
      const glm::vec3 toLight = l.position - points[i];
      const float d = glm::length(toLight);
      if (d >= l.radius || d <= 0.0f) continue;
      const glm::vec3 L = toLight / d;
      if (glm::dot(normals[i], L) <= 0.05f) continue;
      if (l.type == LightType::Spot && glm::dot(l.direction, -L) <= l.cosOuter) continue;
      ++lit;
    }
    return lit;
  }
};

}  // namespace

void placeLights(Scene& s, const SceneParams& params, const Camera& camera, glm::vec3 lo, glm::vec3 hi) {
  Random rng(params.seed);
  const RayGrid grid(camera, kLightSizeAspect, 256, 144);
  const glm::mat4 viewProj = camera.viewProjection(kLightSizeAspect);
  // Targets keep a margin inside the class's range, so that a measurement on another grid
  // (tests/scene_loading_test.cpp measures at 640x360) stays inside it.
  const CoverageRange range = coverageRange(params.lightSize);
  const float targetLo = range.lo * 1.4f, targetHi = range.hi * 0.9f;
  const float extent = std::max(glm::length(hi - lo), 1e-3f);
  const float pi = 3.14159265358979f;
  // A light must light what the camera sees (removing it must change the image): one whose
  // volume reaches no visible surface facing it (behind a box, say) is drawn again.
  // 96x54 rays, fewer for big meshes (a scanned model has 10^5 triangles and no useful bounds).
  const uint32_t rays = uint32_t(std::clamp<size_t>(size_t(2e7) / std::max<size_t>(s.indices.size() / 3, 1), 576, 5184));
  const uint32_t gridW = std::max(32u, uint32_t(std::sqrt(rays * 16.0 / 9.0)));
  const VisibleSurface visible(s, RayGrid(camera, kLightSizeAspect, gridW, gridW * 9 / 16));
  const size_t mustLight = std::max<size_t>(1, visible.points.size() / 500);
  for (uint32_t i = 0; i < params.lightCount; ++i) {
    Light l;
    for (int draw = 0; draw < 16; ++draw) {
      l = Light{};
      // A position the camera sees (within 90% of the image), or the last candidate.
      for (int attempt = 0; attempt < 64; ++attempt) {
        l.position = {rng.uniform(lo.x, hi.x), rng.uniform(lo.y, hi.y), rng.uniform(lo.z, hi.z)};
        glm::vec4 clip = viewProj * glm::vec4(l.position, 1.0f);
        if (clip.w > 0.0f && std::fabs(clip.x) < 0.9f * clip.w && std::fabs(clip.y) < 0.9f * clip.w) break;
      }
      // One draw per statement: the operands of `*` are unsequenced, and GCC and clang drew these
      // two in opposite orders, so the default scene depended on the compiler (the sanitizer build,
      // clang, rendered other light colours). GCC's order is kept: the goldens were made with it.
      const float intensity = rng.uniform(1.0f, 2.0f);
      const float hue = rng.uniform(0.0f, 1.0f);
      l.color = hueToRgb(hue) * intensity;
      // Every third light is a spot aimed at a point below it, cone half-angles 25-45 degrees.
      glm::vec3 aim{l.position.x + rng.uniform(-0.15f, 0.15f) * extent, lo.y,
                    l.position.z + rng.uniform(-0.15f, 0.15f) * extent};
      float outer = rng.uniform(25.0f, 45.0f) * pi / 180.0f;
      if (i % 3 == 2) {
        l.type = LightType::Spot;
        glm::vec3 d = aim - l.position;
        l.direction = glm::dot(d, d) > 1e-8f ? glm::normalize(d) : glm::vec3(0.0f, -1.0f, 0.0f);
        l.cosOuter = std::cos(outer);
        l.cosInner = std::cos(outer * 0.7f);
      }
      // Radius: the smallest whose volume covers the drawn fraction of the image (coverage grows
      // with the radius), by doubling then bisection.
      const RayGrid::Reach reach = grid.reach(l.position, rng.uniform(targetLo, targetHi));
      float rLo = 0.0f, rHi = extent * 0.01f;
      while (!reach.atRadius(rHi) && rHi < extent * 1000.0f) rHi *= 2.0f;
      for (int it = 0; it < 32; ++it) {
        float mid = 0.5f * (rLo + rHi);
        if (reach.atRadius(mid)) rHi = mid;
        else rLo = mid;
      }
      l.radius = rHi;
      if (visible.points.empty() || visible.litBy(l) >= mustLight) break;
    }
    s.lights.push_back(l);
  }
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
      // Translucent panes (opacity < 1): what the transparency techniques (abuffer, depth
      // peeling, lidr-msaa, inferred's stippled layers) sort, peel and blend. Opaque techniques
      // shade them as opaque surfaces.
      {"glass cyan", {0.2f, 0.7f, 0.8f}, {0.5f, 0.5f, 0.5f}, 64.0f, -1, 0.5f},
      {"glass amber", {0.9f, 0.6f, 0.1f}, {0.5f, 0.5f, 0.5f}, 64.0f, -1, 0.4f},
      {"glass violet", {0.6f, 0.3f, 0.8f}, {0.5f, 0.5f, 0.5f}, 64.0f, -1, 0.6f},
      {"glass white", {0.9f, 0.9f, 0.9f}, {0.8f, 0.8f, 0.8f}, 96.0f, -1, 0.3f},
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
  // Four panes facing the default camera, centred on one of its rays at increasing distances, so
  // that the middle of the patch they cover holds all four: up to four translucent layers.
  b.begin("pane cyan", 6);
  b.quad({-5.1f, 1.43f, 5.35f}, 0.7f * X, 0.6f * Y);
  b.begin("pane amber", 7);
  b.quad({-5.4f, 1.22f, 4.9f}, 0.7f * X, 0.6f * Y);
  b.begin("pane violet", 8);
  b.quad({-5.7f, 1.01f, 4.45f}, 0.7f * X, 0.6f * Y);
  b.begin("pane white", 9);
  b.quad({-6.0f, 0.8f, 4.0f}, 0.7f * X, 0.6f * Y);
  b.finish();

  s.cameras = {
      {"default", {0.0f, 5.0f, 13.0f}, {0.0f, 1.0f, -1.0f}},
      {"high", {6.0f, 12.0f, 9.0f}, {0.0f, 0.0f, -2.0f}},
      {"grazing", {-9.0f, 0.15f, 9.5f}, {4.0f, 0.05f, -6.0f}},
      {"side", {9.5f, 3.0f, 6.0f}, {-2.0f, 1.0f, -3.0f}},
      {"close", {1.0f, 2.0f, 3.5f}, {0.5f, 1.5f, -1.0f}},
  };
  // Lights no higher than 1 above the floor, so that most reach it (their radii, solved for the
  // screen coverage of their class, are about 1 for small lights).
  placeLights(s, params, s.cameras[0], {-9.0f, 0.2f, -9.0f}, {9.0f, 1.0f, 9.0f});
  // The first point light and the first spot cast shadows: the shadow techniques render their
  // maps.
  for (size_t i = 0; i < s.lights.size(); ++i)
    s.lights[i].castsShadows = i == 0 || (i == 2 && s.lights[i].type == LightType::Spot);
  return s;
}

const std::vector<AssetScene>& assetScenes() {
  static const std::vector<AssetScene> scenes = {
      {"sponza", "models/dabrovic-sponza.obj"},
      {"dragon", "models/stanford-dragon-100k.obj"},
      {"bunny", "models/stanford-bunny.obj"},
      {"gltf-box", "models/gltf-Box/glTF/Box.gltf"},
      {"gltf-box-textured", "models/gltf-BoxTextured/glTF/BoxTextured.gltf"},
      {"gltf-duck", "models/gltf-Duck/glTF/Duck.gltf"},
      {"gltf-avocado", "models/gltf-Avocado/glTF/Avocado.gltf"},
      {"gltf-water-bottle", "models/gltf-WaterBottle/glTF/WaterBottle.gltf"},
      {"gltf-normal-tangent-test", "models/gltf-NormalTangentTest/glTF/NormalTangentTest.gltf"},
      {"gltf-metal-rough-spheres", "models/gltf-MetalRoughSpheresNoTextures/glTF/MetalRoughSpheresNoTextures.gltf"},
  };
  return scenes;
}

std::string sharedAssetsDirectory() { return PARITY_SOURCE_DIR "/../shared/assets"; }

std::string assetScenePath(const std::string& name) {
  for (const AssetScene& a : assetScenes())
    if (a.name == name) return sharedAssetsDirectory() + "/" + a.relativePath;
  return "";
}

std::vector<std::string> cameraNames(const std::string& sceneName) {
  std::vector<std::string> names;
  if (sceneName == "default") {
    for (const Camera& c : makeDefaultScene(SceneParams{0, LightSize::Small, 1}).cameras) names.push_back(c.name);
    return names;
  }
  return {"default", "outside", "high", "side", "close", "inside"};  // camerasFor() in scene_loader.cpp
}

std::vector<std::string> sceneNames() {
  std::vector<std::string> names = {"default"};
  for (const AssetScene& a : assetScenes())
    if (std::filesystem::is_regular_file(assetScenePath(a.name))) names.push_back(a.name);
  return names;
}

namespace {
bool looksLikePath(const std::string& name) {
  auto endsWith = [&](const char* suffix) {
    std::string x = suffix;
    if (name.size() < x.size()) return false;
    std::string tail = name.substr(name.size() - x.size());
    std::transform(tail.begin(), tail.end(), tail.begin(), [](unsigned char c) { return std::tolower(c); });
    return tail == x;
  };
  return name.find('/') != std::string::npos || endsWith(".gltf") || endsWith(".glb") || endsWith(".obj");
}
}  // namespace

// Edit distance between two names, for "did you mean" on a misspelt scene.
static size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// Lights are uploaded as one storage buffer and listed per light each frame; far more than any
// technique is measured with (thesis §4 uses up to a few thousand), and it keeps a typo such as
// --lights 1000000000 from exhausting memory.
constexpr uint32_t kMaxLights = 65536;

bool makeScene(const std::string& name, const SceneParams& params, Scene* out, std::string* error) {
  if (params.lightCount > kMaxLights) {
    *error = "scene '" + name + "': " + std::to_string(params.lightCount) + " lights requested (limit " +
             std::to_string(kMaxLights) + ")";
    return false;
  }
  if (name == "default") {
    // Built once per process and parameters: placing the lights casts rays through the scene,
    // and a case of `parity run` asks for it twice (its cameras, then its frame). The fork
    // server builds the default parameters' before it forks (harness/cli/main.cpp).
    static std::mutex mutex;
    static std::map<std::tuple<uint32_t, LightSize, uint32_t>, Scene> built;
    std::lock_guard<std::mutex> lock(mutex);
    auto key = std::make_tuple(params.lightCount, params.lightSize, params.seed);
    auto it = built.find(key);
    if (it == built.end()) it = built.emplace(key, makeDefaultScene(params)).first;
    *out = it->second;
    return true;
  }
  if (looksLikePath(name)) return loadSceneFile(name, params, out, error);
  std::string path = assetScenePath(name);
  if (!path.empty()) {
    if (!std::filesystem::is_regular_file(path)) {
      *error = "scene '" + name + "' needs " + path + ", which is not present (shared assets are optional)";
      return false;
    }
    if (!loadSceneFile(path, params, out, error)) return false;
    out->name = name;
    return true;
  }
  std::string known;
  for (const std::string& n : sceneNames()) known += (known.empty() ? "" : ", ") + n;
  std::string suggestion = didYouMean(name, sceneNames());
  *error = "unknown scene '" + name + "' (" + suggestion + "known: " + known + "; or a .gltf/.glb/.obj file path)";
  return false;
}

std::string didYouMean(const std::string& name, const std::vector<std::string>& known) {
  std::string nearest;
  size_t nearestDistance = SIZE_MAX;
  for (const std::string& n : known) {
    size_t d = editDistance(name, n);
    if (d < nearestDistance) nearestDistance = d, nearest = n;
  }
  // Only a plausible misspelling is suggested: at most a third of the name's letters differ.
  return !nearest.empty() && nearestDistance * 3 <= std::max<size_t>(nearest.size(), 3)
             ? "did you mean '" + nearest + "'? "
             : "";
}

}  // namespace parity::scene
