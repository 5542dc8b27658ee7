#include "platforms/ps3/surface.h"

namespace parity::platforms::ps3 {

std::string_view formatName(SurfaceColorFormat format) {
  switch (format) {
    case SurfaceColorFormat::X1R5G5B5_Z1R5G5B5: return "X1R5G5B5_Z1R5G5B5";
    case SurfaceColorFormat::X1R5G5B5_O1R5G5B5: return "X1R5G5B5_O1R5G5B5";
    case SurfaceColorFormat::R5G6B5: return "R5G6B5";
    case SurfaceColorFormat::X8R8G8B8_Z8R8G8B8: return "X8R8G8B8_Z8R8G8B8";
    case SurfaceColorFormat::X8R8G8B8_O8R8G8B8: return "X8R8G8B8_O8R8G8B8";
    case SurfaceColorFormat::A8R8G8B8: return "A8R8G8B8";
    case SurfaceColorFormat::B8: return "B8";
    case SurfaceColorFormat::G8B8: return "G8B8";
    case SurfaceColorFormat::F_W16Z16Y16X16: return "F_W16Z16Y16X16";
    case SurfaceColorFormat::F_W32Z32Y32X32: return "F_W32Z32Y32X32";
    case SurfaceColorFormat::F_X32: return "F_X32";
    case SurfaceColorFormat::X8B8G8R8_Z8B8G8R8: return "X8B8G8R8_Z8B8G8R8";
    case SurfaceColorFormat::X8B8G8R8_O8B8G8R8: return "X8B8G8R8_O8B8G8R8";
    case SurfaceColorFormat::A8B8G8R8: return "A8B8G8R8";
  }
  return "?";
}

uint32_t bytesPerPixel(SurfaceColorFormat format) {
  switch (format) {
    case SurfaceColorFormat::B8: return 1;
    case SurfaceColorFormat::G8B8:
    case SurfaceColorFormat::R5G6B5:
    case SurfaceColorFormat::X1R5G5B5_Z1R5G5B5:
    case SurfaceColorFormat::X1R5G5B5_O1R5G5B5: return 2;
    case SurfaceColorFormat::F_W16Z16Y16X16: return 8;
    case SurfaceColorFormat::F_W32Z32Y32X32: return 16;
    default: return 4;  // all 8888 formats and F_X32
  }
}

std::optional<ColorSurface> requestColorSurface(const SurfaceRequest& r, DiagnosticList& out) {
  ColorSurface s;
  s.name = r.name;
  if (r.channels == 2 && r.bitsPerChannel == 16) {
    if (r.allowPacking && !r.isFloat) {
      // P2: an ARGB8 surface with two 16-bit values packed into its four bytes.
      s.format = SurfaceColorFormat::A8R8G8B8;
      s.packed16x2 = true;
      return s;
    }
    out.report("E_RSX_NO_RG16_SURFACE", {r.name},
               r.name + " asks for a two-channel 16-bit " + (r.isFloat ? "float" : "unorm") +
                   " colour surface; RSX has none (P1). Pack two 16-bit unorm values into A8R8G8B8 (P2)");
    return std::nullopt;
  }
  if (r.channels == 4 && r.bitsPerChannel == 8 && !r.isFloat) s.format = SurfaceColorFormat::A8R8G8B8;
  else if (r.channels == 4 && r.bitsPerChannel == 16 && r.isFloat) s.format = SurfaceColorFormat::F_W16Z16Y16X16;
  else if (r.channels == 4 && r.bitsPerChannel == 32 && r.isFloat) s.format = SurfaceColorFormat::F_W32Z32Y32X32;
  else if (r.channels == 1 && r.bitsPerChannel == 32 && r.isFloat) s.format = SurfaceColorFormat::F_X32;
  else if (r.channels == 1 && r.bitsPerChannel == 8 && !r.isFloat) s.format = SurfaceColorFormat::B8;
  else if (r.channels == 2 && r.bitsPerChannel == 8 && !r.isFloat) s.format = SurfaceColorFormat::G8B8;
  else return std::nullopt;
  return s;
}

void checkMrt(std::string_view pass, std::span<const ColorSurface> targets, Ps3MrtRule rule, DiagnosticList& out) {
  if (targets.empty()) return;
  const ColorSurface& first = targets[0];
  for (std::size_t i = 1; i < targets.size(); ++i) {
    const ColorSurface& t = targets[i];
    if (rule == Ps3MrtRule::SameFormat && t.format != first.format) {
      out.report("E_MRT_FORMAT_MISMATCH", {first.name, t.name},
                 std::string(pass) + " binds " + first.name + " (" + std::string(formatName(first.format)) + ") and " +
                     t.name + " (" + std::string(formatName(t.format)) +
                     "); SET_SURFACE_FORMAT has one colour format for every target (P1)");
    } else if (rule == Ps3MrtRule::SameBpp && bytesPerPixel(t.format) != bytesPerPixel(first.format)) {
      out.report("E_MRT_BPP_MISMATCH", {first.name, t.name},
                 std::string(pass) + " binds " + first.name + " (" + std::to_string(bytesPerPixel(first.format) * 8) +
                     " bpp) and " + t.name + " (" + std::to_string(bytesPerPixel(t.format) * 8) +
                     " bpp); all targets must have the same bits per pixel (P1)");
    }
  }
  checkSharedBlend(pass, targets, out);
}

void checkSharedBlend(std::string_view pass, std::span<const ColorSurface> targets, DiagnosticList& out) {
  const ColorSurface* blended = nullptr;
  for (const ColorSurface& t : targets) {
    if (!t.blend.enabled) continue;
    if (!blended) {
      blended = &t;
      continue;
    }
    BlendState a = blended->blend, b = t.blend;
    if (a != b) {
      out.report("W_MRT_SHARED_BLEND", {blended->name, t.name},
                 std::string(pass) + ": " + blended->name + " and " + t.name +
                     " ask for different blend functions; RSX applies one function to all targets (P1)");
    }
  }
}

}  // namespace parity::platforms::ps3
