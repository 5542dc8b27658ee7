// Xenos k_16_16 fixed point, range -32...32 (X2), evaluated in the same fp32 order as the CPU
// model (platforms/x360/fixed16.cpp): c' = c * 2^bias; NaN -> 0; clamp to [-32, 32];
// s = trunc(c' * 32767/32 + (c' < 0 ? -0.5 : 0.5)) (round half away from zero).
#ifndef PARITY_X360_FIXED16_GLSL
#define PARITY_X360_FIXED16_GLSL
int parityX360EncodeFixed16(float v, int expBias) {
  precise float c = v * exp2(float(expBias));
  if (isnan(c)) c = 0.0;
  c = clamp(c, -32.0, 32.0);
  precise float t = c * 1023.96875 + (c < 0.0 ? -0.5 : 0.5);
  return int(trunc(t));
}
// s * 32 / 32767, unclamped (0x8000 gives -32.000977).
float parityX360DecodeFixed16(uint raw16) {
  int s = int(raw16 << 16) >> 16;
  precise float f = float(s) * 32.0;
  return f / 32767.0;
}
#endif
