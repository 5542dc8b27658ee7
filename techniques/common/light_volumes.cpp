#include "techniques/common/light_volumes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

namespace parity::techniques {

namespace {

struct Shape {
  std::vector<glm::vec3> vertices;
  std::vector<uint32_t> indices;  // counter-clockwise seen from outside
};

// Scales `s` so that every face plane is at least distance 1 from the origin: the mesh then
// encloses the unit sphere (or, for the cone, the exact cone it approximates).
void scaleToEnclose(Shape& s, float exactDistance) {
  float minDistance = 1e30f;
  for (size_t i = 0; i + 2 < s.indices.size(); i += 3) {
    glm::vec3 a = s.vertices[s.indices[i]], b = s.vertices[s.indices[i + 1]], c = s.vertices[s.indices[i + 2]];
    glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
    minDistance = std::min(minDistance, glm::dot(n, a));
  }
  float scale = exactDistance / minDistance;
  for (glm::vec3& v : s.vertices) v *= scale;
}

// Icosahedron subdivided twice (320 faces).
Shape makeSphere() {
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  Shape s;
  for (glm::vec3 v : {glm::vec3(-1, t, 0), glm::vec3(1, t, 0), glm::vec3(-1, -t, 0), glm::vec3(1, -t, 0),
                      glm::vec3(0, -1, t), glm::vec3(0, 1, t), glm::vec3(0, -1, -t), glm::vec3(0, 1, -t),
                      glm::vec3(t, 0, -1), glm::vec3(t, 0, 1), glm::vec3(-t, 0, -1), glm::vec3(-t, 0, 1)})
    s.vertices.push_back(glm::normalize(v));
  s.indices = {0, 11, 5, 0, 5,  1,  0,  1,  7,  0,  7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4,  11, 10, 2,  10, 7, 6, 7, 1, 8,
               3, 9,  4, 3, 4,  2,  3,  2,  6,  3,  6, 8,  3, 8,  9,  4, 9, 5, 2, 4,  11, 6,  2,  10, 8,  6, 7, 9, 8, 1};
  for (int level = 0; level < 2; ++level) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoints;
    auto midpoint = [&](uint32_t a, uint32_t b) {
      auto key = std::minmax(a, b);
      auto it = midpoints.find(key);
      if (it != midpoints.end()) return it->second;
      s.vertices.push_back(glm::normalize(s.vertices[a] + s.vertices[b]));
      uint32_t index = static_cast<uint32_t>(s.vertices.size() - 1);
      midpoints[key] = index;
      return index;
    };
    std::vector<uint32_t> next;
    for (size_t i = 0; i < s.indices.size(); i += 3) {
      uint32_t a = s.indices[i], b = s.indices[i + 1], c = s.indices[i + 2];
      uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      next.insert(next.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
    }
    s.indices = std::move(next);
  }
  scaleToEnclose(s, 1.0f);
  return s;
}

// Cone with its apex at the origin, axis +Z, flat base at z = 1 of radius 1 (scaled per light in
// x and y by tan(outer)): a ring of segments whose edges lie outside the circle.
Shape makeCone() {
  constexpr int kSegments = 24;
  const float ringScale = 1.0f / std::cos(3.14159265358979f / kSegments);
  Shape s;
  s.vertices.push_back(glm::vec3(0.0f));         // apex
  s.vertices.push_back(glm::vec3(0.0f, 0.0f, 1.0f));  // base centre
  for (int i = 0; i < kSegments; ++i) {
    float a = 2.0f * 3.14159265358979f * static_cast<float>(i) / kSegments;
    s.vertices.push_back(glm::vec3(std::cos(a) * ringScale, std::sin(a) * ringScale, 1.0f));
  }
  for (uint32_t i = 0; i < kSegments; ++i) {
    uint32_t a = 2 + i, b = 2 + (i + 1) % kSegments;
    s.indices.insert(s.indices.end(), {0u, b, a});  // side, seen from outside
    s.indices.insert(s.indices.end(), {1u, a, b});  // base, normal +Z
  }
  return s;
}

}  // namespace

LightVolumes::LightVolumes(rhi::Device& device) : device_(device) {
  Shape sphere = makeSphere(), cone = makeCone();
  std::vector<glm::vec3> vertices = sphere.vertices;
  vertices.insert(vertices.end(), cone.vertices.begin(), cone.vertices.end());
  std::vector<uint32_t> indices = sphere.indices;
  indices.insert(indices.end(), cone.indices.begin(), cone.indices.end());
  sphereFirstIndex_ = 0;
  sphereIndexCount_ = static_cast<uint32_t>(sphere.indices.size());
  sphereBaseVertex_ = 0;
  coneFirstIndex_ = sphereIndexCount_;
  coneIndexCount_ = static_cast<uint32_t>(cone.indices.size());
  coneBaseVertex_ = static_cast<uint32_t>(sphere.vertices.size());

  rhi::BufferDesc v;
  v.size = vertices.size() * sizeof(glm::vec3);
  v.initialData = vertices.data();
  v.label = "light volume vertices";
  vertices_ = device.createBuffer(v);
  rhi::BufferDesc i;
  i.size = indices.size() * sizeof(uint32_t);
  i.initialData = indices.data();
  i.label = "light volume indices";
  indices_ = device.createBuffer(i);
}

LightVolumes::~LightVolumes() {
  device_.destroy(vertices_);
  device_.destroy(indices_);
}

void LightVolumes::describeVertexLayout(rhi::PipelineDesc& desc) {
  desc.vertexBuffers[0].stride = sizeof(glm::vec3);
  desc.attributes[0].location = 0;
  desc.attributes[0].format = rhi::VertexFormat::Float3;
  desc.attributes[0].offset = 0;
  desc.attributes[0].bufferSlot = 0;
  desc.attributeCount = 1;
}

void LightVolumes::draw(const scene::Light& light) {
  device_.setVertexBuffer(0, vertices_);
  device_.setIndexBuffer(indices_, rhi::IndexType::UInt32);
  bool cone = light.type == scene::LightType::Spot && light.cosOuter > 0.1f;
  if (cone)
    device_.drawIndexed(coneIndexCount_, 1, coneFirstIndex_, static_cast<int32_t>(coneBaseVertex_));
  else
    device_.drawIndexed(sphereIndexCount_, 1, sphereFirstIndex_, static_cast<int32_t>(sphereBaseVertex_));
}

glm::mat4 LightVolumes::model(const scene::Light& light) {
  glm::mat4 m = glm::translate(glm::mat4(1.0f), light.position);
  if (light.type == scene::LightType::Spot && light.cosOuter > 0.1f) {
    glm::vec3 z = glm::normalize(light.direction);
    glm::vec3 helper = std::abs(z.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    glm::vec3 x = glm::normalize(glm::cross(helper, z));
    glm::vec3 y = glm::cross(z, x);
    float tanOuter = std::sqrt(std::max(0.0f, 1.0f - light.cosOuter * light.cosOuter)) / light.cosOuter;
    glm::mat4 basis(glm::vec4(x, 0), glm::vec4(y, 0), glm::vec4(z, 0), glm::vec4(0, 0, 0, 1));
    return m * basis * glm::scale(glm::mat4(1.0f), glm::vec3(tanOuter * light.radius, tanOuter * light.radius, light.radius));
  }
  return m * glm::scale(glm::mat4(1.0f), glm::vec3(light.radius));
}

bool cameraInsideLightVolume(const scene::Light& light, const scene::Camera& camera, float aspect) {
  float halfHeight = camera.nearPlane * std::tan(glm::radians(camera.fovYDegrees) * 0.5f);
  float halfWidth = halfHeight * aspect;
  float nearCorner = std::sqrt(camera.nearPlane * camera.nearPlane + halfHeight * halfHeight + halfWidth * halfWidth);
  // The enclosing meshes reach past the radius (the sphere by < 5%, the cone's base corners by
  // more): test against the sphere that bounds either mesh.
  float bound = light.radius * 1.5f;
  return glm::length(camera.position - light.position) < bound + nearCorner;
}

ScissorRect lightScissor(const scene::Light& light, const scene::Camera& camera, uint32_t width, uint32_t height) {
  ScissorRect full{0, 0, width, height};
  float aspect = static_cast<float>(width) / static_cast<float>(height);
  glm::mat4 viewProj = camera.viewProjection(aspect);
  float r = light.radius * 1.5f;  // bounds either enclosing mesh (see cameraInsideLightVolume)
  float minX = 1e30f, minY = 1e30f, maxX = -1e30f, maxY = -1e30f;
  for (int corner = 0; corner < 8; ++corner) {
    glm::vec3 p = light.position + glm::vec3(corner & 1 ? r : -r, corner & 2 ? r : -r, corner & 4 ? r : -r);
    glm::vec4 clip = viewProj * glm::vec4(p, 1.0f);
    if (clip.w <= camera.nearPlane) return full;  // a corner behind the near plane: no tight bound
    float x = (clip.x / clip.w * 0.5f + 0.5f) * static_cast<float>(width);
    float y = (clip.y / clip.w * 0.5f + 0.5f) * static_cast<float>(height);  // NDC y = -1 is memory row 0
    minX = std::min(minX, x);
    maxX = std::max(maxX, x);
    minY = std::min(minY, y);
    maxY = std::max(maxY, y);
  }
  int32_t x0 = std::clamp(static_cast<int32_t>(std::floor(minX)), 0, static_cast<int32_t>(width));
  int32_t y0 = std::clamp(static_cast<int32_t>(std::floor(minY)), 0, static_cast<int32_t>(height));
  int32_t x1 = std::clamp(static_cast<int32_t>(std::ceil(maxX)), 0, static_cast<int32_t>(width));
  int32_t y1 = std::clamp(static_cast<int32_t>(std::ceil(maxY)), 0, static_cast<int32_t>(height));
  return {x0, y0, static_cast<uint32_t>(x1 - x0), static_cast<uint32_t>(y1 - y0)};
}

}  // namespace parity::techniques
