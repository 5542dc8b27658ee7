#include "bench/plot.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "harness/run/report_sections.h"

namespace fs = std::filesystem;

namespace parity::bench {

namespace {

constexpr std::array<std::array<int, 3>, 10> kPalette = {{{31, 119, 180}, {255, 127, 14}, {44, 160, 44}, {214, 39, 40},
                                                          {148, 103, 189}, {140, 86, 75}, {227, 119, 194}, {127, 127, 127},
                                                          {188, 189, 34}, {23, 190, 207}}};

std::string hexColor(size_t i) {
  const auto& c = kPalette[i % kPalette.size()];
  char buf[8];
  std::snprintf(buf, sizeof(buf), "#%02x%02x%02x", c[0], c[1], c[2]);
  return buf;
}


// "Nice" tick step (1, 2 or 5 times a power of ten) for about `count` ticks over [lo, hi].
double tickStep(double lo, double hi, int count) {
  double span = std::max(hi - lo, 1e-12);
  double raw = span / count;
  double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (raw <= m * p) return m * p;
  return 10 * p;
}

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%g", std::fabs(v) < 1e-12 ? 0.0 : v);
  return buf;
}

// Data bounds and the mapping to the plot area of a width x height canvas.
struct Frame {
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  double left = 70, right = 190, top = 40, bottom = 55;
  int width = 720, height = 450;
  double px(double x) const { return left + (x - x0) / (x1 - x0) * (width - left - right); }
  double py(double y) const { return height - bottom - (y - y0) / (y1 - y0) * (height - top - bottom); }
};

Frame frameFor(const Plot& plot, int width, int height) {
  Frame f;
  f.width = width;
  f.height = height;
  bool any = false;
  double xmin = 0, xmax = 1, ymax = 1;
  for (const PlotSeries& s : plot.series)
    for (const PlotPoint& p : s.points) {
      if (!any) {
        xmin = xmax = p.x;
        ymax = std::max(p.y, p.hi);
        any = true;
      }
      xmin = std::min(xmin, p.x);
      xmax = std::max(xmax, p.x);
      ymax = std::max({ymax, p.y, p.hi});
    }
  if (xmax <= xmin) xmax = xmin + 1;
  if (ymax <= 0) ymax = 1;
  // Frame time axes start at zero, as the thesis's do, so slopes compare by eye.
  f.x0 = xmin;
  f.x1 = xmax;
  f.y0 = 0;
  f.y1 = ymax * 1.08;
  return f;
}

}  // namespace

std::string renderSvg(const Plot& plot, int width, int height) {
  const Frame f = frameFor(plot, width, height);
  std::string s;
  s += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(width) + "\" height=\"" + std::to_string(height) +
       "\" viewBox=\"0 0 " + std::to_string(width) + " " + std::to_string(height) + "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  s += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  s += "<text x=\"" + num(width / 2.0) + "\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">" + harness::report::xmlEscape(plot.title) + "</text>\n";
  // Axes and ticks.
  const double ax0 = f.px(f.x0), ax1 = f.px(f.x1), ay0 = f.py(f.y0), ay1 = f.py(f.y1);
  s += "<g stroke=\"#222\" fill=\"none\"><line x1=\"" + num(ax0) + "\" y1=\"" + num(ay0) + "\" x2=\"" + num(ax1) + "\" y2=\"" +
       num(ay0) + "\"/><line x1=\"" + num(ax0) + "\" y1=\"" + num(ay0) + "\" x2=\"" + num(ax0) + "\" y2=\"" + num(ay1) + "\"/></g>\n";
  const double xs = tickStep(f.x0, f.x1, 8), ys = tickStep(f.y0, f.y1, 6);
  for (double x = std::ceil(f.x0 / xs) * xs; x <= f.x1 + 1e-9; x += xs)
    s += "<line x1=\"" + num(f.px(x)) + "\" y1=\"" + num(ay0) + "\" x2=\"" + num(f.px(x)) + "\" y2=\"" + num(ay0 + 5) +
         "\" stroke=\"#222\"/><text x=\"" + num(f.px(x)) + "\" y=\"" + num(ay0 + 18) + "\" text-anchor=\"middle\">" + num(x) + "</text>\n";
  for (double y = 0; y <= f.y1 + 1e-9; y += ys)
    s += "<line x1=\"" + num(ax0 - 5) + "\" y1=\"" + num(f.py(y)) + "\" x2=\"" + num(ax1) + "\" y2=\"" + num(f.py(y)) +
         "\" stroke=\"#ddd\"/><text x=\"" + num(ax0 - 8) + "\" y=\"" + num(f.py(y) + 4) + "\" text-anchor=\"end\">" + num(y) + "</text>\n";
  s += "<text x=\"" + num((ax0 + ax1) / 2) + "\" y=\"" + num(height - 12) + "\" text-anchor=\"middle\">" + harness::report::xmlEscape(plot.xLabel) + "</text>\n";
  s += "<text transform=\"translate(16," + num((ay0 + ay1) / 2) + ") rotate(-90)\" text-anchor=\"middle\">" + harness::report::xmlEscape(plot.yLabel) +
       "</text>\n";
  // Curves, whiskers and legend.
  for (size_t i = 0; i < plot.series.size(); ++i) {
    const PlotSeries& series = plot.series[i];
    const std::string color = hexColor(i);
    std::string pts;
    for (const PlotPoint& p : series.points) pts += num(f.px(p.x)) + "," + num(f.py(p.y)) + " ";
    s += "<polyline class=\"curve\" data-series=\"" + harness::report::xmlEscape(series.name) + "\" fill=\"none\" stroke=\"" + color +
         "\" stroke-width=\"2\" points=\"" + pts + "\"/>\n";
    for (const PlotPoint& p : series.points) {
      s += "<circle cx=\"" + num(f.px(p.x)) + "\" cy=\"" + num(f.py(p.y)) + "\" r=\"3\" fill=\"" + color + "\"/>";
      if (p.hi > p.lo)
        s += "<line x1=\"" + num(f.px(p.x)) + "\" y1=\"" + num(f.py(p.lo)) + "\" x2=\"" + num(f.px(p.x)) + "\" y2=\"" +
             num(f.py(p.hi)) + "\" stroke=\"" + color + "\"/>";
    }
    s += "\n";
    const double ly = f.top + 10 + 20.0 * static_cast<double>(i);
    s += "<line x1=\"" + num(width - f.right + 15) + "\" y1=\"" + num(ly) + "\" x2=\"" + num(width - f.right + 40) + "\" y2=\"" +
         num(ly) + "\" stroke=\"" + color + "\" stroke-width=\"2\"/><text x=\"" + num(width - f.right + 46) + "\" y=\"" +
         num(ly + 4) + "\">" + harness::report::xmlEscape(series.name) + "</text>\n";
  }
  s += "</svg>\n";
  return s;
}

bool writePlotPng(const Plot& plot, const std::string& path, std::string* error, int width, int height) {
  const Frame f = frameFor(plot, width, height);
  OIIO::ImageBuf img(OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::UINT8));
  const float white[3] = {1, 1, 1}, ink[3] = {0.13f, 0.13f, 0.13f}, grid[3] = {0.87f, 0.87f, 0.87f};
  OIIO::ImageBufAlgo::fill(img, white);
  auto ix = [&](double x) { return static_cast<int>(std::lround(f.px(x))); };
  auto iy = [&](double y) { return static_cast<int>(std::lround(f.py(y))); };
  const double ys = tickStep(f.y0, f.y1, 6), xs = tickStep(f.x0, f.x1, 8);
  // Text needs a font OIIO can find; without one the plot is still complete as lines.
  auto text = [&](int x, int y, const std::string& t, int size, OIIO::ImageBufAlgo::TextAlignX align) {
    if (!OIIO::ImageBufAlgo::render_text(img, x, y, t, size, "DejaVuSans", ink, align)) (void)img.geterror();
  };
  for (double y = 0; y <= f.y1 + 1e-9; y += ys) {
    OIIO::ImageBufAlgo::render_line(img, ix(f.x0) - 5, iy(y), ix(f.x1), iy(y), grid);
    text(ix(f.x0) - 8, iy(y) + 4, num(y), 12, OIIO::ImageBufAlgo::TextAlignX::Right);
  }
  for (double x = std::ceil(f.x0 / xs) * xs; x <= f.x1 + 1e-9; x += xs) {
    OIIO::ImageBufAlgo::render_line(img, ix(x), iy(f.y0), ix(x), iy(f.y0) + 5, ink);
    text(ix(x), iy(f.y0) + 18, num(x), 12, OIIO::ImageBufAlgo::TextAlignX::Center);
  }
  OIIO::ImageBufAlgo::render_line(img, ix(f.x0), iy(f.y0), ix(f.x1), iy(f.y0), ink);
  OIIO::ImageBufAlgo::render_line(img, ix(f.x0), iy(f.y0), ix(f.x0), iy(f.y1), ink);
  text(width / 2, 22, plot.title, 15, OIIO::ImageBufAlgo::TextAlignX::Center);
  text(static_cast<int>((f.px(f.x0) + f.px(f.x1)) / 2), height - 12, plot.xLabel, 12, OIIO::ImageBufAlgo::TextAlignX::Center);
  text(8, static_cast<int>(f.top) - 8, plot.yLabel, 12, OIIO::ImageBufAlgo::TextAlignX::Left);
  for (size_t i = 0; i < plot.series.size(); ++i) {
    const auto& c = kPalette[i % kPalette.size()];
    const float color[3] = {c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f};
    const auto& pts = plot.series[i].points;
    for (size_t k = 0; k < pts.size(); ++k) {
      // Two pixels wide, like the SVG's stroke.
      if (k > 0)
        for (int d = 0; d < 2; ++d)
          OIIO::ImageBufAlgo::render_line(img, ix(pts[k - 1].x), iy(pts[k - 1].y) + d, ix(pts[k].x), iy(pts[k].y) + d, color);
      OIIO::ImageBufAlgo::render_box(img, ix(pts[k].x) - 2, iy(pts[k].y) - 2, ix(pts[k].x) + 2, iy(pts[k].y) + 2, color, true);
      if (pts[k].hi > pts[k].lo) OIIO::ImageBufAlgo::render_line(img, ix(pts[k].x), iy(pts[k].lo), ix(pts[k].x), iy(pts[k].hi), color);
    }
    const int ly = static_cast<int>(f.top + 10 + 20.0 * static_cast<double>(i));
    const int lx = static_cast<int>(width - f.right + 15);
    OIIO::ImageBufAlgo::render_box(img, lx, ly - 1, lx + 25, ly + 1, color, true);
    text(lx + 31, ly + 4, plot.series[i].name, 12, OIIO::ImageBufAlgo::TextAlignX::Left);
  }
  fs::path target(path);
  std::error_code ec;
  if (target.has_parent_path()) fs::create_directories(target.parent_path(), ec);
  fs::path tmp = target.parent_path() / (".tmp-" + target.filename().string());  // keeps .png for OIIO's format choice
  if (!img.write(tmp.string())) {
    *error = path + ": cannot write PNG (" + img.geterror() + ")";
    fs::remove(tmp, ec);
    return false;
  }
  fs::rename(tmp, target, ec);
  if (ec) {
    *error = path + ": cannot replace (" + ec.message() + ")";
    return false;
  }
  return true;
}

}  // namespace parity::bench
