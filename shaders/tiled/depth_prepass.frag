#version 450
// Depth pre-pass of tiled forward shading: the depth buffer for the forward pass's EQUAL test and
// the same depth in a float target the light culling compute pass reads.
layout(location = 0) out float outDepth;

void main() { outDepth = gl_FragCoord.z; }
