#version 450
// Depth pre-pass (Trebilco §"Light Indexed Deferred Rendering", pass 1). Besides the depth buffer
// it keeps the window-space depth in a float colour target: the light volume pass reads the
// surface depth there while the depth buffer is attached for its depth test (a texture cannot be
// sampled and attached in the same pass).
layout(location = 0) out float outDepth;

void main() { outDepth = gl_FragCoord.z; }
