#version 450
// A light's enclosing volume (techniques/common/light_volumes.h) for the depth-fail stencil marks.
#include "parity_math.glsl"

layout(push_constant, std430) uniform Volume {
  mat4 clipFromObject;
} volume;

layout(location = 0) in vec3 inPosition;

void main() { gl_Position = mul(volume.clipFromObject, vec4(inPosition, 1.0)); }
