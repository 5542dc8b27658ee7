#version 450
// Scene geometry for the geometry and material passes: view-space normal, linear depth (view
// distance along -z over the far plane, the DSF depth) and the triangle's normal-group ID.
#include "parity_math.glsl"
#include "scene_data.glsl"

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;
layout(location = 3) in uint inNormalGroup;

layout(location = 0) out vec3 outViewNormal;
layout(location = 1) out float outLinearDepth;
layout(location = 2) out vec2 outUv;
layout(location = 3) flat out uint outNormalGroup;
layout(location = 4) out vec3 outViewPos;  // for the normal map's tangent frame

void main() {
  vec4 viewPos = mul(frame.view, vec4(inPosition, 1.0));
  outViewNormal = mul(mat3(frame.view), inNormal);
  outLinearDepth = -viewPos.z / frame.nearFar.y;
  outUv = inUv;
  outNormalGroup = inNormalGroup;
  outViewPos = viewPos.xyz;
  gl_Position = mul(frame.viewProj, vec4(inPosition, 1.0));
}
