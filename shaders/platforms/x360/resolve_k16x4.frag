#version 450
// Xbox 360 resolve of a k_16_16_16_16 surface (the Rgba16Hdr light buffer) into a signed
// k_16_16_16_16 texture with no averaging and no exponent bias: the raw int16 is kept (X3, the
// signed-resolve parameter's default). EDRAM host storage: RGBA32F s * 2^-15, possibly the sum of
// several blended writes, so the encode's clamp to [0x8001, 0x7FFF] is applied here. Output:
// RGBA32F float(s), the host stand-in for the 16-bit signed texture.
layout(binding = 0) uniform sampler2D uEdram;
layout(location = 0) out vec4 oWords;
void main() {
  vec4 f = texelFetch(uEdram, ivec2(gl_FragCoord.xy), 0);
  oWords = clamp(roundEven(f * 32768.0), vec4(-32767.0), vec4(32767.0));
}
