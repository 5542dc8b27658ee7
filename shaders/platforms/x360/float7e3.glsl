// Xenos k_2_10_10_10_FLOAT ("7e3", X2's 32-bpp HDR format): the conversions of the CPU model
// (platforms/x360/float7e3.cpp), bit for bit. RGB: 3 exponent bits (bias 3), 7 mantissa bits,
// denormals, [0, 31.875]; negative and NaN store 0; round to nearest, ties to even. Alpha: 2 bits.
#ifndef PARITY_X360_FLOAT7E3_GLSL
#define PARITY_X360_FLOAT7E3_GLSL
uint parityX360Encode7e3(float v) {
  uint f = floatBitsToUint(v);
  if (isnan(v) || (f & 0x80000000u) != 0u) return 0u;
  f = min(f, 0x41FF0000u);
  uint rebased;
  if (f < 0x3E800000u) {
    uint shift = 125u - (f >> 23);
    rebased = shift >= 32u ? 0u : (0x800000u | (f & 0x7FFFFFu)) >> shift;
  } else {
    rebased = f - 0x3E000000u;
  }
  return ((rebased + 0x7FFFu + ((rebased >> 16) & 1u)) >> 16) & 0x3FFu;
}
float parityX360Decode7e3(uint bits) {
  bits &= 0x3FFu;
  if (bits == 0u) return 0.0;
  uint mantissa = bits & 0x7Fu, exponent = bits >> 7;
  if (exponent == 0u) {  // denormal: normalise the mantissa
    int top = findMSB(mantissa);  // 0..6
    return uintBitsToFloat((uint(top + 118) << 23) | (((mantissa << (7 - top)) & 0x7Fu) << 16));
  }
  return uintBitsToFloat(((exponent + 124u) << 23) | (mantissa << 16));
}
// The value a k_2_10_10_10_FLOAT sample holds for a shader output (alpha at 2 bits).
vec4 parityX360Quantise7e3(vec4 v) {
  float a = isnan(v.a) ? 0.0 : clamp(v.a, 0.0, 1.0);
  return vec4(parityX360Decode7e3(parityX360Encode7e3(v.r)), parityX360Decode7e3(parityX360Encode7e3(v.g)),
              parityX360Decode7e3(parityX360Encode7e3(v.b)), float(uint(a * 3.0 + 0.5)) / 3.0);
}
#endif
