// View-space normal <-> two channels, the half-sphere mapping of the inferred lighting paper
// (Kircher & Lawrance 2009, §2.1, eq. 1-3). Shared by every technique that stores normals in a
// two-channel 16-bit target (logical Rg16Unorm, resolved by the platform layer).
//
// Right-handed view space, camera looking down -z: visible surfaces have n.z > -1. Eq. 1 rotates
// the sphere onto the half sphere z >= 0 by the half-way vector to +z, so no sign bit is needed;
// only n'.xy is stored, remapped from [-1, 1] to the unorm range [0, 1].
#ifndef PARITY_NORMAL_ENCODING_GLSL
#define PARITY_NORMAL_ENCODING_GLSL

#include "parity_math.glsl"

// Eq. 1: n' = (n + (0, 0, 1)) / |n + (0, 0, 1)|, stored as n'.xy * 0.5 + 0.5.
vec2 encodeNormalHalfSphere(vec3 n) {
  vec3 h = normalize3(n + vec3(0.0, 0.0, 1.0));
  return h.xy * 0.5 + 0.5;
}

// Eq. 2-3: z = sqrt(1 - |n'.xy|^2), n = (2 z n'x, 2 z n'y, 2 z^2 - 1).
vec3 decodeNormalHalfSphere(vec2 e) {
  vec2 h = e * 2.0 - 1.0;
  float z = sqrt(max(0.0, 1.0 - dot2(h, h)));
  return vec3(2.0 * z * h.x, 2.0 * z * h.y, 2.0 * z * z - 1.0);
}

#endif
