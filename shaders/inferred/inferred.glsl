// Shared by the inferred-lighting shaders (techniques/inferred/inferred.cpp mirrors the block).
#ifndef PARITY_INFERRED_GLSL
#define PARITY_INFERRED_GLSL

layout(set = 0, binding = 3, std140) uniform InferredParams {
  vec4 sizes;  // xy output size, zw L-buffer (and G-buffer) size, in pixels
  vec4 dsf;    // x: relative linear-depth threshold of the DSF match
} inferred;

// The DSF ID (§3.1): object ID in the upper 8 bits, normal-group ID in the lower 8, stored as a
// 16-bit unorm value.
uint dsfId(uint objectId, uint normalGroup) { return ((objectId & 255u) << 8) | (normalGroup & 255u); }
float dsfIdToUnorm(uint id) { return float(id) / 65535.0; }
uint dsfIdFromUnorm(float v) { return uint(clamp(v, 0.0, 1.0) * 65535.0 + 0.5); }

// Luminance (Rec. 709) of a light colour: the specular intensity the L-buffer's alpha holds.
float lightLuminance(vec3 c) { return (0.2126 * c.r + 0.7152 * c.g) + 0.0722 * c.b; }

#endif
