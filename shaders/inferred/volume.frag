#version 450
// Stencil marks only: no colour is written (write mask 0).
layout(location = 0) out vec4 outColor;
void main() { outColor = vec4(0.0); }
