#version 450
// Tiled deferred shading (thesis §2.4): one full-screen pass; each pixel reads its G-buffer once
// and sums ambient, the directional light and its tile's lights.
#include "parity_math.glsl"
#include "scene_data.glsl"
#include "phong.glsl"
#include "tiled_lighting.glsl"
#include "platform.glsl"

layout(set = 0, binding = 4) uniform PARITY_DEPTH_SAMPLER sceneDepth;  // read as the platform reads depth
layout(set = 0, binding = 5) uniform sampler2D gbufferNormal;
layout(set = 0, binding = 6) uniform sampler2D gbufferDiffusePower;
layout(set = 0, binding = 7) uniform sampler2D gbufferSpecular;

layout(location = 0) out vec4 outColor;

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  float depth = parityReadDepth(texelFetch(sceneDepth, pixel, 0));
  if (depth >= 1.0) {
    outColor = vec4(0.0, 0.0, 0.0, 1.0);  // the forward techniques' clear colour
    return;
  }
  vec2 ndc = (vec2(pixel) + 0.5) / vec2(textureSize(sceneDepth, 0)) * 2.0 - 1.0;
  vec4 h = mul(frame.invViewProj, vec4(ndc, depth, 1.0));
  vec3 worldPos = h.xyz / h.w;

  vec3 N = parityReadRgba16Hdr(texelFetch(gbufferNormal, pixel, 0)).xyz;
  vec4 diffusePower = parityReadRgba16Hdr(texelFetch(gbufferDiffusePower, pixel, 0));
  vec3 diffuseColor = diffusePower.rgb;
  float power = diffusePower.w;
  vec3 specularColor = parityReadRgba16Hdr(texelFetch(gbufferSpecular, pixel, 0)).rgb;
  vec3 C = normalize3(frame.cameraPos.xyz - worldPos);

  vec3 color = diffuseColor * frame.ambient.rgb;  // eq. 3.5
  color += phongTerms(N, frame.directionalDir.xyz, C, diffuseColor, specularColor, power) *
           frame.directionalColor.rgb;  // eq. 3.6
  addTileLights(color, pixel, worldPos, N, C, diffuseColor, specularColor, power);
  outColor = vec4(color, 1.0);
}
