// What the deferred techniques (deferred shading, light pre-pass) store per pixel in their
// geometry pass and how a later full-screen or light-volume pass gets it back.
//   normal          view space, half-sphere mapping (normal_encoding.glsl, eq. 1-3), in a
//                   logical Rg16Unorm target (written with parityWriteRg16)
//   specular power  p / 255 in an 8-bit unorm channel: every integer power up to 255 survives
//                   8-bit storage exactly (larger powers are clamped to 255)
//   position        not stored: reconstructed from the depth buffer and the pixel position with
//                   the inverse view-projection (thesis §3.1.4)
// Needs scene_data.glsl (the frame block) included before.
#ifndef PARITY_GBUFFER_GLSL
#define PARITY_GBUFFER_GLSL

#include "normal_encoding.glsl"
#include "parity_math.glsl"

float encodeSpecularPower(float power) { return clamp(power / 255.0, 0.0, 1.0); }
float decodeSpecularPower(float stored) { return stored * 255.0; }

// World-space unit normal -> the two stored channels (view space, so that the visible half of
// the sphere is the one the mapping keeps precise).
vec2 encodeWorldNormal(vec3 worldNormal) {
  vec3 viewNormal = mul(mat3(frame.view), worldNormal);
  return encodeNormalHalfSphere(viewNormal);
}

// The inverse: the view matrix is a rotation plus a translation, so its 3x3 inverse is the
// transpose. Normalised again so that the shading sees a unit vector as the forward shader does.
vec3 decodeWorldNormal(vec2 stored) {
  vec3 viewNormal = decodeNormalHalfSphere(stored);
  return normalize3(mul(transpose(mat3(frame.view)), viewNormal));
}

// Thesis §3.1.4: window x, y scaled to [0, 1], depth from the depth buffer, through the inverse
// of the view-projection and window transforms, divided by w. The rhi conventions (NDC y = -1
// is memory row 0 = gl_FragCoord.y 0.5, depth range [0, 1]) make NDC = window * 2 - 1 on both
// backends.
vec3 worldPositionFromDepth(vec2 fragCoord, vec2 targetSize, float depth) {
  vec2 ndc = fragCoord / targetSize * 2.0 - 1.0;
  vec4 p = mul(frame.invViewProj, vec4(ndc, depth, 1.0));
  return p.xyz / p.w;
}

#endif
