// The G-buffer as the deferred shading passes read it: one texel per pixel (texelFetch), through
// the platform's read paths for depth and normals.
#ifndef PARITY_DEFERRED_GBUFFER_READ_GLSL
#define PARITY_DEFERRED_GBUFFER_READ_GLSL

layout(set = 0, binding = 4) uniform PARITY_DEPTH_SAMPLER gbufferDepth;
layout(set = 0, binding = 5) uniform PARITY_RG16_SAMPLER gbufferNormals;
layout(set = 0, binding = 6) uniform sampler2D gbufferDiffuse;
layout(set = 0, binding = 7) uniform sampler2D gbufferSpecular;

struct Surface {
  vec3 worldPos;
  vec3 N;              // world space, unit
  vec3 C;              // towards the camera, unit
  vec3 diffuseColor;
  vec3 specularColor;
  float power;
};

Surface readSurface() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  Surface s;
  float depth = parityReadDepth(texelFetch(gbufferDepth, p, 0));
  s.worldPos = worldPositionFromDepth(gl_FragCoord.xy, vec2(textureSize(gbufferDiffuse, 0)), depth);
  s.N = decodeWorldNormal(parityReadRg16(texelFetch(gbufferNormals, p, 0)));
  s.C = normalize3(frame.cameraPos.xyz - s.worldPos);
  s.diffuseColor = texelFetch(gbufferDiffuse, p, 0).rgb;
  vec4 specular = texelFetch(gbufferSpecular, p, 0);
  s.specularColor = specular.rgb;
  s.power = decodeSpecularPower(specular.a);
  return s;
}

#endif
