#version 450
// A light's volume (sphere or cone enclosing it, techniques/common/light_volumes.h), placed by the
// light's object-to-world matrix from the volume transform buffer; the light index is in the
// material block's flags.y.
#include "parity_math.glsl"
#include "scene_data.glsl"

layout(set = 0, binding = 3, std430) readonly buffer VolumeTransforms { mat4 volumeModel[]; };

layout(location = 0) in vec3 inPosition;

void main() {
  vec4 world = mul(volumeModel[material.flags.y], vec4(inPosition, 1.0));
  gl_Position = mul(frame.viewProj, world);
}
