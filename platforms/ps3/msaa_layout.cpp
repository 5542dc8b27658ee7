#include "platforms/ps3/msaa_layout.h"

namespace parity::platforms::ps3 {

uint32_t sampleCount(AntiAliasMode mode) {
  switch (mode) {
    case AntiAliasMode::Center1: return 1;
    case AntiAliasMode::DiagonalCentered2: return 2;
    case AntiAliasMode::SquareCentered4:
    case AntiAliasMode::SquareRotated4: return 4;
  }
  return 1;
}

uint32_t aaFactorU(AntiAliasMode mode) { return mode == AntiAliasMode::Center1 ? 1 : 2; }

uint32_t aaFactorV(AntiAliasMode mode) { return sampleCount(mode) == 4 ? 2 : 1; }

MemoryTexel rsxSampleTexel(AntiAliasMode mode, uint32_t x, uint32_t y, uint32_t sample) {
  // sample_index = x + y*2 inside the block.
  const uint32_t u = aaFactorU(mode);
  const uint32_t v = aaFactorV(mode);
  return {x * u + sample % 2, y * v + (v == 2 ? sample / 2 : 0)};
}

}  // namespace parity::platforms::ps3
