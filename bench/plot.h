// Line plots of frame time against a swept parameter, one curve per technique (the thesis's
// figures 4.1-4.12), written as SVG by hand and as PNG rasterised into an OpenImageIO ImageBuf.
#pragma once

#include <string>
#include <vector>

namespace parity::bench {

struct PlotPoint {
  double x = 0, y = 0;
  double lo = 0, hi = 0;  // spread drawn as a whisker (p25..p75); lo == hi: none
};

struct PlotSeries {
  std::string name;  // technique
  std::vector<PlotPoint> points;  // sorted by x
};

struct Plot {
  std::string title, xLabel, yLabel;
  std::vector<PlotSeries> series;
};

// Each curve is one <polyline class="curve" data-series="NAME">, so a reader (and the test) can
// count the curves.
std::string renderSvg(const Plot& plot, int width = 720, int height = 450);

// Atomic PNG (temporary file, then rename). Text is drawn where OpenImageIO finds a font;
// curves and axes are always drawn. False with "PATH: reason".
bool writePlotPng(const Plot& plot, const std::string& path, std::string* error, int width = 720, int height = 450);

}  // namespace parity::bench
