// One point or spot light at a surface point: the body of the single-pass forward shader's light
// loop (shaders/forward/forward_single_pass.frag, eq. 3.7, 3.8, 3.11, 3.12), shared by the
// deferred techniques so that every technique evaluates the same expressions in the same order.
// Needs scene_data.glsl and phong.glsl included before.
#ifndef PARITY_DEFERRED_LIGHT_GLSL
#define PARITY_DEFERRED_LIGHT_GLSL

// (RGB_D * D + RGB_S * S) * light colour * A * F; 0 beyond the radius or outside the cone.
vec3 localLightTerms(Light light, vec3 worldPos, vec3 N, vec3 C, vec3 diffuseColor, vec3 specularColor, float power) {
  vec3 toSurface = worldPos - light.positionRadius.xyz;
  float d = length3(toSurface);
  float A = attenuation(d, light.colorK.w, light.positionRadius.w);
  if (A == 0.0) return vec3(0.0);
  vec3 L = toSurface / d;
  float F = 1.0;
  if (floatBitsToUint(light.directionType.w) == LIGHT_SPOT)
    F = spotFactor(light.directionType.xyz, L, light.cone.x, light.cone.y);  // eq. 3.12
  return phongTerms(N, L, C, diffuseColor, specularColor, power) * light.colorK.rgb * (A * F);
}

// Deferred lighting splits the terms: with unit colours the same expression yields the diffuse
// light (D * colour * A * F) and the specular light (S * colour * A * F) separately.
vec3 localDiffuseLight(Light light, vec3 worldPos, vec3 N, vec3 C, float power) {
  return localLightTerms(light, worldPos, N, C, vec3(1.0), vec3(0.0), power);
}
vec3 localSpecularLight(Light light, vec3 worldPos, vec3 N, vec3 C, float power) {
  return localLightTerms(light, worldPos, N, C, vec3(0.0), vec3(1.0), power);
}

#endif
