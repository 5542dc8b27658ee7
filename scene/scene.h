// A scene on the CPU: world-space triangle meshes with materials, lights and named cameras.
// Node transforms are baked into the vertices, so every technique draws the same data.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace parity::scene {

struct Vertex {
  glm::vec3 position;
  glm::vec3 normal;
  glm::vec2 uv;
};
static_assert(sizeof(Vertex) == 32, "vertex layout is shared with shaders (stride 32)");

struct Material {
  std::string name;
  glm::vec3 diffuse{0.8f};
  glm::vec3 specular{0.2f};
  float specularPower = 32.0f;
  int diffuseTexture = -1;  // index into Scene::textures, -1: none
  float opacity = 1.0f;     // < 1: a translucent (alpha) polygon, for techniques that light them
  // Tangent-space normal map (glTF convention: RGB = (x, y, z) * 0.5 + 0.5, +x along +u, +y
  // towards the image's top row, i.e. along -v); index into Scene::textures, -1: none. The
  // vertices carry no tangents: shaders build the frame from screen-space derivatives
  // (shaders/include/normal_mapping.glsl).
  int normalTexture = -1;
};

struct Texture {
  std::string name;
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> rgba8;  // row 0 first
};

// A contiguous index range drawn with one material.
struct Mesh {
  std::string name;
  uint32_t firstIndex = 0, indexCount = 0;
  int material = 0;
  glm::vec3 boundsMin{0.0f}, boundsMax{0.0f};  // world-space AABB
};

enum class LightType : uint32_t { Point = 0, Spot = 1 };

struct Light {
  LightType type = LightType::Point;
  glm::vec3 position{0.0f};
  glm::vec3 color{1.0f};     // intensity per channel
  float radius = 1.0f;       // no effect beyond this distance
  glm::vec3 direction{0.0f, -1.0f, 0.0f};  // spot only
  float cosOuter = 0.8f, cosInner = 0.9f;   // spot only
  // Rendered into a shadow map by techniques with shadows (techniques/effects/shadow_maps.h).
  // Default false: shadow maps cost a depth pass per light (six for a point light).
  bool castsShadows = false;
  // k of the attenuation window(d / radius) / (1 + (k d)^2) (shaders/include/phong.glsl):
  // 2 / radius: A = 0.44 halfway to the radius, so a light visibly fills the volume that
  // defines its size class.
  float attenuationK() const { return 2.0f / radius; }
};

struct Camera {
  std::string name;
  glm::vec3 position{0.0f, 2.0f, 8.0f};
  glm::vec3 target{0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float fovYDegrees = 60.0f;
  float nearPlane = 0.1f, farPlane = 100.0f;
  // Vulkan-style projection (rhi.h conventions): depth [0, 1], "up" maps to NDC y = -1.
  glm::mat4 viewProjection(float aspect) const;
};

struct Scene {
  std::string name;
  std::vector<Vertex> vertices;
  std::vector<uint32_t> indices;
  std::vector<Mesh> meshes;
  std::vector<Material> materials;
  std::vector<Texture> textures;
  std::vector<Light> lights;
  glm::vec3 ambient{0.05f};
  glm::vec3 directionalDir{-0.3f, -1.0f, -0.4f};  // incidence direction, normalised on use
  glm::vec3 directionalColor{0.15f};
  // The directional light's counterpart of Light::castsShadows. Default true: techniques with
  // shadows have always rendered its map, so existing images stay as they are.
  bool directionalCastsShadows = true;
  std::vector<Camera> cameras;  // [0] is the default camera
  const Camera* camera(const std::string& name) const;  // null when unknown
};

enum class LightSize { Small, Big };

struct SceneParams {
  uint32_t lightCount = 24;
  // Thesis §4: "small" lights cover 0.25–5% of the screen, "big" ones 20–100%.
  LightSize lightSize = LightSize::Small;
  uint32_t seed = 1;
};

// Aspect ratio at which light sizes are measured (the default 320x180 image).
constexpr float kLightSizeAspect = 16.0f / 9.0f;

// Screen-coverage ranges of the size classes (fractions of the image), thesis §4.
struct CoverageRange {
  float lo, hi;
};
CoverageRange coverageRange(LightSize size);

// Fraction of the image covered by a sphere (a light's volume) seen from `camera`, counted over
// the pixel centres of a gridWidth x gridHeight image; 1 when the camera is inside the sphere.
float sphereScreenCoverage(const Camera& camera, float aspect, glm::vec3 center, float radius,
                           uint32_t gridWidth = 256, uint32_t gridHeight = 144);

// Places params.lightCount lights from params.seed inside [boundsMin, boundsMax] (every third one
// a spot aimed downwards), each with a radius adjusted so that its volume covers a fraction of
// the image of `camera` (kLightSizeAspect) drawn from the size class's range, as the thesis's
// §3.2 adjusts its random lights to the constraints of the test.
void placeLights(Scene& scene, const SceneParams& params, const Camera& camera, glm::vec3 boundsMin,
                 glm::vec3 boundsMax);

// First hits of rays against a scene's triangles (light placement's view of what the camera
// sees, the enclosure test): the triangles' edges prepared once, each mesh's bounds tested first.
class RayCaster {
 public:
  explicit RayCaster(const Scene& scene);
  // Distance along the unit ray (origin, d) to the first triangle it hits (infinity when none),
  // and that triangle's normal on the side facing the ray.
  float firstHit(glm::vec3 origin, glm::vec3 d, glm::vec3* normal) const;

 private:
  struct Triangle {
    glm::vec3 a, e1, e2;
  };
  struct MeshRange {
    glm::vec3 lo, hi;
    size_t begin, end;  // into triangles_
  };
  std::vector<Triangle> triangles_;
  std::vector<MeshRange> meshes_;
};
// The share of 48 rays from `point` (16 around the horizon at -30, 0 and +30 degrees) that hit
// the scene: near 1 inside an enclosed space such as Sponza's courtyard.
float enclosure(const Scene& scene, glm::vec3 point);

// The procedural default scene: a floor, three walls, boxes and spheres of several materials,
// named cameras ("default", "high", "grazing", "side", "close"), and `lightCount` point and spot
// lights placed from `seed`. Deterministic on every platform (no std:: distributions).
Scene makeDefaultScene(const SceneParams& params = {});

// Loads a glTF 2.0 (.gltf, .glb) or OBJ (+MTL) file: node transforms baked into world-space
// vertices, one Mesh per primitive (glTF) or per shape and material (OBJ), cameras derived from
// the bounds ("default" and "outside" in front, "high", "side", "close", "inside"; for an
// enclosed model, whose outside shows only walls, "default" is the inside view) and lights
// placed by placeLights(). Returns
// false with one line "FILE: reason" for a file that cannot be used (truncated, missing buffer
// or texture, no triangles, ...).
bool loadSceneFile(const std::string& path, const SceneParams& params, Scene* out, std::string* error);

// Folder of the optional shared assets (next to the source tree); may not exist.
std::string sharedAssetsDirectory();
// A named scene backed by a file under sharedAssetsDirectory().
struct AssetScene {
  std::string name;
  std::string relativePath;  // relative to sharedAssetsDirectory()
};
const std::vector<AssetScene>& assetScenes();  // every registered name, present or not
// Full path of a registered asset scene, or "" for an unknown name.
std::string assetScenePath(const std::string& name);

// "default" and the asset scenes whose files are present.
std::vector<std::string> sceneNames();
// The cameras a scene will have, without loading it (file scenes get the cameras that
// scene_loader.cpp places around their bounds).
std::vector<std::string> cameraNames(const std::string& sceneName);
// Builds a scene by name or from a file path (anything with a '/' or a .gltf/.glb/.obj suffix);
// returns false with a one-line reason for an unknown name or an unusable file.
bool makeScene(const std::string& name, const SceneParams& params, Scene* out, std::string* error);

// "did you mean 'NAME'? " for the known name nearest to a misspelt `name` (edit distance at
// most a third of its letters), or "" when none is plausible. Used for every name a user types.
std::string didYouMean(const std::string& name, const std::vector<std::string>& known);

}  // namespace parity::scene
