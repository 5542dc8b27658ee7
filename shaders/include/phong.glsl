// The Phong model of the forward-vs-deferred thesis, §3.1.2, equations 3.5–3.12.
#ifndef PARITY_PHONG_GLSL
#define PARITY_PHONG_GLSL
#include "parity_math.glsl"

// (RGB_D * D + RGB_S * S) for light incidence vector L (from the light to the surface).
vec3 phongTerms(vec3 N, vec3 L, vec3 C, vec3 diffuseColor, vec3 specularColor, float power) {
  float D = clamp(dot3(N, -L), 0.0, 1.0);                       // eq. 3.9
  vec3 R = reflect3(L, N);
  float S = D > 0.0 ? pow(clamp(dot3(R, C), 0.0, 1.0), power) : 0.0;  // eq. 3.10
  return diffuseColor * D + specularColor * S;
}

// Attenuation, eq. 3.11, A = 1 / (1 + d^2), with the distance measured in units of 1/k (k = 2 /
// radius, scene::Light::attenuationK), times a window (1 - (d/radius)^4)^2 that
// takes it smoothly to 0 at the radius, so that a light volume of that radius bounds the light
// exactly (deferred techniques draw those volumes).
float attenuation(float d, float k, float radius) {
  if (d >= radius) return 0.0;
  float kd = k * d;
  float x = d / radius;
  float x2 = x * x;
  float w = 1.0 - x2 * x2;
  return (w * w) / (1.0 + kd * kd);
}

// Spot factor, eq. 3.12, clamped to [0, 1].
float spotFactor(vec3 spotDir, vec3 L, float cosOuter, float cosInner) {
  float cosS = dot3(spotDir, L);
  return clamp((cosOuter - cosS) / (cosOuter - cosInner), 0.0, 1.0);
}

#endif
