#version 450
// One triangle covering the target at the far plane (depth 1). Drawn with depth test GREATER
// against the scene's depth it reaches exactly the pixels the geometry pass covered: cleared
// pixels hold 1, which 1 does not exceed.
void main() {
  vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
  gl_Position = vec4(p * 2.0 - 1.0, 1.0, 1.0);
}
