// The n/m buffer and depth as the light pre-pass's light passes read them (texelFetch, through
// the platform's read paths).
#ifndef PARITY_LIGHT_PREPASS_NM_READ_GLSL
#define PARITY_LIGHT_PREPASS_NM_READ_GLSL

layout(set = 0, binding = 4) uniform PARITY_DEPTH_SAMPLER nmDepth;
layout(set = 0, binding = 5) uniform PARITY_RG16_SAMPLER nmNormals;
layout(set = 0, binding = 6) uniform sampler2D nmPower;

struct LitPoint {
  vec3 worldPos;
  vec3 N;  // world space, unit
  vec3 C;  // towards the camera, unit
  float power;
};

LitPoint readLitPoint() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  LitPoint s;
  float depth = parityReadDepth(texelFetch(nmDepth, p, 0));
  s.worldPos = worldPositionFromDepth(gl_FragCoord.xy, vec2(textureSize(nmPower, 0)), depth);
  s.N = decodeWorldNormal(parityReadRg16(texelFetch(nmNormals, p, 0)));
  s.C = normalize3(frame.cameraPos.xyz - s.worldPos);
  s.power = decodeSpecularPower(texelFetch(nmPower, p, 0).r);
  return s;
}

#endif
