// RSX MSAA surface layout (P5, the contrast to Xenos in X1).
//
// An anti-aliased RSX surface is stored as a wider (and, for 4 samples, taller) surface:
// aa_factor_u = 2 for any AA mode, aa_factor_v = 2 only for the 4-sample modes
// (RSXThread.cpp L1346-1348), and a sample sits at x + y*2 inside its 2x1 or 2x2 block
// (ColorResolvePass.glsl L27-33). So RSX 2x is horizontal where Xenos 2x is vertical.
#pragma once

#include <cstdint>

namespace parity::platforms::ps3 {

// CELL_GCM_SURFACE_* anti-aliasing modes (gcm_enums.h L928-931).
enum class AntiAliasMode : uint8_t {
  Center1 = 0,
  DiagonalCentered2 = 3,
  SquareCentered4 = 4,
  SquareRotated4 = 5,
};

uint32_t sampleCount(AntiAliasMode mode);
uint32_t aaFactorU(AntiAliasMode mode);
uint32_t aaFactorV(AntiAliasMode mode);

struct MemoryTexel {
  uint32_t x = 0, y = 0;
};

// The memory texel holding sample `sample` of pixel (x, y).
MemoryTexel rsxSampleTexel(AntiAliasMode mode, uint32_t x, uint32_t y, uint32_t sample);

}  // namespace parity::platforms::ps3
