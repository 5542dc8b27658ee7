// DX10 (FL10.0): native R16G16_UNORM; depth read only through the single-sample R24X8 copy
// (D1), which the host keeps as R32_UINT holding the 24-bit word (X8 = 0).
// Writes: the shader rounds v * 65535 to nearest as the model does (round half up, in fp32
// without contraction). D3D10 hardware converts in the output merger instead (round to nearest
// even within 0.6 ULP), which can differ from the model at ties; GL and Vulkan drivers may
// differ as well (NVIDIA truncates: 0.001 -> 65), so the exact path stores the integer through an
// RG16_UINT view, and the blendable float path writes (k + 0.25) / 65535, which every
// conversion within 0.6 ULP (nearest, nearest-even, truncation) stores as k.
uvec2 parityDx10Unorm16(vec2 v) {
  precise vec2 t = clamp(v, 0.0, 1.0) * 65535.0 + 0.5;
  return uvec2(floor(t));
}
#define PARITY_RG16_BITS_TYPE uvec4
uvec4 parityWriteRg16Bits(vec2 v) { return uvec4(parityDx10Unorm16(v), 0u, 0u); }
vec4 parityWriteRg16(vec2 v) { return vec4((vec2(parityDx10Unorm16(v)) + 0.25) / 65535.0, 0.0, 1.0); }
#define PARITY_RG16_SAMPLER sampler2D
vec2 parityReadRg16(vec4 texel) { return texel.xy; }
#define PARITY_DEPTH_SAMPLER usampler2D
#define PARITY_DEPTH_ARRAY_SAMPLER usampler2DArray  // a layered depth target (shadow cube faces)
#define PARITY_DEPTH_TEXEL uvec4
// R24_UNORM: D24 / 16777215.
float parityReadDepth(uvec4 texel) { return float(texel.x & 0xFFFFFFu) / 16777215.0; }

// Rgba16Hdr (light accumulation): colour output for the attachment, and the logical value of a
// texel of its read texture. Additive blending must stay correct on the stored values, so a
// platform may only scale linearly here.
vec4 parityWriteRgba16Hdr(vec4 v) { return v; }
vec4 parityReadRgba16Hdr(vec4 texel) { return texel; }
