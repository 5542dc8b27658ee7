// Explicit-order arithmetic for every dot-product-based built-in.
//
// Why: the GL and Vulkan front ends expand mat*vec, dot, normalize and reflect in different
// floating-point orders (measured on Mesa: only 11.9% of RGBA32F pixels agree with the
// built-ins). Written out with explicit parentheses, as below, GL and Vulkan images are
// bit-identical, so any difference the harness reports is a real porting bug. Use these in
// every shader of the project instead of the built-ins.
//
// PARITY_PLAIN_BUILTINS maps them back to the built-ins; only the test that demonstrates the
// difference defines it.
#ifndef PARITY_MATH_GLSL
#define PARITY_MATH_GLSL

#ifdef PARITY_PLAIN_BUILTINS

float dot2(vec2 a, vec2 b) { return dot(a, b); }
float dot3(vec3 a, vec3 b) { return dot(a, b); }
float dot4(vec4 a, vec4 b) { return dot(a, b); }
vec4 mul(mat4 m, vec4 v) { return m * v; }
vec3 mul(mat3 m, vec3 v) { return m * v; }
mat4 mul(mat4 a, mat4 b) { return a * b; }
float length3(vec3 v) { return length(v); }
float distance3(vec3 a, vec3 b) { return distance(a, b); }
vec3 normalize3(vec3 v) { return normalize(v); }
vec3 reflect3(vec3 i, vec3 n) { return reflect(i, n); }
vec3 cross3(vec3 a, vec3 b) { return cross(a, b); }
vec3 faceforward3(vec3 n, vec3 i, vec3 nref) { return faceforward(n, i, nref); }

#else

float dot2(vec2 a, vec2 b) { return a.x * b.x + a.y * b.y; }
float dot3(vec3 a, vec3 b) { return (a.x * b.x + a.y * b.y) + a.z * b.z; }
float dot4(vec4 a, vec4 b) { return ((a.x * b.x + a.y * b.y) + a.z * b.z) + a.w * b.w; }
// Column-major, as GLSL: m[i] is column i.
vec4 mul(mat4 m, vec4 v) { return ((m[0] * v.x + m[1] * v.y) + m[2] * v.z) + m[3] * v.w; }
vec3 mul(mat3 m, vec3 v) { return (m[0] * v.x + m[1] * v.y) + m[2] * v.z; }
mat4 mul(mat4 a, mat4 b) { return mat4(mul(a, b[0]), mul(a, b[1]), mul(a, b[2]), mul(a, b[3])); }
float length3(vec3 v) { return sqrt(dot3(v, v)); }
float distance3(vec3 a, vec3 b) { return length3(a - b); }
vec3 normalize3(vec3 v) { return v * inversesqrt(dot3(v, v)); }
vec3 reflect3(vec3 i, vec3 n) { return i - (2.0 * dot3(n, i)) * n; }
vec3 cross3(vec3 a, vec3 b) {
  return vec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
vec3 faceforward3(vec3 n, vec3 i, vec3 nref) { return dot3(nref, i) < 0.0 ? n : -n; }

#endif
#endif
