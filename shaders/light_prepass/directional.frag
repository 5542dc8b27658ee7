#version 450
// Light pre-pass, first light pass (full screen): the directional light's diffuse and specular
// light (eq. 3.6 without the material colours) into the light accumulation target(s).
#include "parity_math.glsl"
#include "scene_data.glsl"
#include "phong.glsl"
#include "../platforms/platform.glsl"
#include "gbuffer.glsl"
#include "nm_read.glsl"
#define PARITY_LIGHT_ACCUMULATION_OUTPUTS
#include "light_prepass.glsl"

void main() {
  LitPoint s = readLitPoint();
  vec3 L = frame.directionalDir.xyz;
  vec3 diffuseLight = phongTerms(s.N, L, s.C, vec3(1.0), vec3(0.0), s.power) * frame.directionalColor.rgb;
  vec3 specularLight = phongTerms(s.N, L, s.C, vec3(0.0), vec3(1.0), s.power) * frame.directionalColor.rgb;
  writeLight(diffuseLight, specularLight);
}
