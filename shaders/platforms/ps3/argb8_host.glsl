// PS3: host storage of an A8R8G8B8 surface, the one convention for packed16x2 colour and the
// depth-as-ARGB8 bitcast (platforms/ps3/remap.h, kHostChannelOfConsole): the RGBA8 texel's two
// 16-bit words are the console's 16-bit halves, little-endian, so host (r, g, b, a) hold
// console (R, A, B, G) and the host RG16 view is the Y16_X16 view.
#ifndef PARITY_PS3_ARGB8_HOST_GLSL
#define PARITY_PS3_ARGB8_HOST_GLSL
// Console channels [A, R, G, B] -> host texel (r, g, b, a).
vec4 parityPs3HostTexelOfArgb(vec4 argb) { return vec4(argb[1], argb[0], argb[3], argb[2]); }
// Host texel (r, g, b, a) -> console channels [A, R, G, B].
vec4 parityPs3ArgbOfHostTexel(vec4 host) { return vec4(host.g, host.r, host.a, host.b); }
#endif
