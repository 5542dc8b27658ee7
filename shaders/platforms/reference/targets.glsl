// Reference platform: no quirks. Rg16Unorm is RG32F and depth D32F; values pass unchanged.
vec4 parityWriteRg16(vec2 v) { return vec4(v, 0.0, 1.0); }
// Exact-write path: RG32F has no integer view and needs none (no conversion decides bits).
#define PARITY_RG16_BITS_TYPE vec4
vec4 parityWriteRg16Bits(vec2 v) { return vec4(v, 0.0, 1.0); }
#define PARITY_RG16_SAMPLER sampler2D
vec2 parityReadRg16(vec4 texel) { return texel.xy; }
#define PARITY_DEPTH_SAMPLER sampler2D
#define PARITY_DEPTH_ARRAY_SAMPLER sampler2DArray  // a layered depth target (shadow cube faces)
#define PARITY_DEPTH_TEXEL vec4
float parityReadDepth(vec4 texel) { return texel.x; }

// Rgba16Hdr (light accumulation): colour output for the attachment, and the logical value of a
// texel of its read texture. Additive blending must stay correct on the stored values, so a
// platform may only scale linearly here.
vec4 parityWriteRgba16Hdr(vec4 v) { return v; }
vec4 parityReadRgba16Hdr(vec4 texel) { return texel; }
