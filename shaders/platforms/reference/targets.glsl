// Reference platform: no quirks. Rg16Unorm is RG32F and depth D32F; values pass unchanged.
vec4 parityWriteRg16(vec2 v) { return vec4(v, 0.0, 1.0); }
#define PARITY_RG16_SAMPLER sampler2D
vec2 parityReadRg16(vec4 texel) { return texel.xy; }
#define PARITY_DEPTH_SAMPLER sampler2D
#define PARITY_DEPTH_TEXEL vec4
float parityReadDepth(vec4 texel) { return texel.x; }
