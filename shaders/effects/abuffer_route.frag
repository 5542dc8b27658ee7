#version 450
// Stencil routing set-up (Myers & Bavoil 2007; Ferko 2012 §4.1): drawn once per sample with
// only that sample in the coverage mask, so sample i's stencil gets its own value i + 2 (the
// pipeline's stencil op REPLACE with reference i + 2).
layout(push_constant, std430) uniform Route { uvec4 index; } route;  // x: the sample routed
void main() { gl_SampleMask[0] = int(1u << route.index.x); }
