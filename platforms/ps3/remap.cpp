#include "platforms/ps3/remap.h"

#include <cstdio>
#include <string>

namespace parity::platforms::ps3 {

uint32_t makeRemap(RemapOrder order, RemapFrom inA, RemapFrom inR, RemapFrom inG, RemapFrom inB, RemapOut outA,
                   RemapOut outR, RemapOut outG, RemapOut outB) {
  return uint32_t(inA) | uint32_t(inR) << 2 | uint32_t(inG) << 4 | uint32_t(inB) << 6 | uint32_t(outA) << 8 |
         uint32_t(outR) << 10 | uint32_t(outG) << 12 | uint32_t(outB) << 14 | uint32_t(order) << 16;
}

int remapSource(uint32_t remap, int out) {
  uint32_t control = (remap >> (8 + 2 * out)) & 3u;
  if (control == uint32_t(RemapOut::Zero) || control == uint32_t(RemapOut::One)) return -1;
  return static_cast<int>((remap >> (2 * out)) & 3u);
}

Argb applyRemap(uint32_t remap, const Argb& in) {
  Argb out{};
  for (int o = 0; o < 4; ++o) {
    uint32_t control = (remap >> (8 + 2 * o)) & 3u;
    if (control == uint32_t(RemapOut::Zero)) out[o] = 0.0f;
    else if (control == uint32_t(RemapOut::One)) out[o] = 1.0f;
    else out[o] = in[(remap >> (2 * o)) & 3u];
  }
  return out;
}

std::array<uint8_t, 4> hostTexelOfArgb8(const Argb8Bytes& console) {
  std::array<uint8_t, 4> host{};
  for (int c = 0; c < 4; ++c) host[kHostChannelOfConsole[c]] = console[c];
  return host;
}

Argb8Bytes argb8OfHostTexel(const std::array<uint8_t, 4>& host) {
  Argb8Bytes console{};
  for (int c = 0; c < 4; ++c) console[c] = host[kHostChannelOfConsole[c]];
  return console;
}

namespace {
// Console write-mask bit of each channel [A, R, G, B] (packed16.h kWriteA, kWriteR, kWriteG, kWriteB).
constexpr uint8_t kConsoleMaskBit[4] = {8, 1, 2, 4};
}  // namespace

uint8_t consoleWriteMaskOfHost(uint8_t hostMask) {
  uint8_t m = 0;
  for (int c = 0; c < 4; ++c)
    if (hostMask & (1u << kHostChannelOfConsole[c])) m |= kConsoleMaskBit[c];
  return m;
}

uint8_t hostWriteMaskOfConsole(uint8_t consoleMask) {
  uint8_t m = 0;
  for (int c = 0; c < 4; ++c)
    if (consoleMask & kConsoleMaskBit[c]) m |= uint8_t(1u << kHostChannelOfConsole[c]);
  return m;
}

Rgba toRgba(const Argb& argb) { return Rgba{argb[kR], argb[kG], argb[kB], argb[kA]}; }

std::optional<uint32_t> rewriteY16X16Remap(uint32_t remap, std::string_view texture, DiagnosticList* out) {
  const bool xxxy = (remap >> 16) & 1u;
  uint32_t low = remap & 0xFFu;
  uint32_t rewritten;
  switch (low) {
    case 0xE4: rewritten = xxxy ? 0x56 : 0x66; break;
    case 0x4E: rewritten = xxxy ? 0xA9 : 0x99; break;
    case 0xEE: rewritten = 0xAA; break;
    case 0x44: rewritten = 0x55; break;
    default: {
      if (out) {
        char hex[8];
        std::snprintf(hex, sizeof hex, "0x%02X", static_cast<unsigned>(low));
        out->report("E_Y16X16_REMAP_INVALID", {std::string(texture)},
                    std::string(texture) + " is read as Y16_X16 with remap low byte " + hex +
                        "; only 0xE4, 0x4E, 0xEE and 0x44 are valid, others crash the system (P2)");
      }
      return std::nullopt;
    }
  }
  return (remap & ~0xFFu) | rewritten;
}

}  // namespace parity::platforms::ps3
