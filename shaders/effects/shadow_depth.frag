#version 450
// Depth only: the shadow map keeps the nearest occluder's depth, no colour is written.
void main() {}
