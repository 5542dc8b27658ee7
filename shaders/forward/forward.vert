#version 450
// Forward shading: world-space vertices (the scene bakes node transforms), one camera.
#include "parity_math.glsl"
#include "scene_data.glsl"

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;

layout(location = 0) out vec3 outWorldPos;
layout(location = 1) out vec3 outNormal;
layout(location = 2) out vec2 outUv;

void main() {
  outWorldPos = inPosition;
  outNormal = inNormal;
  outUv = inUv;
  gl_Position = mul(frame.viewProj, vec4(inPosition, 1.0));
}
