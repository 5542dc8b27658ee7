#version 450
// Light volume pass: keeps a fragment only where the visible surface (depth pre-pass) is
// reached by light material.flags.y, i.e. where the forward shader's attenuation (eq. 3.11,
// windowed to 0 at the radius) and spot factor (eq. 3.12) are both non-zero. The volume mesh
// only bounds the light; this test makes the light index texture hold exactly the lights that
// add something, so overlaps are counted as the paper counts them ("lights that hit a surface").
// With LIDR_FRONT_FACES (MSAA technique 2) nothing is tested here: the depth test alone keeps the
// front faces in front of the farthest opaque sample.
// Outputs the push-constant colours: material.diffuse (and material.specular for a second target).
#include "parity_math.glsl"
#include "scene_data.glsl"

layout(set = 0, binding = 4) uniform sampler2D surfaceDepth;

layout(location = 0) out vec4 outIndexA;
#ifdef LIDR_SECOND_TARGET
layout(location = 1) out vec4 outIndexB;
#endif

void main() {
#ifndef LIDR_FRONT_FACES
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  float depth = texelFetch(surfaceDepth, pixel, 0).r;
  if (depth >= 1.0) discard;  // background: no surface
  vec2 size = vec2(textureSize(surfaceDepth, 0));
  vec2 ndc = (vec2(pixel) + 0.5) / size * 2.0 - 1.0;
  vec4 h = mul(frame.invViewProj, vec4(ndc, depth, 1.0));
  vec3 world = h.xyz / h.w;

  Light light = lights[material.flags.y];
  vec3 toSurface = world - light.positionRadius.xyz;
  float d = length3(toSurface);
  if (!(d < light.positionRadius.w)) discard;
  if (floatBitsToUint(light.directionType.w) == LIGHT_SPOT && !(dot3(light.directionType.xyz, toSurface / d) > light.cone.x))
    discard;
#endif
  outIndexA = material.diffuse;
#ifdef LIDR_SECOND_TARGET
  outIndexB = material.specular;
#endif
}
