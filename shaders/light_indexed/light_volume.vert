#version 450
// A light's enclosing volume (techniques/common/light_volumes.h) placed by its model matrix.
// The light is material.flags.y (scene_data.glsl's push-constant block).
#include "parity_math.glsl"
#include "scene_data.glsl"

layout(set = 0, binding = 3, std430) readonly buffer VolumeModels { mat4 volumeModels[]; };

layout(location = 0) in vec3 inPosition;

void main() {
  vec4 world = mul(volumeModels[material.flags.y], vec4(inPosition, 1.0));
  gl_Position = mul(frame.viewProj, world);
}
