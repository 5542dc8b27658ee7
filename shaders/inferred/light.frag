#version 450
// Light pass (§2.2): one full-screen quad per light (scissored, stencil-masked by its volume),
// plus one for the ambient and directional light (material.flags.z = 1). Adds diffuse light in
// RGB and the specular intensity in A (the light's luminance times the Phong specular term), the
// same Phong terms forward shading evaluates (phong.glsl), from the G-buffer texel's position
// (reconstructed from depth), normal and specular power.
#include "parity_math.glsl"
#include "scene_data.glsl"
#include "phong.glsl"
#include "normal_encoding.glsl"
#include "platform.glsl"
#include "inferred.glsl"

layout(set = 0, binding = 4) uniform PARITY_RG16_SAMPLER gNormals;
layout(set = 0, binding = 5) uniform PARITY_DEPTH_SAMPLER gDepth;
layout(set = 0, binding = 6) uniform sampler2D gSpecular;

layout(location = 0) out vec4 outLight;

void main() {
  ivec2 texel = ivec2(gl_FragCoord.xy);
  float depth = parityReadDepth(texelFetch(gDepth, texel, 0));
  if (depth >= 1.0) {  // nothing drawn here
    outLight = parityWriteRgba16Hdr(vec4(0.0));
    return;
  }
  vec2 ndc = (vec2(texel) + 0.5) / inferred.sizes.zw * 2.0 - 1.0;
  vec4 world = mul(frame.invViewProj, vec4(ndc, depth, 1.0));
  vec3 P = world.xyz / world.w;
  vec3 nView = decodeNormalHalfSphere(parityReadRg16(texelFetch(gNormals, texel, 0)));
  // View -> world: the view matrix's rotation is orthonormal, its inverse is its transpose.
  vec3 N = normalize3(vec3(dot3(frame.view[0].xyz, nView), dot3(frame.view[1].xyz, nView), dot3(frame.view[2].xyz, nView)));
  vec3 C = normalize3(frame.cameraPos.xyz - P);
  float power = floor(texelFetch(gSpecular, texel, 0).r * 255.0 + 0.5);

  vec3 L;
  vec3 color;
  float attenuationSpot = 1.0;
  if (material.flags.z == 1u) {
    L = frame.directionalDir.xyz;
    color = frame.directionalColor.rgb;
  } else {
    Light light = lights[material.flags.y];
    vec3 toSurface = P - light.positionRadius.xyz;
    float d = length3(toSurface);
    float A = attenuation(d, light.colorK.w, light.positionRadius.w);
    if (A == 0.0) {
      outLight = parityWriteRgba16Hdr(vec4(0.0));
      return;
    }
    L = toSurface / d;
    float F = 1.0;
    if (floatBitsToUint(light.directionType.w) == LIGHT_SPOT)
      F = spotFactor(light.directionType.xyz, L, light.cone.x, light.cone.y);  // eq. 3.12
    attenuationSpot = A * F;
    color = light.colorK.rgb;
  }
  float D = phongTerms(N, L, C, vec3(1.0), vec3(0.0), power).x;
  float S = phongTerms(N, L, C, vec3(0.0), vec3(1.0), power).x;
  vec4 light = vec4(color * D, lightLuminance(color) * S) * attenuationSpot;
  if (material.flags.z == 1u) light.rgb += frame.ambient.rgb;
  outLight = parityWriteRgba16Hdr(light);
}
