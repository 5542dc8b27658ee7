#include "harness/compare/diagnosis.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>

namespace parity::harness {

namespace {

// RGB as floats in [0, 1], row 0 first (alpha plays no part: the porting bugs named here show
// in colour).
struct Rgb {
  int w = 0, h = 0;
  std::vector<float> v;
  float at(int x, int y, int c) const {
    x = std::clamp(x, 0, w - 1);
    y = std::clamp(y, 0, h - 1);
    return v[(static_cast<size_t>(y) * w + x) * 3 + c];
  }
};

Rgb toRgb(const OIIO::ImageBuf& img) {
  Rgb r;
  r.w = img.spec().width;
  r.h = img.spec().height;
  int n = img.spec().nchannels;
  std::vector<float> px(static_cast<size_t>(r.w) * r.h * n);
  img.get_pixels(OIIO::ROI(0, r.w, 0, r.h, 0, 1, 0, n), OIIO::TypeDesc::FLOAT, px.data());
  r.v.resize(static_cast<size_t>(r.w) * r.h * 3);
  for (size_t i = 0; i < static_cast<size_t>(r.w) * r.h; ++i)
    for (int c = 0; c < 3; ++c) r.v[i * 3 + c] = px[i * n + std::min(c, n - 1)];
  return r;
}

// The golden as the bug would have rendered it at (x, y, c); `t` is the render, for candidates
// that predict a range rather than one value (the closest value of the range to the render).
using PixelFn = std::function<float(const Rgb& g, const Rgb& t, int x, int y, int c)>;

struct Candidate {
  std::string cause;
  PixelFn apply;  // the golden as the bug would have rendered it
  // apply() predicts a range, not a value: its residual is never above a point candidate's
  // for the same bug, so it is considered only when no point candidate explains the render
  // (an averaged image is "half-pixel shift", not "in rasterisation").
  bool range = false;
};

float srgbEncode(float v) {
  v = std::clamp(v, 0.0f, 1.0f);
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}
float srgbDecode(float v) {
  v = std::clamp(v, 0.0f, 1.0f);
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

std::vector<Candidate> candidates() {
  std::vector<Candidate> list;
  list.push_back({"vertical flip", [](const Rgb& g, const Rgb&, int x, int y, int c) { return g.at(x, g.h - 1 - y, c); }});
  list.push_back({"horizontal flip", [](const Rgb& g, const Rgb&, int x, int y, int c) { return g.at(g.w - 1 - x, y, c); }});
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx) {
      if (dx == 0 && dy == 0) continue;
      list.push_back({"integer shift by (" + std::to_string(dx) + ", " + std::to_string(dy) + ") pixels",
                      [dx, dy](const Rgb& g, const Rgb&, int x, int y, int c) { return g.at(x - dx, y - dy, c); }});
    }
  // Sampling half a pixel off: each pixel is the average of two (or four) neighbours.
  for (int sy = -1; sy <= 1; ++sy)
    for (int sx = -1; sx <= 1; ++sx) {
      if (sx == 0 && sy == 0) continue;
      std::ostringstream name;
      name << "half-pixel shift by (" << sx * 0.5 << ", " << sy * 0.5 << ")";
      list.push_back({name.str(), [sx, sy](const Rgb& g, const Rgb&, int x, int y, int c) {
                        return 0.25f * (g.at(x, y, c) + g.at(x + sx, y, c) + g.at(x, y + sy, c) + g.at(x + sx, y + sy, c));
                      }});
    }
  list.push_back({"RGBA/BGRA swizzle", [](const Rgb& g, const Rgb&, int x, int y, int c) { return g.at(x, y, c == 1 ? 1 : 2 - c); }});
  list.push_back({"sRGB applied twice", [](const Rgb& g, const Rgb&, int x, int y, int c) { return srgbEncode(g.at(x, y, c)); }});
  list.push_back({"sRGB missing", [](const Rgb& g, const Rgb&, int x, int y, int c) { return srgbDecode(g.at(x, y, c)); }});
  for (int e = -5; e <= 5; ++e) {
    if (e == 0) continue;
    float k = std::ldexp(1.0f, e);
    std::string factor = e > 0 ? std::to_string(1 << e) : "1/" + std::to_string(1 << -e);
    list.push_back({"value range scaled x" + factor,
                    [k](const Rgb& g, const Rgb&, int x, int y, int c) { return std::clamp(g.at(x, y, c) * k, 0.0f, 1.0f); }});
  }
  list.push_back({"value range 0..1 vs -1..1 (written as x*0.5+0.5)",
                  [](const Rgb& g, const Rgb&, int x, int y, int c) { return g.at(x, y, c) * 0.5f + 0.5f; }});
  list.push_back({"value range 0..1 vs -1..1 (written as x*2-1)",
                  [](const Rgb& g, const Rgb&, int x, int y, int c) { return std::clamp(g.at(x, y, c) * 2.0f - 1.0f, 0.0f, 1.0f); }});
  // Lost low bits of 8-bit data: dropped (truncation) or requantised to fewer levels.
  for (int bits = 1; bits <= 6; ++bits) {
    std::string name = "precision loss of " + std::to_string(bits) + " bit" + (bits > 1 ? "s" : "");
    list.push_back({name, [bits](const Rgb& g, const Rgb&, int x, int y, int c) {
                      int v = static_cast<int>(std::lround(std::clamp(g.at(x, y, c), 0.0f, 1.0f) * 255.0f));
                      return static_cast<float>((v >> bits) << bits) / 255.0f;
                    }});
    list.push_back({name, [bits](const Rgb& g, const Rgb&, int x, int y, int c) {
                      float levels = static_cast<float>((1 << (8 - bits)) - 1);
                      float q = std::round(std::clamp(g.at(x, y, c), 0.0f, 1.0f) * levels) / levels;
                      return std::round(q * 255.0f) / 255.0f;
                    }});
  }
  // Rasterising half a pixel off (D3D9 pixel centres on a .5 host, or a half-pixel offset in
  // the vertex stage): each pixel samples the scene on the boundary between the golden's
  // neighbours, so it is one of them at a geometry edge and between them where shading is
  // smooth; the render is explained where it lies within their range.
  for (int sy = -1; sy <= 1; ++sy)
    for (int sx = -1; sx <= 1; ++sx) {
      if (sx == 0 && sy == 0) continue;
      std::ostringstream name;
      name << "half-pixel shift by (" << sx * 0.5 << ", " << sy * 0.5 << ") in rasterisation";
      list.push_back({name.str(), [sx, sy](const Rgb& g, const Rgb& t, int x, int y, int c) {
                        const float n[4] = {g.at(x, y, c), g.at(x + sx, y, c), g.at(x, y + sy, c), g.at(x + sx, y + sy, c)};
                        const float lo = *std::min_element(n, n + 4), hi = *std::max_element(n, n + 4);
                        const float slack = 0.25f * (hi - lo);
                        return std::clamp(t.at(x, y, c), lo - slack, hi + slack);
                      },
                      true});
    }
  return list;
}

// Differences under this (per channel) are rounding, not content.
constexpr float kSame = 2.5f / 255.0f;
// Pixels this far from the border decide: shifts bring unknown content in at the edges.
constexpr int kMargin = 3;

struct Score {
  double mean = 0;      // mean absolute difference over interior RGB
  size_t differ = 0;    // interior pixels with a channel over kSame
};

Score score(const Rgb& g, const Rgb& t, const PixelFn* fn) {
  Score s;
  size_t n = 0;
  for (int y = kMargin; y < g.h - kMargin; ++y)
    for (int x = kMargin; x < g.w - kMargin; ++x) {
      // A pixel the render did not change is no evidence against a candidate: a shader bug
      // touches only the pixels the shader writes, not those the frame's clear keeps.
      if (fn) {
        bool unchanged = true;
        for (int c = 0; c < 3; ++c) unchanged = unchanged && std::abs(g.at(x, y, c) - t.at(x, y, c)) <= kSame;
        if (unchanged) {
          n += 3;
          continue;
        }
      }
      float worst = 0;
      for (int c = 0; c < 3; ++c) {
        float d = std::abs((fn ? (*fn)(g, t, x, y, c) : g.at(x, y, c)) - t.at(x, y, c));
        s.mean += d;
        worst = std::max(worst, d);
      }
      s.differ += worst > kSame;
      n += 3;
    }
  if (n) s.mean /= static_cast<double>(n);
  return s;
}

}  // namespace

const std::vector<std::string>& diagnosisClasses() {
  static const std::vector<std::string> names = {
      "vertical flip",     "horizontal flip",    "integer shift", "half-pixel shift",    "RGBA/BGRA swizzle",
      "sRGB applied twice", "sRGB missing",      "value range",   "precision loss"};
  return names;
}

std::optional<Diagnosis> diagnose(const OIIO::ImageBuf& golden, const OIIO::ImageBuf& image) {
  if (golden.spec().width != image.spec().width || golden.spec().height != image.spec().height) return std::nullopt;
  Rgb g = toRgb(golden), t = toRgb(image);
  if (g.w <= 2 * kMargin || g.h <= 2 * kMargin) return std::nullopt;
  Score base = score(g, t, nullptr);
  if (base.differ == 0) return std::nullopt;
  // A range candidate fits any pixel that lies between its neighbours, which a handful of
  // changed pixels at edges always do: it needs the widespread change a shifted rasterisation
  // makes (every edge of the image), at least 1% of the pixels.
  const size_t interior = static_cast<size_t>(g.w - 2 * kMargin) * static_cast<size_t>(g.h - 2 * kMargin);
  const bool widespread = base.differ * 100 >= interior;
  std::optional<Diagnosis> best;
  for (const Candidate& c : candidates()) {
    if (c.range && (best || !widespread)) break;  // range candidates come last
    Score s = score(g, t, &c.apply);
    // It must explain nearly everything: almost no differing pixel left, and the remaining
    // difference a small fraction of the original. A regression confined to part of the image
    // leaves its pixels differing under every candidate.
    // Either almost every differing pixel is explained and most of the difference, or almost all
    // of the difference and all but a few pixels (shading that is not linear between
    // neighbours, e.g. a specular highlight under a half-pixel shift).
    bool explains = (s.differ * 50 <= base.differ && s.mean <= 0.2 * base.mean) ||
                    (s.differ * 20 <= base.differ && s.mean <= 0.05 * base.mean);
    if (!explains || (best && s.mean >= best->residual)) continue;
    Diagnosis d;
    d.cause = c.cause;
    d.baseline = base.mean;
    d.residual = s.mean;
    std::ostringstream detail;
    detail << "applying \"" << c.cause << "\" to the golden leaves " << s.differ << " of " << base.differ
           << " differing pixels (mean difference " << s.mean << " instead of " << base.mean << ")";
    d.detail = detail.str();
    best = d;
  }
  return best;
}

nlohmann::json toJson(const Diagnosis& d) {
  return {{"cause", d.cause}, {"detail", d.detail}, {"baseline_mean", d.baseline}, {"residual_mean", d.residual}};
}

}  // namespace parity::harness
