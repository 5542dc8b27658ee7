// DX10 (FL10.0): native R16G16_UNORM; depth read only through the single-sample R24X8 copy
// (D1), which the host keeps as R32_UINT holding the 24-bit word (X8 = 0).
vec4 parityWriteRg16(vec2 v) { return vec4(v, 0.0, 1.0); }
#define PARITY_RG16_SAMPLER sampler2D
vec2 parityReadRg16(vec4 texel) { return texel.xy; }
#define PARITY_DEPTH_SAMPLER usampler2D
#define PARITY_DEPTH_TEXEL uvec4
// R24_UNORM: D24 / 16777215.
float parityReadDepth(uvec4 texel) { return float(texel.x & 0xFFFFFFu) / 16777215.0; }
