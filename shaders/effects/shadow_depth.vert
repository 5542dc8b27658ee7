#version 450
// Shadow-map pass: world-space vertices into one face of a light's shadow map.
#include "parity_math.glsl"

layout(location = 0) in vec3 inPosition;
layout(push_constant, std430) uniform ShadowFace { mat4 lightViewProj; } face;

void main() { gl_Position = mul(face.lightViewProj, vec4(inPosition, 1.0)); }
