// Scene data shared by every technique: the layout mirrors scene/scene_gpu.h (std140 / std430).
#ifndef PARITY_SCENE_DATA_GLSL
#define PARITY_SCENE_DATA_GLSL

#define LIGHT_POINT 0u
#define LIGHT_SPOT 1u

layout(set = 0, binding = 0, std140) uniform FrameData {
  mat4 viewProj;
  vec4 cameraPos;        // xyz
  vec4 ambient;          // rgb: ambient light intensity
  vec4 directionalDir;   // xyz: incidence direction (from the light towards the scene)
  vec4 directionalColor; // rgb: intensity (0: no directional light)
  uvec4 counts;          // x: local light count
  mat4 view;             // world -> view (right-handed, camera looks down -z)
  mat4 invViewProj;      // clip -> world, for reconstructing positions from depth
  vec4 nearFar;          // x near plane, y far plane
} frame;

// A point or spot light. Attenuation: thesis eq. 3.11 with distance in units of 1/k, windowed
// to reach 0 at `radius` (see phong.glsl); the light affects nothing beyond `radius`.
struct Light {
  vec4 positionRadius;   // xyz position, w radius
  vec4 colorK;           // rgb intensity, w k
  vec4 directionType;    // xyz spot direction, w type (LIGHT_POINT / LIGHT_SPOT) as float bits
  vec4 cone;             // x cos(outer), y cos(inner)
};

layout(set = 0, binding = 1, std430) readonly buffer LightData { Light lights[]; };

// Per-draw material, in push constants.
layout(push_constant, std430) uniform Material {
  vec4 diffuse;          // rgb diffuse colour
  vec4 specular;         // rgb specular colour, w specular power
  uvec4 flags;           // x: MATERIAL_* bits; y: light index (per-light passes)
} material;

// Bits of material.flags.x (scene/scene_gpu.h: kMaterialDiffuseTexture, kMaterialNormalMap).
#define MATERIAL_DIFFUSE_TEXTURE 1u
#define MATERIAL_NORMAL_MAP 2u

#endif
