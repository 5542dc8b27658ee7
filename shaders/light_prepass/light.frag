#version 450
// Light pre-pass, light volume pass: diffuse and specular light of light material.flags.y
// (eq. 3.7 / 3.8 with 3.11, 3.12, without the material colours), added by blending (One, One).
#include "parity_math.glsl"
#include "scene_data.glsl"
#include "phong.glsl"
#include "../platforms/platform.glsl"
#include "gbuffer.glsl"
#include "deferred_light.glsl"
#include "nm_read.glsl"
#define PARITY_LIGHT_ACCUMULATION_OUTPUTS
#include "light_prepass.glsl"

void main() {
  LitPoint s = readLitPoint();
  Light light = lights[material.flags.y];
  writeLight(localDiffuseLight(light, s.worldPos, s.N, s.C, s.power),
             localSpecularLight(light, s.worldPos, s.N, s.C, s.power));
}
