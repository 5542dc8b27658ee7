// EXPECT: image probes, buffer values, buffer comparisons, console memory bytes and images.
#include "harness/scripts/runner/steps.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <set>
#include <sstream>

#include "harness/compare/flip.h"

namespace parity::harness::script::runner {

ExpectResult ExpectSteps::probe(const Command& c) {
  ExpectResult e;
  e.line = c.loc.line;
  Resource& r = res_.at(c.buffer);
  std::ostringstream what;
  what << "line " << c.loc.line << ": EXPECT " << c.buffer << " IDX " << c.px << " " << c.py << " SIZE " << c.pw << " " << c.ph;
  if (r.logical)
    throw Failure{what.str() + ": LOGICAL image texels are platform-specific; read it in a shader or use MEMORY BYTES"};
  if (!r.texture && !(r.cpu && r.width > 0)) throw Failure{what.str() + ": '" + c.buffer + "' is not an image or framebuffer"};
  if (c.px + c.pw > r.width || c.py + c.ph > r.height)
    throw Failure{what.str() + ": outside the " + std::to_string(r.width) + "x" + std::to_string(r.height) + " image"};
  std::vector<uint8_t> px = contents(c.buffer);
  const Layout& L = r.def->type.layout;
  double tol[4];
  bool pct[4];
  for (int i = 0; i < 4; ++i) {
    if (c.tolerances.empty()) tol[i] = 0.002, pct[i] = false;
    else {
      const Tolerance& t = c.tolerances[c.tolerances.size() == 4 ? i : 0];
      tol[i] = t.percent ? t.value : t.value / 255.0;
      pct[i] = t.percent;
    }
  }
  uint32_t bad = 0;
  std::string first;
  for (uint32_t y = c.py; y < c.py + c.ph; ++y)
    for (uint32_t x = c.px; x < c.px + c.pw; ++x) {
      const uint8_t* t = px.data() + (size_t(y) * r.width + x) * L.stride;
      double actual[4] = {0, 0, 0, 1};
      bool has[4] = {false, false, false, false};
      for (const Field& f : L.fields) {
        int ch = f.channel == 'R' ? 0 : f.channel == 'G' ? 1 : f.channel == 'B' ? 2 : f.channel == 'A' ? 3 : 0;
        double v = readScalar(t + f.offset, f.scalar);
        if (f.mode == Mode::Unorm || f.mode == Mode::Srgb) v /= std::ldexp(1.0, int(scalarSize(f.scalar) * 8)) - 1;
        if (f.mode == Mode::Snorm) v /= std::ldexp(1.0, int(scalarSize(f.scalar) * 8 - 1)) - 1;
        if (f.mode == Mode::Srgb && ch != 3) v = srgbToLinear(v);
        actual[ch] = v;
        has[ch] = true;
      }
      bool ok = true;
      for (int i = 0; i < (c.rgba ? 4 : 3); ++i) {
        if (!has[i]) continue;
        double expected = c.color[i] / 255.0, diff = std::fabs(expected - actual[i]);
        if (pct[i] ? diff > tol[i] / 100.0 * std::fabs(actual[i]) : diff > tol[i]) ok = false;
      }
      if (ok) continue;
      if (bad++ == 0) {
        std::ostringstream s;
        bool scale = L.fields[0].mode == Mode::Unorm || L.fields[0].mode == Mode::Srgb;
        s << "first at (" << x << ", " << y << "): expected (";
        for (int i = 0; i < (c.rgba ? 4 : 3); ++i) s << (i ? ", " : "") << fmt(c.color[i]);
        s << "), got (";
        for (int i = 0; i < (c.rgba ? 4 : 3); ++i) s << (i ? ", " : "") << fmt(scale ? std::round(actual[i] * 255.0 * 1000) / 1000 : actual[i] * 255.0);
        s << ")";
        first = s.str();
      }
    }
  e.pass = bad == 0;
  e.message = what.str() + (bad ? ": " + std::to_string(bad) + " of " + std::to_string(c.pw * c.ph) + " pixels differ, " + first : ": ok");
  return e;
}

ExpectResult ExpectSteps::values(const Command& c) {
  ExpectResult e;
  e.line = c.loc.line;
  const Buffer* b = script_.findBuffer(c.buffer);
  const Layout& L = c.valueTypeGiven ? c.valueType.layout : b->type.layout;
  std::vector<uint8_t> bytes = contents(c.buffer);
  std::string what = "line " + std::to_string(c.loc.line) + ": EXPECT " + c.buffer + " IDX " + std::to_string(c.px);
  // A given value type reads its elements from byte px on; else px indexes the buffer's layout.
  size_t base = c.valueTypeGiven ? c.px : 0;
  size_t elem = c.valueTypeGiven ? 0 : c.px / L.stride, field = c.valueTypeGiven ? 0 : L.fields.size();
  for (size_t f = 0; f < L.fields.size() && !c.valueTypeGiven; ++f)
    if (L.fields[f].offset == c.px % L.stride) field = f;
  if (field == L.fields.size()) throw Failure{what + ": byte offset " + std::to_string(c.px) + " is not the start of a component"};
  for (size_t i = 0; i < c.values.size(); ++i) {
    const Field& f = L.fields[field];
    size_t off = base + elem * L.stride + f.offset;
    if (off + scalarSize(f.scalar) > bytes.size())
      throw Failure{what + ": value " + std::to_string(i) + " is past the end of the buffer (" + std::to_string(bytes.size()) + " bytes)"};
    double actual = readScalar(bytes.data() + off, f.scalar);
    const Value& v = c.values[i];
    double expected = v.d;
    bool ok = true;
    bool integer = isIntegerScalar(f.scalar);
    switch (c.comparator) {
      case Comparator::Eq: ok = integer ? actual == expected : std::fabs(actual - expected) <= 1e-6 * std::max(1.0, std::fabs(expected)); break;
      case Comparator::Ne: ok = integer ? actual != expected : std::fabs(actual - expected) > 1e-6 * std::max(1.0, std::fabs(expected)); break;
      case Comparator::Lt: ok = actual < expected; break;
      case Comparator::Le: ok = actual <= expected; break;
      case Comparator::Gt: ok = actual > expected; break;
      case Comparator::Ge: ok = actual >= expected; break;
      case Comparator::FuzzyEq: {
        const Tolerance& t = c.tolerances[0];
        double d = std::fabs(actual - expected);
        ok = t.percent ? d <= t.value / 100.0 * std::fabs(expected) : d <= t.value;
        break;
      }
    }
    if (!ok) {
      static const char* kOps[] = {"==", "!=", "<", "<=", ">", ">=", "~="};
      e.pass = false;
      e.message = what + ": value " + std::to_string(i) + " (byte " + std::to_string(off) + "): expected " +
                  kOps[int(c.comparator)] + " " + fmt(expected) + ", got " + fmt(actual);
      return e;
    }
    if (++field == L.fields.size()) field = 0, ++elem;
  }
  e.pass = true;
  e.message = what + ": ok";
  return e;
}

ExpectResult ExpectSteps::buffers(const Command& c) {
  ExpectResult e;
  e.line = c.loc.line;
  const Buffer* a = script_.findBuffer(c.buffer);
  const Buffer* b = script_.findBuffer(c.other);
  std::string what = "line " + std::to_string(c.loc.line) + ": EXPECT " + c.buffer + (c.emd ? " EQ_HISTOGRAM_EMD_BUFFER " : c.rmse ? " RMSE_BUFFER " : " EQ_BUFFER ") + c.other;
  std::vector<uint8_t> x = contents(c.buffer), y = contents(c.other);
  const Layout &La = a->type.layout, &Lb = b->type.layout;
  size_t na = x.size() / La.stride, nb = y.size() / Lb.stride;
  if (La.fields.size() != Lb.fields.size() || La.fields[0].scalar != Lb.fields[0].scalar)
    throw Failure{what + ": the buffers have different types (" + a->type.name + ", " + b->type.name + ")"};
  if (na != nb) {
    e.message = what + ": " + std::to_string(na) + " elements vs " + std::to_string(nb);
    return e;
  }
  double sum = 0;
  size_t n = 0;
  for (size_t i = 0; i < na; ++i)
    for (size_t f = 0; f < La.fields.size(); ++f) {
      double va = readScalar(x.data() + i * La.stride + La.fields[f].offset, La.fields[f].scalar);
      double vb = readScalar(y.data() + i * Lb.stride + Lb.fields[f].offset, Lb.fields[f].scalar);
      if (!c.rmse && !c.emd && va != vb) {
        e.message = what + ": element " + std::to_string(i) + " component " + std::to_string(f) + ": " + fmt(va) + " vs " + fmt(vb);
        return e;
      }
      sum += (va - vb) * (va - vb);
      ++n;
    }
  if (c.emd) {
    // Amber's EQ_HISTOGRAM_EMD_BUFFER: per channel, 256-bin histograms normalised by the
    // element count; EMD = sum |cumulative difference| / 256; the largest channel's EMD is
    // compared with the tolerance. 8-bit unorm only.
    if (La.fields[0].scalar != Scalar::Uint8) throw Unsupported{"EQ_HISTOGRAM_EMD_BUFFER on " + a->type.name};
    double worst = 0;
    for (size_t f = 0; f < La.fields.size(); ++f) {
      std::vector<double> ha(256, 0), hb(256, 0);
      for (size_t i = 0; i < na; ++i) {
        ha[x[i * La.stride + La.fields[f].offset]] += 1.0 / double(na);
        hb[y[i * Lb.stride + Lb.fields[f].offset]] += 1.0 / double(nb);
      }
      double cum = 0, emd = 0;
      for (int k = 0; k < 256; ++k) {
        cum += ha[k] - hb[k];
        emd += std::fabs(cum);
      }
      worst = std::max(worst, emd / 256.0);
    }
    e.pass = worst <= c.rmseTolerance;
    e.message = what + ": histogram EMD " + fmt(worst) + (e.pass ? " <= " : " > ") + fmt(c.rmseTolerance);
    return e;
  }
  if (c.rmse) {
    double rmse = n ? std::sqrt(sum / static_cast<double>(n)) : 0.0;
    // Allowance for the float rounding of the inputs (1.1f - 1.0f is 0.10000002).
    e.pass = rmse <= c.rmseTolerance + 1e-6;
    e.message = what + ": RMSE " + fmt(rmse) + (e.pass ? " <= " : " > ") + fmt(c.rmseTolerance);
    return e;
  }
  e.pass = true;
  e.message = what + ": ok";
  return e;
}

// Ours: the console memory bytes of a LOGICAL image (platforms::GpuTargets::consoleBytes), per
// pixel in the console's byte order; the expected bytes are one pixel's (every pixel of the
// rectangle must hold them) or every pixel's, row by row.
ExpectResult ExpectSteps::memory(const Command& c) {
  ExpectResult e;
  e.line = c.loc.line;
  Resource& r = res_.at(c.buffer);
  std::ostringstream what;
  what << "line " << c.loc.line << ": EXPECT " << c.buffer << " MEMORY BYTES" << (c.afterResolve ? " RESOLVED" : "") << " IDX "
       << c.px << " " << c.py << " SIZE " << c.pw << " " << c.ph << " on " << opts_.platform;
  if (c.px + c.pw > r.width || c.py + c.ph > r.height)
    throw Failure{what.str() + ": outside the " + std::to_string(r.width) + "x" + std::to_string(r.height) + " image"};
  std::vector<uint8_t> bytes = targets_->consoleBytes(c.buffer, c.afterResolve);
  size_t pixels = size_t(r.width) * r.height;
  size_t bpp = pixels ? bytes.size() / pixels : 0;
  bool perPixel = c.values.size() == bpp * c.pw * c.ph && c.values.size() != bpp;
  if (bpp == 0 || (c.values.size() != bpp && !perPixel))
    throw Failure{what.str() + ": " + std::to_string(c.values.size()) + " bytes given, a pixel holds " + std::to_string(bpp)};
  auto hex = [](const uint8_t* b, size_t n) {
    std::string s;
    char buf[8];
    for (size_t i = 0; i < n; ++i) std::snprintf(buf, sizeof(buf), "%s%02X", i ? " " : "", b[i]), s += buf;
    return s;
  };
  uint32_t bad = 0;
  std::string first;
  for (uint32_t y = c.py; y < c.py + c.ph; ++y)
    for (uint32_t x = c.px; x < c.px + c.pw; ++x) {
      const uint8_t* got = bytes.data() + (size_t(y) * r.width + x) * bpp;
      size_t k = perPixel ? (size_t(y - c.py) * c.pw + (x - c.px)) * bpp : 0;
      std::vector<uint8_t> want(bpp);
      for (size_t i = 0; i < bpp; ++i) want[i] = static_cast<uint8_t>(c.values[k + i].i);
      if (std::memcmp(got, want.data(), bpp) == 0) continue;
      if (bad++ == 0)
        first = "first at (" + std::to_string(x) + ", " + std::to_string(y) + "): expected " + hex(want.data(), bpp) + ", got " + hex(got, bpp);
    }
  e.pass = bad == 0;
  e.message = what.str() + (bad ? ": " + std::to_string(bad) + " of " + std::to_string(c.pw * c.ph) + " pixels differ, " + first : ": ok");
  return e;
}

// Ours: an RGBA8 image against a PNG: RMSE over all channels (0-255 units), the largest
// channel difference, and (FLIP t) the mean LDR-FLIP error (harness/compare/flip.h, 0..1).
ExpectResult ExpectSteps::image(const Command& c) {
  ExpectResult e;
  e.line = c.loc.line;
  std::string what = "line " + std::to_string(c.loc.line) + ": EXPECT " + c.buffer + " EQ_IMAGE " + c.imageFile;
  Resource& r = res_.at(c.buffer);
  const Layout& L = r.def->type.layout;
  if (L.stride != 4 || L.fields.size() != 4 || L.fields[0].scalar != Scalar::Uint8)
    throw Failure{what + ": EQ_IMAGE compares 8-bit RGBA images, '" + c.buffer + "' is " + r.def->type.name};
  std::vector<uint8_t> want;
  uint32_t w = 0, h = 0;
  std::string why;
  if (!loadPng(c.imageFile, &want, &w, &h, &why)) throw Failure{what + ": " + why};
  if (w != r.width || h != r.height) {
    e.message = what + ": reference is " + std::to_string(w) + "x" + std::to_string(h) + ", image is " +
                std::to_string(r.width) + "x" + std::to_string(r.height);
    return e;
  }
  std::vector<uint8_t> got = contents(c.buffer);  // R, G, B, A by channel name after toTextureBytes
  std::vector<uint8_t> rgba(got.size());
  for (size_t i = 0; i + 3 < got.size(); i += 4)
    for (const Field& f : L.fields) {
      int ch = f.channel == 'R' ? 0 : f.channel == 'G' ? 1 : f.channel == 'B' ? 2 : 3;
      rgba[i + size_t(ch)] = got[i + f.offset];
    }
  double sum = 0, worst = 0;
  for (size_t i = 0; i < rgba.size() && i < want.size(); ++i) {
    double d = std::fabs(double(rgba[i]) - double(want[i]));
    sum += d * d;
    worst = std::max(worst, d);
  }
  double rmse = rgba.empty() ? 0 : std::sqrt(sum / double(rgba.size()));
  // FLIP alone judges by FLIP; RMSE/MAX given with it still apply.
  bool flipOnly = c.imageFlip && !c.imageRmse && !c.imageMax;
  double rmseLimit = flipOnly ? 255 : c.imageRmse.value_or(0);
  double maxLimit = flipOnly ? 255 : c.imageMax.value_or(c.imageRmse ? 255 : 0);
  e.pass = rmse <= rmseLimit + 1e-9 && worst <= maxLimit;
  e.message = what + ": RMSE " + fmt(rmse) + " (limit " + fmt(rmseLimit) + "), max " + fmt(worst) + " (limit " + fmt(maxLimit) + ")";
  if (c.imageFlip) {
    OIIO::ImageSpec spec(int(w), int(h), 4, OIIO::TypeDesc::UINT8);
    OIIO::ImageBuf reference(spec, want.data()), test(spec, rgba.data());
    FlipResult flip = computeLdrFlip(reference, test);
    if (!flip.ok) throw Failure{what + ": FLIP: " + flip.error};
    e.pass = e.pass && flip.mean <= *c.imageFlip + 1e-12;
    e.message += ", FLIP mean " + fmt(flip.mean) + " (limit " + fmt(*c.imageFlip) + ")";
  }
  return e;
}

}  // namespace parity::harness::script::runner
