// X2's 32-bpp HDR format, k_2_10_10_10_FLOAT (platforms/x360/float7e3.h): the conversion vectors.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "platforms/x360/float7e3.h"

using namespace parity::platforms::x360;

namespace {

TEST(X360Float7e3, EncodeVectors) {
  EXPECT_EQ(encodeFloat7e3(0.0f), 0u);
  EXPECT_EQ(encodeFloat7e3(-0.0f), 0u);
  EXPECT_EQ(encodeFloat7e3(-1.0f), 0u);  // unsigned: negatives store 0
  EXPECT_EQ(encodeFloat7e3(std::numeric_limits<float>::quiet_NaN()), 0u);
  EXPECT_EQ(encodeFloat7e3(1.0f), 0x180u);        // exponent 3 (bias 3), mantissa 0
  EXPECT_EQ(encodeFloat7e3(0.25f), 0x080u);       // the smallest normal
  EXPECT_EQ(encodeFloat7e3(0.125f), 0x040u);      // a denormal: 64 x 2^-9
  EXPECT_EQ(encodeFloat7e3(std::ldexp(1.0f, -9)), 0x001u);  // the smallest denormal
  EXPECT_EQ(encodeFloat7e3(31.875f), 0x3FFu);     // the largest value
  EXPECT_EQ(encodeFloat7e3(1000.0f), 0x3FFu);     // saturates
  EXPECT_EQ(encodeFloat7e3(std::numeric_limits<float>::infinity()), 0x3FFu);
  // Ties round to the even mantissa: 1 + 1/256 lies halfway between 1 and 1 + 1/128.
  EXPECT_EQ(encodeFloat7e3(1.0f + 1.0f / 256.0f), 0x180u);
  EXPECT_EQ(encodeFloat7e3(1.0f + 3.0f / 256.0f), 0x182u);
  EXPECT_EQ(encodeFloat7e3(std::ldexp(1.0f, -10)), 0x000u);      // half the smallest denormal: to 0
  EXPECT_EQ(encodeFloat7e3(std::ldexp(3.0f, -10)), 0x002u);      // 1.5 denormal steps: to 2
  EXPECT_EQ(encodeFloat7e3(0.2499f), 0x080u);                    // rounds up into the normals
}

TEST(X360Float7e3, EveryCodeDecodesAndEncodesBack) {
  float previous = -1.0f;
  for (uint32_t code = 0; code < 1024; ++code) {
    const float v = decodeFloat7e3(code);
    EXPECT_GT(v, previous) << code;  // strictly increasing: no two codes share a value
    EXPECT_EQ(encodeFloat7e3(v), code) << code;
    previous = v;
  }
  EXPECT_EQ(decodeFloat7e3(0x3FF), kFloat7e3Max);
  EXPECT_EQ(decodeFloat7e3(0x001), std::ldexp(1.0f, -9));
  EXPECT_EQ(decodeFloat7e3(0x07F), 127.0f * std::ldexp(1.0f, -9));  // the largest denormal
}

TEST(X360Float7e3, WordLayout) {
  const uint32_t word = packFloat7e3x3Unorm2({1.0f, 0.25f, 31.875f, 1.0f});
  EXPECT_EQ(word, 0x180u | 0x080u << 10 | 0x3FFu << 20 | 3u << 30);
  const auto back = unpackFloat7e3x3Unorm2(word);
  EXPECT_EQ(back[0], 1.0f);
  EXPECT_EQ(back[1], 0.25f);
  EXPECT_EQ(back[2], 31.875f);
  EXPECT_EQ(back[3], 1.0f);
  EXPECT_EQ(encodeUnorm2(0.5f), 2u);  // 1.5 rounds up
  EXPECT_EQ(encodeUnorm2(0.1f), 0u);
}

}  // namespace
