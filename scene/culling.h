// Bounding-volume tests for light lists and camera visibility lists (thesis §3.1.1): sphere–AABB
// for point lights, cone–AABB for spot lights, frustum–AABB for the camera. Every test is
// conservative: it may keep an object the volume misses, never drop one it touches, so a
// technique that draws only the listed objects renders the same image as one that draws all.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace parity::scene {

struct Aabb {
  glm::vec3 min, max;
};

// Squared distance from a point to the box (0 inside); Ericson's SqDistPointAABB.
float distanceSquaredPointAabb(glm::vec3 p, const Aabb& box);
// The sphere reaches into the box: squared distance < radius^2 (the thesis's pseudo code compares
// with the centre, a typo; Ericson compares with the squared radius).
bool sphereIntersectsAabb(glm::vec3 center, float radius, const Aabb& box);
// A plane n·x = d (n not necessarily unit): true when the whole box lies on the side n·x < d.
bool aabbOutsidePlane(glm::vec3 n, float d, const Aabb& box);
// A spot light's volume: the cone from `apex` along unit `direction` with half-angle acos(cosOuter),
// cut by the sphere of radius `range`. The cone is bounded by the square pyramid that touches it
// along four lines (the thesis's bounding pyramid); the box is rejected when it lies outside one
// of the pyramid's four side planes or outside the sphere. (The thesis's "is a corner inside the
// pyramid" test misses boxes that straddle the pyramid with every corner outside; the separating
// plane test does not.)
bool coneIntersectsAabb(glm::vec3 apex, glm::vec3 direction, float cosOuter, float range, const Aabb& box);
// The light's volume (sphere for a point light, cone for a spot) reaches into the box.
bool lightIntersectsAabb(const Light& light, const Aabb& box);

// View frustum planes (a, b, c, d: inside where a x + b y + c z + d >= 0) of a Vulkan-style
// projection (depth 0..1), from the rows of the view-projection matrix (Gribb–Hartmann).
struct Frustum {
  glm::vec4 planes[6];
};
Frustum frustumFromViewProjection(const glm::mat4& viewProj);
bool frustumIntersectsAabb(const Frustum& f, const Aabb& box);

// The lists of §3.1: the camera visibility list (meshes in the frustum) and, per light, the
// visibility light list (meshes the light's volume touches that are also visible).
struct LightLists {
  std::vector<uint32_t> visible;               // mesh indices, in scene order
  std::vector<std::vector<uint32_t>> perLight; // per light: mesh indices, in scene order
};
LightLists buildLightLists(const Scene& scene, const glm::mat4& viewProj);

}  // namespace parity::scene
