#include "harness/compare/flip.h"

#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <exception>
#include <memory>
#include <numbers>
#include <system_error>
#include <thread>

#include "harness/compare/flip_filter.h"
#include "harness/io/image_io.h"

namespace parity::harness {

namespace {

using Vec3 = std::array<double, 3>;

// The paper's constants (section 4): colour and feature exponents, error redistribution, and
// the peak-to-trough width of the human edge detector in degrees.
constexpr double kQc = 0.7, kQf = 0.5, kPc = 0.4, kPt = 0.95, kEdgeWidth = 0.082;

double srgbToLinear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

constexpr Vec3 linearRgbToXyz(const Vec3& c) {
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
constexpr Vec3 kWhite = linearRgbToXyz({1.0, 1.0, 1.0});

// YCxCz: the linearised opponent space in which the contrast sensitivity filters apply.
Vec3 xyzToYcxcz(const Vec3& c) {
  double x = c[0] / kWhite[0], y = c[1] / kWhite[1], z = c[2] / kWhite[2];
  return {116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)};
}

Vec3 ycxczToXyz(const Vec3& c) {
  double y = (c[0] + 16.0) / 116.0;
  return {(y + c[1] / 500.0) * kWhite[0], y * kWhite[1], (y - c[2] / 200.0) * kWhite[2]};
}

// The cube root of v > 0: a first guess from the exponent bits (within a few percent), then three
// Halley steps, each cubing the relative error: within a few ulps of std::cbrt, and the
// evaluation takes 8% less time with it (six roots a pixel).
double cubeRoot(double v) {
  double y = std::bit_cast<double>(std::bit_cast<uint64_t>(v) / 3 + 0x2a9f7893782da1ceull);
  for (int i = 0; i < 3; ++i) {
    double y3 = y * y * y;
    y *= (y3 + 2.0 * v) / (2.0 * y3 + v);
  }
  return y;
}

Vec3 xyzToLab(const Vec3& c) {
  constexpr double delta = 6.0 / 29.0;
  constexpr double deltaCube = delta * delta * delta;
  constexpr double factor = 1.0 / (3.0 * delta * delta);
  auto f = [&](double v) { return v > deltaCube ? cubeRoot(v) : factor * v + 4.0 / 29.0; };
  double x = f(c[0] / kWhite[0]), y = f(c[1] / kWhite[1]), z = f(c[2] / kWhite[2]);
  return {116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)};
}

// Hunt effect: chroma scaled with lightness.
Vec3 hunt(const Vec3& lab) { return {lab[0], 0.01 * lab[0] * lab[1], 0.01 * lab[0] * lab[2]}; }

// A CSF-filtered YCxCz colour back to linear RGB clamped to the RGB cube, then Hunt-adjusted L*a*b*.
Vec3 filteredToHuntLab(const Vec3& ycxcz) {
  Vec3 rgb = xyzToLinearRgb(ycxczToXyz(ycxcz));
  for (double& c : rgb) c = std::clamp(c, 0.0, 1.0);
  return hunt(xyzToLab(linearRgbToXyz(rgb)));
}

double hyab(const Vec3& a, const Vec3& b) {
  double da = a[1] - b[1], db = a[2] - b[2];
  return std::abs(a[0] - b[0]) + std::sqrt(da * da + db * db);  // hypot's overflow care is not needed here
}

using flip::Kernel;

// The half i >= 0 of a kernel given for offsets -r..r.
Kernel halfOf(const std::vector<double>& full, Kernel::Kind kind) {
  int r = static_cast<int>(full.size() / 2);
  return Kernel(std::vector<double>(full.begin() + r, full.end()), kind);
}

// Contrast sensitivity of one opponent channel as a sum of (at most) two Gaussians in the
// frequency domain, i.e. two spatial Gaussians; each is separable, and the pair is normalised
// so the 2D kernel sums to one.
struct Csf {
  double a1, b1, a2, b2;
};
constexpr Csf kCsfAchromatic{1.0, 0.0047, 0.0, 1e-5}, kCsfRedGreen{1.0, 0.0053, 0.0, 1e-5},
    kCsfBlueYellow{34.1, 0.04, 13.5, 0.025};

// The channel's two separable Gaussians (unnormalised) and the weight of each 2D product.
struct CsfKernels {
  Kernel g1, g2;
  double weight1 = 0, weight2 = 0;  // weight2 == 0: one Gaussian only
};

CsfKernels csfKernels(const Csf& csf, int radius, double ppd) {
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
  return {halfOf(g1, Kernel::Symmetric), halfOf(g2, Kernel::Symmetric), w1 / total, w2 / total};
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

// One image's rows as linear RGB, each channel clamped to [0, 1] first; a grey image's first
// channel stands for all three. Rows are read in the band's own thread.
class LinearRows {
 public:
  explicit LinearRows(const OIIO::ImageBuf& image)
      : image_(image),
        channels_(image.spec().nchannels >= 3 ? 3 : 1),
        bytes_(image.spec().format == OIIO::TypeDesc::UINT8) {
    if (bytes_) byteRow_.resize(static_cast<size_t>(image.spec().width) * channels_);
    else floatRow_.resize(static_cast<size_t>(image.spec().width) * channels_);
  }

  void read(int y) {
    OIIO::ROI roi(0, image_.spec().width, y, y + 1, 0, 1, 0, channels_);
    if (bytes_) image_.get_pixels(roi, OIIO::TypeDesc::UINT8, byteRow_.data());
    else image_.get_pixels(roi, OIIO::TypeDesc::FLOAT, floatRow_.data());
  }

  Vec3 at(int x) const {
    Vec3 rgb;
    for (int c = 0; c < 3; ++c) {
      size_t i = static_cast<size_t>(x) * channels_ + (channels_ == 3 ? c : 0);
      rgb[c] = bytes_ ? byteToLinear()[byteRow_[i]]
                      : srgbToLinear(std::clamp(static_cast<double>(floatRow_[i]), 0.0, 1.0));
    }
    return rgb;
  }

 private:
  // An 8-bit image (the usual case) holds 256 values: each one's linear value, computed once
  // from the float OpenImageIO reads for it, as for any other format, instead of a pow per channel.
  static const std::array<double, 256>& byteToLinear() {
    static const std::array<double, 256> table = [] {
      std::array<double, 256> t;
      for (int k = 0; k < 256; ++k) {
        unsigned char byte = static_cast<unsigned char>(k);
        float v = 0;
        OIIO::convert_pixel_values(OIIO::TypeDesc::UINT8, &byte, OIIO::TypeDesc::FLOAT, &v, 1);
        t[k] = srgbToLinear(std::clamp(static_cast<double>(v), 0.0, 1.0));
      }
      return t;
    }();
    return table;
  }

  const OIIO::ImageBuf& image_;
  int channels_;
  bool bytes_;
  std::vector<unsigned char> byteRow_;
  std::vector<float> floatRow_;
};

// Everything one evaluation shares between its threads.
struct Setup {
  int width = 0, height = 0;
  const OIIO::ImageBuf* images[2];           // reference, test
  CsfKernels csf[3];                         // achromatic, red-green, blue-yellow
  Kernel gauss, edge, point;                 // the feature detectors' smoothing, edge and point kernels
  int radius = 0;                            // the largest kernel radius
  double cmax = 0, pccmax = 0;               // the colour error's redistribution
};

// The separable filters, and the threads' bands of rows.
//
// Each pair is filtered as the reference and the difference test - reference: where the images
// agree the difference filters to exactly 0, and a small difference keeps its own relative
// precision instead of drowning in the rounding of two nearly equal colours (the colour and
// feature errors are roots of these differences, steep near 0). That lets the difference and the
// features run on floats, twice the samples per vector instruction of doubles. The reference's
// colour stays in double: the RGB clamp that follows turns its absolute rounding into colour
// difference where a colour lies on a face of the cube (black, saturated white).
enum ColourPass { kY, kCx, kCz1, kCz2 };                 // inputs: 0 Y, 1 Cx, 2 Cz
enum FeaturePass { kEdgeX, kEdgeY, kPointX, kPointY };  // input: 0 (Y + 16) / 116

std::vector<flip::SeparablePass> colourPasses(const Setup& s) {
  return {{0, &s.csf[0].g1, &s.csf[0].g1}, {1, &s.csf[1].g1, &s.csf[1].g1}, {2, &s.csf[2].g1, &s.csf[2].g1},
          {2, &s.csf[2].g2, &s.csf[2].g2}};
}

// The detectors along one axis and the Gaussian across; the derivative is taken first.
std::vector<flip::SeparablePass> featurePasses(const Setup& s) {
  return {{0, &s.edge, &s.gauss}, {0, &s.gauss, &s.edge, true}, {0, &s.point, &s.gauss}, {0, &s.gauss, &s.point, true}};
}

template <class T>
Vec3 filteredColour(const Setup& s, const flip::SeparableRows<T>& rows, int x) {
  auto v = [&](int pass) { return static_cast<double>(rows.row(pass)[x]); };
  return {s.csf[0].weight1 * v(kY), s.csf[1].weight1 * v(kCx), s.csf[2].weight1 * v(kCz1) + s.csf[2].weight2 * v(kCz2)};
}

double length(double x, double y) { return std::sqrt(x * x + y * y); }

struct BandTotals {
  double sum = 0, min = 1.0, max = 0.0;
};

// The error of the output rows y0..y1 - 1 into errors (the whole map), row by row.
BandTotals evaluateBand(const Setup& s, int y0, int y1, float* errors) {
  const int w = s.width, h = s.height, r = s.radius;
  flip::SeparableRows<double> refColour(w, h, r, 3, colourPasses(s));
  flip::SeparableRows<float> diffColour(w, h, r, 3, colourPasses(s));
  flip::SeparableRows<float> refFeatures(w, h, r, 1, featurePasses(s)), diffFeatures(w, h, r, 1, featurePasses(s));
  LinearRows ref(*s.images[0]), test(*s.images[1]);
  auto pushInputRow = [&](int y) {
    ref.read(y);
    test.read(y);
    for (int x = 0; x < w; ++x) {
      Vec3 v[2] = {xyzToYcxcz(linearRgbToXyz(ref.at(x))), xyzToYcxcz(linearRgbToXyz(test.at(x)))};
      for (int c = 0; c < 3; ++c) {
        refColour.input(c)[x] = v[0][c];
        diffColour.input(c)[x] = static_cast<float>(v[1][c] - v[0][c]);
      }
      double lr = (v[0][0] + 16.0) / 116.0, lt = (v[1][0] + 16.0) / 116.0;
      refFeatures.input(0)[x] = static_cast<float>(lr);
      diffFeatures.input(0)[x] = static_cast<float>(lt - lr);
    }
    refColour.push(y);
    diffColour.push(y);
    refFeatures.push(y);
    diffFeatures.push(y);
  };

  BandTotals t;
  int next = std::max(0, y0 - r);  // the next input row to push
  for (int y = y0; y < y1; ++y) {
    for (int last = std::min(h - 1, y + r); next <= last; ++next) pushInputRow(next);
    refColour.output(y);
    diffColour.output(y);
    refFeatures.output(y);
    diffFeatures.output(y);
    const float* fr[4] = {refFeatures.row(0), refFeatures.row(1), refFeatures.row(2), refFeatures.row(3)};
    const float* fd[4] = {diffFeatures.row(0), diffFeatures.row(1), diffFeatures.row(2), diffFeatures.row(3)};
    for (int x = 0; x < w; ++x) {
      // Colour: HyAB distance of the filtered colours in Hunt-adjusted L*a*b*, redistributed so
      // that pc * cmax maps to pt. Where the difference filters to 0 the colours are equal.
      Vec3 cd = filteredColour(s, diffColour, x);
      double dc = 0;
      if (cd[0] != 0 || cd[1] != 0 || cd[2] != 0) {
        Vec3 cr = filteredColour(s, refColour, x);
        Vec3 ct{cr[0] + cd[0], cr[1] + cd[1], cr[2] + cd[2]};
        dc = std::pow(hyab(filteredToHuntLab(cr), filteredToHuntLab(ct)), kQc);
      }
      dc = dc < s.pccmax ? kPt / s.pccmax * dc : kPt + (dc - s.pccmax) / (s.cmax - s.pccmax) * (1.0 - kPt);
      // Features: the larger difference of the edge and point detectors' magnitudes.
      auto magnitudes = [&](int px, int py) {
        double rx = fr[px][x], ry = fr[py][x];
        return std::abs(length(rx, ry) - length(rx + fd[px][x], ry + fd[py][x]));
      };
      static_assert(kQf == 0.5, "the feature exponent is taken as a square root");
      double df = std::sqrt(std::max(magnitudes(kEdgeX, kEdgeY), magnitudes(kPointX, kPointY)) / std::numbers::sqrt2);
      double e = std::pow(dc, 1.0 - df);
      errors[static_cast<size_t>(y) * w + x] = static_cast<float>(e);
      t.sum += e;
      t.min = std::min(t.min, e);
      t.max = std::max(t.max, e);
    }
  }
  return t;
}

// The values in increasing order. Errors are never negative, and non-negative floats order as
// their bit patterns do as unsigned integers: two passes of a 16-bit radix sort, linear in the
// pixels: 0.03 s for a 1920x1080 map (docs/BENCH.md's machine), where each of the three
// percentiles sorted a copy with std::sort, 0.11 s each.
std::vector<float> sortedErrors(const std::vector<float>& values) {
  std::vector<float> sorted(values);
  std::unique_ptr<float[]> scratch(new float[values.size()]);
  float* from = sorted.data();
  float* to = scratch.get();
  for (int shift : {0, 16}) {
    auto digit = [shift](float v) { return (std::bit_cast<uint32_t>(v) >> shift) & 0xffff; };
    std::vector<size_t> start(65537, 0);
    for (size_t i = 0; i < values.size(); ++i) ++start[digit(from[i]) + 1];
    for (size_t d = 1; d < start.size(); ++d) start[d] += start[d - 1];
    for (size_t i = 0; i < values.size(); ++i) to[start[digit(from[i])]++] = from[i];
    std::swap(from, to);
  }
  return sorted;  // two passes: back in `sorted`
}

double weightedPercentileOfSorted(const std::vector<float>& sorted, double share) {
  double total = 0;
  for (float v : sorted) total += v;
  double running = 0;
  for (float v : sorted) {
    running += v;
    if (running > share * total) return v;
  }
  return sorted.empty() ? 0.0 : sorted.back();
}

}  // namespace

double flipDefaultPixelsPerDegree() { return 0.7 * 3840.0 / 0.7 * std::numbers::pi / 180.0; }

double flipWeightedPercentile(std::vector<float> values, double share) {
  std::sort(values.begin(), values.end());
  return weightedPercentileOfSorted(values, share);
}

FlipResult computeLdrFlip(const OIIO::ImageBuf& reference, const OIIO::ImageBuf& test, double ppd, int threads) {
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

  Setup s;
  s.width = a.width;
  s.height = a.height;
  s.images[0] = &reference;
  s.images[1] = &test;

  // One radius for the three CSF filters, wide enough for the widest Gaussian.
  double maxScale = std::max({kCsfAchromatic.b1, kCsfAchromatic.b2, kCsfRedGreen.b1, kCsfRedGreen.b2,
                              kCsfBlueYellow.b1, kCsfBlueYellow.b2});
  int csfRadius = static_cast<int>(std::ceil(3.0 * std::sqrt(maxScale / (2.0 * std::numbers::pi * std::numbers::pi)) * ppd));
  s.csf[0] = csfKernels(kCsfAchromatic, csfRadius, ppd);
  s.csf[1] = csfKernels(kCsfRedGreen, csfRadius, ppd);
  s.csf[2] = csfKernels(kCsfBlueYellow, csfRadius, ppd);
  std::vector<double> across, edge, point;
  featureKernels(ppd, false, &across, &edge);
  featureKernels(ppd, true, &across, &point);
  s.gauss = halfOf(across, Kernel::Symmetric);
  s.edge = halfOf(edge, Kernel::Antisymmetric);
  s.point = halfOf(point, Kernel::ZeroSum);
  s.radius = std::max(csfRadius, s.gauss.radius());
  s.cmax = std::pow(hyab(hunt(xyzToLab(linearRgbToXyz({0, 1, 0}))), hunt(xyzToLab(linearRgbToXyz({0, 0, 1})))), kQc);
  s.pccmax = kPc * s.cmax;

  // Bands of rows, one per thread; each filters the 2 * radius input rows around its edges again,
  // so by default a band is at least 4 radii tall.
  size_t n = static_cast<size_t>(r.width) * r.height;
  r.errorMap.resize(n);
  int hardware = static_cast<int>(std::thread::hardware_concurrency());
  int bands = threads > 0 ? threads : std::min(hardware, r.height / std::max(1, 4 * s.radius));
  bands = std::clamp(bands, 1, r.height);
  std::vector<BandTotals> totals(bands);
  std::vector<std::exception_ptr> failures(bands);
  auto run = [&](int band) {
    try {
      totals[band] = evaluateBand(s, r.height * band / bands, r.height * (band + 1) / bands, r.errorMap.data());
    } catch (...) {
      failures[band] = std::current_exception();
    }
  };
  std::vector<std::thread> workers;
  for (int band = 1; band < bands; ++band) {
    try {
      workers.emplace_back(run, band);
    } catch (const std::system_error&) {  // no thread to be had: this one does the band
      run(band);
    }
  }
  run(0);
  for (std::thread& t : workers) t.join();
  for (const std::exception_ptr& failure : failures)
    if (failure) std::rethrow_exception(failure);

  double sum = 0;
  r.min = 1.0;
  r.max = 0.0;
  for (const BandTotals& t : totals) {
    sum += t.sum;
    r.min = std::min(r.min, t.min);
    r.max = std::max(r.max, t.max);
  }
  r.mean = sum / static_cast<double>(n);
  std::vector<float> sorted = sortedErrors(r.errorMap);
  r.weightedQuartile1 = weightedPercentileOfSorted(sorted, 0.25);
  r.weightedMedian = weightedPercentileOfSorted(sorted, 0.5);
  r.weightedQuartile3 = weightedPercentileOfSorted(sorted, 0.75);
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
