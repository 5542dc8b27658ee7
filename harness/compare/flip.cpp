#include "harness/compare/flip.h"

#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "harness/io/image_io.h"

namespace parity::harness {

namespace {

using Vec3 = std::array<double, 3>;

// The paper's constants (section 4): colour and feature exponents, error redistribution, and
// the peak-to-trough width of the human edge detector in degrees.
constexpr double kQc = 0.7, kQf = 0.5, kPc = 0.4, kPt = 0.95, kEdgeWidth = 0.082;

double srgbToLinear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

Vec3 linearRgbToXyz(const Vec3& c) {
  return {(10135552.0 / 24577794.0) * c[0] + (8788810.0 / 24577794.0) * c[1] + (4435075.0 / 24577794.0) * c[2],
          (2613072.0 / 12288897.0) * c[0] + (8788810.0 / 12288897.0) * c[1] + (887015.0 / 12288897.0) * c[2],
          (1425312.0 / 73733382.0) * c[0] + (8788810.0 / 73733382.0) * c[1] + (70074185.0 / 73733382.0) * c[2]};
}

Vec3 xyzToLinearRgb(const Vec3& c) {
  return {3.241003275 * c[0] - 1.537398934 * c[1] - 0.498615861 * c[2],
          -0.969224334 * c[0] + 1.875930071 * c[1] + 0.041554224 * c[2],
          0.055639423 * c[0] - 0.204011202 * c[1] + 1.057148933 * c[2]};
}

// D65 white of the sRGB primaries: XYZ of linear (1, 1, 1).
const Vec3& whitePoint() {
  static const Vec3 w = linearRgbToXyz({1.0, 1.0, 1.0});
  return w;
}

// YCxCz: the linearised opponent space in which the contrast sensitivity filters apply.
Vec3 xyzToYcxcz(const Vec3& c) {
  const Vec3& w = whitePoint();
  double x = c[0] / w[0], y = c[1] / w[1], z = c[2] / w[2];
  return {116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)};
}

Vec3 ycxczToXyz(const Vec3& c) {
  const Vec3& w = whitePoint();
  double y = (c[0] + 16.0) / 116.0;
  return {(y + c[1] / 500.0) * w[0], y * w[1], (y - c[2] / 200.0) * w[2]};
}

Vec3 xyzToLab(const Vec3& c) {
  const Vec3& w = whitePoint();
  constexpr double delta = 6.0 / 29.0;
  constexpr double deltaCube = delta * delta * delta;
  constexpr double factor = 1.0 / (3.0 * delta * delta);
  auto f = [&](double v) { return v > deltaCube ? std::cbrt(v) : factor * v + 4.0 / 29.0; };
  double x = f(c[0] / w[0]), y = f(c[1] / w[1]), z = f(c[2] / w[2]);
  return {116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)};
}

// Hunt effect: chroma scaled with lightness.
Vec3 hunt(const Vec3& lab) { return {lab[0], 0.01 * lab[0] * lab[1], 0.01 * lab[0] * lab[2]}; }

double hyab(const Vec3& a, const Vec3& b) {
  return std::abs(a[0] - b[0]) + std::hypot(a[1] - b[1], a[2] - b[2]);
}

// One plane of doubles with edge-clamped separable correlation.
struct Plane {
  int w = 0, h = 0;
  std::vector<double> v;
  Plane(int width, int height) : w(width), h(height), v(static_cast<size_t>(width) * height, 0.0) {}
  double& at(int x, int y) { return v[static_cast<size_t>(y) * w + x]; }
  double at(int x, int y) const { return v[static_cast<size_t>(y) * w + x]; }
};

// kx along x, then ky along y; both of odd length centred on the pixel.
Plane separable(const Plane& in, const std::vector<double>& kx, const std::vector<double>& ky) {
  int rx = static_cast<int>(kx.size() / 2), ry = static_cast<int>(ky.size() / 2);
  Plane tmp(in.w, in.h), out(in.w, in.h);
  for (int y = 0; y < in.h; ++y)
    for (int x = 0; x < in.w; ++x) {
      double s = 0;
      for (int i = -rx; i <= rx; ++i) s += kx[i + rx] * in.at(std::clamp(x + i, 0, in.w - 1), y);
      tmp.at(x, y) = s;
    }
  for (int y = 0; y < in.h; ++y)
    for (int x = 0; x < in.w; ++x) {
      double s = 0;
      for (int i = -ry; i <= ry; ++i) s += ky[i + ry] * tmp.at(x, std::clamp(y + i, 0, in.h - 1));
      out.at(x, y) = s;
    }
  return out;
}

// Contrast sensitivity of one opponent channel as a sum of (at most) two Gaussians in the
// frequency domain, i.e. two spatial Gaussians; each is separable, and the pair is normalised
// so the 2D kernel sums to one.
struct Csf {
  double a1, b1, a2, b2;
};
constexpr Csf kCsfAchromatic{1.0, 0.0047, 0.0, 1e-5}, kCsfRedGreen{1.0, 0.0053, 0.0, 1e-5},
    kCsfBlueYellow{34.1, 0.04, 13.5, 0.025};

Plane csfFilter(const Plane& in, const Csf& csf, int radius, double ppd) {
  double dx = 1.0 / ppd;
  const double pi2 = std::numbers::pi * std::numbers::pi;
  std::vector<double> g1(2 * radius + 1), g2(2 * radius + 1);
  double s1 = 0, s2 = 0;
  for (int i = -radius; i <= radius; ++i) {
    double d2 = (i * dx) * (i * dx);
    g1[i + radius] = std::exp(-pi2 * d2 / csf.b1);
    g2[i + radius] = std::exp(-pi2 * d2 / csf.b2);
    s1 += g1[i + radius];
    s2 += g2[i + radius];
  }
  double w1 = csf.a1 * std::sqrt(std::numbers::pi / csf.b1), w2 = csf.a2 * std::sqrt(std::numbers::pi / csf.b2);
  double total = w1 * s1 * s1 + w2 * s2 * s2;  // sum of the 2D kernel
  Plane out = separable(in, g1, g1);
  if (w2 == 0.0) {
    for (double& v : out.v) v *= w1 / total;
    return out;
  }
  Plane second = separable(in, g2, g2);
  for (size_t i = 0; i < out.v.size(); ++i) out.v[i] = (w1 * out.v[i] + w2 * second.v[i]) / total;
  return out;
}

// Edge (first derivative of a Gaussian) or point (second derivative) detector along x, with
// positive and negative weights normalised to sum to +1 and -1, and the smoothing Gaussian
// across, normalised to sum to 1.
void featureKernels(double ppd, bool point, std::vector<double>* across, std::vector<double>* along) {
  double sd = 0.5 * kEdgeWidth * ppd;
  int radius = static_cast<int>(std::ceil(3.0 * sd));
  across->assign(2 * radius + 1, 0.0);
  along->assign(2 * radius + 1, 0.0);
  double gsum = 0, pos = 0, neg = 0;
  for (int i = -radius; i <= radius; ++i) {
    double g = std::exp(-(i * i) / (2.0 * sd * sd));
    (*across)[i + radius] = g;
    gsum += g;
    double f = point ? (i * i / (sd * sd) - 1.0) * g : -i * g;
    (*along)[i + radius] = f;
    if (f > 0) pos += f;
    else neg -= f;
  }
  for (double& v : *across) v /= gsum;
  for (double& v : *along) v = v > 0 ? v / pos : v / neg;
}

// Per pixel the length of the (x, y) response of a detector.
Plane featureMagnitude(const Plane& y, double ppd, bool point) {
  std::vector<double> across, along;
  featureKernels(ppd, point, &across, &along);
  Plane fx = separable(y, along, across);
  Plane fy = separable(y, across, along);
  for (size_t i = 0; i < fx.v.size(); ++i) fx.v[i] = std::hypot(fx.v[i], fy.v[i]);
  return fx;
}

// The image as three planes of YCxCz, from sRGB-encoded values clamped to [0, 1].
std::array<Plane, 3> toYcxcz(const OIIO::ImageBuf& img) {
  int w = img.spec().width, h = img.spec().height, n = img.spec().nchannels;
  std::vector<float> px(static_cast<size_t>(w) * h * n);
  img.get_pixels(OIIO::ROI(0, w, 0, h, 0, 1, 0, n), OIIO::TypeDesc::FLOAT, px.data());
  std::array<Plane, 3> out{Plane(w, h), Plane(w, h), Plane(w, h)};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float* p = &px[(static_cast<size_t>(y) * w + x) * n];
      Vec3 rgb;
      for (int c = 0; c < 3; ++c) rgb[c] = srgbToLinear(std::clamp(static_cast<double>(p[n >= 3 ? c : 0]), 0.0, 1.0));
      Vec3 v = xyzToYcxcz(linearRgbToXyz(rgb));
      for (int c = 0; c < 3; ++c) out[c].at(x, y) = v[c];
    }
  return out;
}

}  // namespace

double flipDefaultPixelsPerDegree() { return 0.7 * 3840.0 / 0.7 * std::numbers::pi / 180.0; }

double flipWeightedPercentile(std::vector<float> values, double share) {
  std::sort(values.begin(), values.end());
  double total = 0;
  for (float v : values) total += v;
  double running = 0;
  for (float v : values) {
    running += v;
    if (running > share * total) return v;
  }
  return values.empty() ? 0.0 : values.back();
}

FlipResult computeLdrFlip(const OIIO::ImageBuf& reference, const OIIO::ImageBuf& test, double ppd) {
  FlipResult r;
  const OIIO::ImageSpec& a = reference.spec();
  const OIIO::ImageSpec& b = test.spec();
  if (a.width != b.width || a.height != b.height) {
    r.error = "images differ in size: " + std::to_string(a.width) + "x" + std::to_string(a.height) + " versus " +
              std::to_string(b.width) + "x" + std::to_string(b.height);
    return r;
  }
  if (a.width <= 0 || a.height <= 0 || a.nchannels <= 0 || b.nchannels <= 0) {
    r.error = "empty image";
    return r;
  }
  r.width = a.width;
  r.height = a.height;
  r.pixelsPerDegree = ppd;
  std::array<Plane, 3> ref = toYcxcz(reference), tst = toYcxcz(test);

  // Colour pipeline: CSF filtering in YCxCz, back to linear RGB clamped to the RGB cube, then
  // HyAB distance in Hunt-adjusted L*a*b*, redistributed so that pc * cmax maps to pt.
  double maxScale = std::max({kCsfAchromatic.b1, kCsfAchromatic.b2, kCsfRedGreen.b1, kCsfRedGreen.b2,
                              kCsfBlueYellow.b1, kCsfBlueYellow.b2});
  int radius = static_cast<int>(std::ceil(3.0 * std::sqrt(maxScale / (2.0 * std::numbers::pi * std::numbers::pi)) * ppd));
  auto filtered = [&](const std::array<Plane, 3>& img) {
    return std::array<Plane, 3>{csfFilter(img[0], kCsfAchromatic, radius, ppd), csfFilter(img[1], kCsfRedGreen, radius, ppd),
                                csfFilter(img[2], kCsfBlueYellow, radius, ppd)};
  };
  std::array<Plane, 3> fr = filtered(ref), ft = filtered(tst);
  auto labAt = [](const std::array<Plane, 3>& img, size_t i) {
    Vec3 rgb = xyzToLinearRgb(ycxczToXyz({img[0].v[i], img[1].v[i], img[2].v[i]}));
    for (double& c : rgb) c = std::clamp(c, 0.0, 1.0);
    return hunt(xyzToLab(linearRgbToXyz(rgb)));
  };
  double cmax = std::pow(hyab(hunt(xyzToLab(linearRgbToXyz({0, 1, 0}))), hunt(xyzToLab(linearRgbToXyz({0, 0, 1})))), kQc);
  double pccmax = kPc * cmax;

  // Feature pipeline on the unfiltered, normalised achromatic channel.
  Plane yr = ref[0], yt = tst[0];
  for (double& v : yr.v) v = (v + 16.0) / 116.0;
  for (double& v : yt.v) v = (v + 16.0) / 116.0;
  Plane er = featureMagnitude(yr, ppd, false), et = featureMagnitude(yt, ppd, false);
  Plane pr = featureMagnitude(yr, ppd, true), pt = featureMagnitude(yt, ppd, true);

  size_t n = static_cast<size_t>(r.width) * r.height;
  r.errorMap.resize(n);
  double sum = 0;
  r.min = 1.0;
  r.max = 0.0;
  for (size_t i = 0; i < n; ++i) {
    double dc = std::pow(hyab(labAt(fr, i), labAt(ft, i)), kQc);
    dc = dc < pccmax ? kPt / pccmax * dc : kPt + (dc - pccmax) / (cmax - pccmax) * (1.0 - kPt);
    double df = std::max(std::abs(er.v[i] - et.v[i]), std::abs(pt.v[i] - pr.v[i]));
    df = std::pow(df / std::numbers::sqrt2, kQf);
    double e = std::pow(dc, 1.0 - df);
    r.errorMap[i] = static_cast<float>(e);
    sum += e;
    r.min = std::min(r.min, e);
    r.max = std::max(r.max, e);
  }
  r.mean = sum / static_cast<double>(n);
  r.weightedQuartile1 = flipWeightedPercentile(r.errorMap, 0.25);
  r.weightedMedian = flipWeightedPercentile(r.errorMap, 0.5);
  r.weightedQuartile3 = flipWeightedPercentile(r.errorMap, 0.75);
  r.ok = true;
  return r;
}

bool writeFlipMap(const FlipResult& result, const std::string& path, std::string* error) {
  OIIO::ImageSpec spec(result.width, result.height, 1, OIIO::TypeDesc::FLOAT);
  OIIO::ImageBuf map(spec);
  map.set_pixels(OIIO::ROI(0, result.width, 0, result.height, 0, 1, 0, 1), OIIO::TypeDesc::FLOAT, result.errorMap.data());
  OIIO::ImageBuf coloured = OIIO::ImageBufAlgo::color_map(map, 0, "magma");
  if (coloured.has_error()) {
    *error = path + ": cannot build the FLIP map: " + coloured.geterror();
    return false;
  }
  return writeImage(path, coloured, error);
}

nlohmann::json toJson(const FlipResult& r) {
  if (!r.ok) return {{"error", r.error}};
  return {{"mean", r.mean},
          {"weighted_quartile_1", r.weightedQuartile1},
          {"weighted_median", r.weightedMedian},
          {"weighted_quartile_3", r.weightedQuartile3},
          {"min", r.min},
          {"max", r.max},
          {"pixels_per_degree", r.pixelsPerDegree}};
}

}  // namespace parity::harness
