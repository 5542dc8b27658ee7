// 24-bit depth words from a sampled D24 depth value.
//
// A D24 depth texel samples as d = D24 / 16777215 (fp32). D24 = round(d * 2^24 - d): d * 2^24
// is exact, and for every D24 whose quotient is correctly rounded the difference rounds back to
// D24 (checked exhaustively on the CPU), whereas round(d * 16777215) is off for about a third
// of them.
#ifndef PARITY_DEPTH24_GLSL
#define PARITY_DEPTH24_GLSL
uint parityDepthToD24(float d) {
  precise float x = clamp(d, 0.0, 1.0) * 16777216.0;
  precise float y = x - clamp(d, 0.0, 1.0);
  return uint(roundEven(y));
}
#endif
