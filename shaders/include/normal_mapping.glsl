// Tangent-space normal maps without per-vertex tangents: the tangent frame is built per pixel
// from the screen-space derivatives of position and texture coordinates (a cotangent frame,
// Schüler 2013), so the 32-byte vertex layout stays as it is. Every geometry pass that shades
// or stores a normal gets it from shadingNormal(), so all techniques see the same normal.
//
// Convention (glTF; scene::Material::normalTexture): RGB = n * 0.5 + 0.5 with +x along +u and
// +y towards the image's top row, which is -v here (v = 0 is row 0), and +z along the surface
// normal. OBJ texture coordinates are flipped on load to the same convention.
//
// Needs scene_data.glsl (the material block) included before.
#ifndef PARITY_NORMAL_MAPPING_GLSL
#define PARITY_NORMAL_MAPPING_GLSL

#include "parity_math.glsl"

// scene::kNormalMapBinding: bound by SceneGpu::drawMesh() for every mesh (a flat 1x1 texture
// when the material has no normal map).
layout(set = 0, binding = 10) uniform sampler2D normalMap;

// The unit normal to shade with at `position` (any space, the same as `interpolatedNormal`'s),
// texture coordinates `uv`. Without a normal map exactly normalize3(interpolatedNormal), so
// materials without one render as before. Call it in uniform control flow (before any
// discard): it takes derivatives.
vec3 shadingNormal(vec3 interpolatedNormal, vec3 position, vec2 uv) {
  vec3 N = normalize3(interpolatedNormal);
  if ((material.flags.x & MATERIAL_NORMAL_MAP) == 0u) return N;
  vec3 dpdx = dFdx(position);
  vec3 dpdy = dFdy(position);
  vec2 duvdx = dFdx(uv);
  vec2 duvdy = dFdy(uv);
  // The gradients of u and v in the plane perpendicular to N (T ~ grad u, B ~ grad v: along
  // dp/du and dp/dv, mirrored mappings included), scaled together so that their relative
  // lengths (a stretched mapping) are kept. Each is a solution of grad . dp = duv divided by
  // cross(dpdx, dpdy) . N; only its sign matters here, and it is negative for front faces
  // because window y grows downwards (rhi.h conventions), positive for back faces.
  vec3 dpdyPerp = cross3(dpdy, N);
  vec3 dpdxPerp = cross3(N, dpdx);
  vec3 T = dpdyPerp * duvdx.x + dpdxPerp * duvdy.x;
  vec3 B = dpdyPerp * duvdx.y + dpdxPerp * duvdy.y;
  if (dot3(cross3(dpdx, dpdy), N) < 0.0) {
    T = -T;
    B = -B;
  }
  float lengthSquared = max(dot3(T, T), dot3(B, B));
  if (!(lengthSquared > 0.0)) return N;  // no texture-coordinate variation: no frame
  float invLength = inversesqrt(lengthSquared);
  vec3 t = texture(normalMap, uv).rgb * 2.0 - 1.0;
  // +y of the map is -v (towards the top row).
  vec3 n = (T * (t.x * invLength) - B * (t.y * invLength)) + N * t.z;
  float nn = dot3(n, n);
  return nn > 0.0 ? n * inversesqrt(nn) : N;
}

#endif
