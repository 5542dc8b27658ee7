#include "scene/culling.h"

#include <algorithm>
#include <cmath>

namespace parity::scene {

namespace {
// Relative slack that keeps the tests conservative against rounding in the shaders' own
// attenuation and spot-factor arithmetic at the very edge of a volume.
constexpr float kSlack = 1e-4f;
}  // namespace

float distanceSquaredPointAabb(glm::vec3 p, const Aabb& box) {
  float d = 0.0f;
  for (int i = 0; i < 3; ++i) {
    if (p[i] < box.min[i]) d += (box.min[i] - p[i]) * (box.min[i] - p[i]);
    if (p[i] > box.max[i]) d += (p[i] - box.max[i]) * (p[i] - box.max[i]);
  }
  return d;
}

bool sphereIntersectsAabb(glm::vec3 center, float radius, const Aabb& box) {
  return distanceSquaredPointAabb(center, box) < radius * radius;
}

bool aabbOutsidePlane(glm::vec3 n, float d, const Aabb& box) {
  // The corner furthest along n (the "positive vertex"): if even it is behind, all are.
  glm::vec3 p{n.x >= 0.0f ? box.max.x : box.min.x, n.y >= 0.0f ? box.max.y : box.min.y,
              n.z >= 0.0f ? box.max.z : box.min.z};
  return glm::dot(n, p) < d;
}

bool coneIntersectsAabb(glm::vec3 apex, glm::vec3 direction, float cosOuter, float range, const Aabb& box) {
  if (!sphereIntersectsAabb(apex, range * (1.0f + kSlack), box)) return false;
  if (cosOuter <= 0.0f) return true;  // half-angle of 90 degrees or more: no useful pyramid
  glm::vec3 a = glm::normalize(direction);
  glm::vec3 helper = std::fabs(a.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
  glm::vec3 u = glm::normalize(glm::cross(a, helper));
  glm::vec3 w = glm::cross(a, u);
  float c = cosOuter, s = std::sqrt(std::max(0.0f, 1.0f - c * c));
  // Side planes through the apex, tangent to the cone, normals pointing inwards: n = a s - e c
  // for e = ±u, ±w. A box is outside when all of it is behind one of them (with a little slack).
  for (glm::vec3 e : {u, -u, w, -w}) {
    glm::vec3 n = a * s - e * c;
    if (aabbOutsidePlane(n, glm::dot(n, apex) - kSlack * range, box)) return false;
  }
  return true;
}

bool lightIntersectsAabb(const Light& light, const Aabb& box) {
  if (light.type == LightType::Spot)
    return coneIntersectsAabb(light.position, light.direction, light.cosOuter, light.radius, box);
  return sphereIntersectsAabb(light.position, light.radius * (1.0f + kSlack), box);
}

Frustum frustumFromViewProjection(const glm::mat4& m) {
  auto row = [&](int r) { return glm::vec4(m[0][r], m[1][r], m[2][r], m[3][r]); };
  Frustum f;
  f.planes[0] = row(3) + row(0);  // x >= -w
  f.planes[1] = row(3) - row(0);  // x <= w
  f.planes[2] = row(3) + row(1);  // y >= -w
  f.planes[3] = row(3) - row(1);  // y <= w
  f.planes[4] = row(2);           // z >= 0
  f.planes[5] = row(3) - row(2);  // z <= w
  return f;
}

bool frustumIntersectsAabb(const Frustum& f, const Aabb& box) {
  for (const glm::vec4& p : f.planes) {
    glm::vec3 n(p);
    float scale = glm::length(n);
    if (aabbOutsidePlane(n, -p.w - kSlack * scale, box)) return false;
  }
  return true;
}

LightLists buildLightLists(const Scene& scene, const glm::mat4& viewProj) {
  LightLists lists;
  Frustum f = frustumFromViewProjection(viewProj);
  for (uint32_t i = 0; i < scene.meshes.size(); ++i)
    if (frustumIntersectsAabb(f, {scene.meshes[i].boundsMin, scene.meshes[i].boundsMax})) lists.visible.push_back(i);
  lists.perLight.resize(scene.lights.size());
  for (size_t l = 0; l < scene.lights.size(); ++l)
    for (uint32_t i : lists.visible)
      if (lightIntersectsAabb(scene.lights[l], {scene.meshes[i].boundsMin, scene.meshes[i].boundsMax}))
        lists.perLight[l].push_back(i);
  return lists;
}

}  // namespace parity::scene
