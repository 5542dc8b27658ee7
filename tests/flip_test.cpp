// LDR-FLIP against the reference tool's published values for the tree pair in
// ../shared/assets/flip (its README), against a straightforward evaluation at every pixel, plus
// properties any FLIP must have, and `parity diff --flip`.
#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <iomanip>
#include <numbers>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/compare/flip.h"
#include "harness/io/image_io.h"
#include "harness/run/process.h"

namespace fs = std::filesystem;
using namespace parity;

namespace {

fs::path flipAssets() { return fs::path(PARITY_SOURCE_DIR) / ".." / "shared" / "assets" / "flip"; }

TEST(Flip, TreePairMatchesTheReferenceTool) {
  fs::path dir = flipAssets();
  if (!fs::exists(dir / "tree-ref.png") || !fs::exists(dir / "tree-test.png"))
    GTEST_SKIP() << "../shared/assets/flip is absent (optional shared assets); nothing to validate against";
  OIIO::ImageBuf ref, test;
  std::string error;
  ASSERT_TRUE(harness::readImage((dir / "tree-ref.png").string(), &ref, &error)) << error;
  ASSERT_TRUE(harness::readImage((dir / "tree-test.png").string(), &test, &error)) << error;
  harness::FlipResult r = harness::computeLdrFlip(ref, test);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_NEAR(r.pixelsPerDegree, 67.0206, 1e-4);
  // Published by the reference tool at 67 pixels per degree (the README of the assets).
  EXPECT_NEAR(r.mean, 0.133285, 1e-4);
  // The weighted percentiles sit on a steep part of the sorted errors, where the reference
  // tool's float arithmetic moves single pixels across them: within 1e-3.
  EXPECT_NEAR(r.weightedQuartile1, 0.184586, 1e-3);
  EXPECT_NEAR(r.weightedMedian, 0.333096, 1e-3);
  EXPECT_NEAR(r.weightedQuartile3, 0.503230, 1e-3);
  EXPECT_NEAR(r.min, 0.0, 1e-6);
  EXPECT_NEAR(r.max, 0.983044, 1e-4);
}

OIIO::ImageBuf gradient(int w, int h) {
  OIIO::ImageBuf img(OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::UINT8));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float v[3] = {x / float(w - 1), y / float(h - 1), ((x / 4 + y / 4) % 2) ? 0.9f : 0.1f};
      img.setpixel(x, y, v);
    }
  return img;
}

TEST(Flip, IdenticalImagesHaveZeroErrorAndDifferencesRaiseIt) {
  OIIO::ImageBuf a = gradient(64, 48);
  harness::FlipResult same = harness::computeLdrFlip(a, a);
  ASSERT_TRUE(same.ok) << same.error;
  EXPECT_EQ(same.mean, 0.0);
  EXPECT_EQ(same.max, 0.0);
  OIIO::ImageBuf b;
  b.copy(a);
  float black[3] = {0, 0, 0};
  OIIO::ImageBufAlgo::fill(b, black, OIIO::ROI(10, 30, 10, 30, 0, 1, 0, 3));
  harness::FlipResult diff = harness::computeLdrFlip(a, b);
  ASSERT_TRUE(diff.ok);
  EXPECT_GT(diff.mean, 0.05);
  EXPECT_LE(diff.max, 1.0);
  EXPECT_LE(diff.weightedQuartile1, diff.weightedMedian);
  EXPECT_LE(diff.weightedMedian, diff.weightedQuartile3);
  // Error stays where the images differ (plus the filters' reach).
  EXPECT_EQ(diff.errorMap[static_cast<size_t>(47) * 64 + 63], 0.0f);
  OIIO::ImageBuf small = gradient(32, 48);
  EXPECT_FALSE(harness::computeLdrFlip(a, small).ok);
}

// The LDR-FLIP map computed the plain way, as harness/compare/flip.cpp did before it was made
// fast: double precision throughout, every separable filter a full horizontal then vertical pass
// over whole planes with each tap's coordinate clamped to the image. Independent of the fast
// code's float filters, folded kernels, rows in rings, bands of threads and lookup tables.
namespace plain {

using Vec3 = std::array<double, 3>;

Vec3 rgbToXyz(const Vec3& c) {
  return {(10135552.0 / 24577794.0) * c[0] + (8788810.0 / 24577794.0) * c[1] + (4435075.0 / 24577794.0) * c[2],
          (2613072.0 / 12288897.0) * c[0] + (8788810.0 / 12288897.0) * c[1] + (887015.0 / 12288897.0) * c[2],
          (1425312.0 / 73733382.0) * c[0] + (8788810.0 / 73733382.0) * c[1] + (70074185.0 / 73733382.0) * c[2]};
}
Vec3 xyzToRgb(const Vec3& c) {
  return {3.241003275 * c[0] - 1.537398934 * c[1] - 0.498615861 * c[2],
          -0.969224334 * c[0] + 1.875930071 * c[1] + 0.041554224 * c[2],
          0.055639423 * c[0] - 0.204011202 * c[1] + 1.057148933 * c[2]};
}
const Vec3 kWhite = rgbToXyz({1, 1, 1});
Vec3 huntLab(const Vec3& xyz) {
  const double d = 6.0 / 29.0;
  auto f = [&](double v) { return v > d * d * d ? std::cbrt(v) : v / (3 * d * d) + 4.0 / 29.0; };
  double x = f(xyz[0] / kWhite[0]), y = f(xyz[1] / kWhite[1]), z = f(xyz[2] / kWhite[2]);
  double l = 116 * y - 16;
  return {l, 0.01 * l * 500 * (x - y), 0.01 * l * 200 * (y - z)};
}
double hyab(const Vec3& a, const Vec3& b) { return std::abs(a[0] - b[0]) + std::hypot(a[1] - b[1], a[2] - b[2]); }

using Plane = std::vector<double>;

Plane separable(const Plane& in, int w, int h, const std::vector<double>& kx, const std::vector<double>& ky) {
  int rx = static_cast<int>(kx.size() / 2), ry = static_cast<int>(ky.size() / 2);
  Plane tmp(in.size()), out(in.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int i = -rx; i <= rx; ++i) tmp[y * w + x] += kx[i + rx] * in[y * w + std::clamp(x + i, 0, w - 1)];
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int i = -ry; i <= ry; ++i) out[y * w + x] += ky[i + ry] * tmp[std::clamp(y + i, 0, h - 1) * w + x];
  return out;
}

std::vector<float> flipMap(const OIIO::ImageBuf& refImage, const OIIO::ImageBuf& testImage, double ppd) {
  const double pi = std::numbers::pi;
  int w = refImage.spec().width, h = refImage.spec().height;
  // YCxCz planes of both images (sRGB clamped to [0, 1]; a grey image's channel 0 for all three).
  auto ycxcz = [&](const OIIO::ImageBuf& img) {
    std::array<Plane, 3> p{Plane(w * h), Plane(w * h), Plane(w * h)};
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        Vec3 rgb;
        for (int c = 0; c < 3; ++c) {
          double v = std::clamp(double(img.getchannel(x, y, 0, img.spec().nchannels >= 3 ? c : 0)), 0.0, 1.0);
          rgb[c] = v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
        }
        Vec3 xyz = rgbToXyz(rgb);
        double nx = xyz[0] / kWhite[0], ny = xyz[1] / kWhite[1], nz = xyz[2] / kWhite[2];
        p[0][y * w + x] = 116 * ny - 16;
        p[1][y * w + x] = 500 * (nx - ny);
        p[2][y * w + x] = 200 * (ny - nz);
      }
    return p;
  };
  std::array<Plane, 3> ref = ycxcz(refImage), test = ycxcz(testImage);

  // Contrast sensitivity: per channel one or two Gaussians (a, b), normalised together.
  const double csf[3][4] = {{1, 0.0047, 0, 1e-5}, {1, 0.0053, 0, 1e-5}, {34.1, 0.04, 13.5, 0.025}};
  int radius = static_cast<int>(std::ceil(3 * std::sqrt(0.04 / (2 * pi * pi)) * ppd));
  auto filterColour = [&](const std::array<Plane, 3>& img) {
    std::array<Plane, 3> out;
    for (int c = 0; c < 3; ++c) {
      std::vector<double> g1, g2;
      double s1 = 0, s2 = 0;
      for (int i = -radius; i <= radius; ++i) {
        double d2 = (i / ppd) * (i / ppd);
        g1.push_back(std::exp(-pi * pi * d2 / csf[c][1]));
        g2.push_back(std::exp(-pi * pi * d2 / csf[c][3]));
        s1 += g1.back();
        s2 += g2.back();
      }
      double w1 = csf[c][0] * std::sqrt(pi / csf[c][1]), w2 = csf[c][2] * std::sqrt(pi / csf[c][3]);
      double total = w1 * s1 * s1 + w2 * s2 * s2;
      Plane a = separable(img[c], w, h, g1, g1), b = separable(img[c], w, h, g2, g2);
      out[c].resize(a.size());
      for (size_t i = 0; i < a.size(); ++i) out[c][i] = (w1 * a[i] + w2 * b[i]) / total;
    }
    return out;
  };
  std::array<Plane, 3> fr = filterColour(ref), ft = filterColour(test);
  auto lab = [&](const std::array<Plane, 3>& p, size_t i) {
    double y = (p[0][i] + 16) / 116;
    Vec3 rgb = xyzToRgb({(y + p[1][i] / 500) * kWhite[0], y * kWhite[1], (y - p[2][i] / 200) * kWhite[2]});
    for (double& c : rgb) c = std::clamp(c, 0.0, 1.0);
    return huntLab(rgbToXyz(rgb));
  };

  // Edge and point detectors on the normalised luminance.
  double sd = 0.5 * 0.082 * ppd;
  int fr3 = static_cast<int>(std::ceil(3 * sd));
  std::vector<double> gauss, edge, point;
  double gsum = 0, epos = 0, eneg = 0, ppos = 0, pneg = 0;
  for (int i = -fr3; i <= fr3; ++i) {
    double g = std::exp(-(i * i) / (2 * sd * sd));
    gauss.push_back(g);
    edge.push_back(-i * g);
    point.push_back((i * i / (sd * sd) - 1) * g);
    gsum += g;
    (edge.back() > 0 ? epos : eneg) += std::abs(edge.back());
    (point.back() > 0 ? ppos : pneg) += std::abs(point.back());
  }
  for (double& v : gauss) v /= gsum;
  for (double& v : edge) v /= v > 0 ? epos : eneg;
  for (double& v : point) v /= v > 0 ? ppos : pneg;
  auto features = [&](const Plane& l, const std::vector<double>& k) {
    Plane x = separable(l, w, h, k, gauss), y = separable(l, w, h, gauss, k);
    for (size_t i = 0; i < x.size(); ++i) x[i] = std::hypot(x[i], y[i]);
    return x;
  };
  Plane lr = ref[0], lt = test[0];
  for (double& v : lr) v = (v + 16) / 116;
  for (double& v : lt) v = (v + 16) / 116;
  Plane er = features(lr, edge), et = features(lt, edge), pr = features(lr, point), pt = features(lt, point);

  double cmax = std::pow(hyab(huntLab(rgbToXyz({0, 1, 0})), huntLab(rgbToXyz({0, 0, 1}))), 0.7), pccmax = 0.4 * cmax;
  std::vector<float> map(static_cast<size_t>(w) * h);
  for (size_t i = 0; i < map.size(); ++i) {
    double dc = std::pow(hyab(lab(fr, i), lab(ft, i)), 0.7);
    dc = dc < pccmax ? 0.95 / pccmax * dc : 0.95 + (dc - pccmax) / (cmax - pccmax) * 0.05;
    double df = std::pow(std::max(std::abs(er[i] - et[i]), std::abs(pt[i] - pr[i])) / std::numbers::sqrt2, 0.5);
    map[i] = static_cast<float>(std::pow(dc, 1 - df));
  }
  return map;
}

}  // namespace plain

// A pair with what makes the fast evaluation's shortcuts visible: black and white regions (the RGB
// clamp after filtering), edges, noise, a region that differs by one 8-bit level and one lit a
// little more (small differences, where the colour and feature errors are steep), regions that
// agree, and in a float image values outside [0, 1].
std::pair<OIIO::ImageBuf, OIIO::ImageBuf> awkwardPair(int w, int h, int channels, OIIO::TypeDesc format) {
  OIIO::ImageBuf a(OIIO::ImageSpec(w, h, channels, format)), b(OIIO::ImageSpec(w, h, channels, format));
  uint32_t state = 12345;
  auto noise = [&] { return ((state = state * 1664525u + 1013904223u) >> 8) / float(1 << 24); };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float v[4], u[4];
      for (int c = 0; c < channels; ++c) {
        float base = x < w / 4 ? 0.0f : x > 3 * w / 4 ? 1.0f : 0.2f + 0.6f * ((x / 3 + y / 3 + c) % 3) / 2.0f;
        v[c] = y > h / 2 && x > w / 3 && x < 2 * w / 3 ? noise() : base;
        u[c] = v[c];
        if (y < h / 3 && x > w / 3 && x < w / 2) u[c] = std::min(1.0f, v[c] + 1.0f / 255);  // one level
        if (y > 2 * h / 3 && x < w / 2) u[c] = std::min(1.0f, v[c] * 1.1f + 0.02f);        // a little brighter
        if (y > h / 3 && y < h / 2 && x > w / 2 && x < 3 * w / 4 && c == 0) u[c] = 1.0f - v[c];  // a colour change
        if (format == OIIO::TypeDesc::FLOAT && x % 7 == 3) v[c] = u[c] = 1.7f;  // beyond the [0, 1] a float holds
        if (format == OIIO::TypeDesc::FLOAT && x % 11 == 5) u[c] = -0.3f;
      }
      a.setpixel(x, y, v);
      b.setpixel(x, y, u);
    }
  return {std::move(a), std::move(b)};
}

// Every pixel within 1e-4 of the plain evaluation, and the same map whatever the number of bands:
// sizes with a width that is no multiple of the filters' vector blocks, heights below a kernel's
// reach and bands of a few rows; grey, RGBA and float images.
TEST(Flip, EveryPixelMatchesThePlainEvaluation) {
  struct Case {
    int w, h, channels;
    OIIO::TypeDesc format;
  };
  for (const Case& c : {Case{61, 47, 3, OIIO::TypeDesc::UINT8}, Case{13, 5, 3, OIIO::TypeDesc::UINT8},
                        Case{40, 29, 1, OIIO::TypeDesc::UINT8}, Case{37, 23, 4, OIIO::TypeDesc::FLOAT}}) {
    SCOPED_TRACE(std::to_string(c.w) + "x" + std::to_string(c.h) + ", " + std::to_string(c.channels) + " channels, " +
                 c.format.c_str());
    auto [a, b] = awkwardPair(c.w, c.h, c.channels, c.format);
    std::vector<float> expected = plain::flipMap(a, b, harness::flipDefaultPixelsPerDegree());
    std::vector<float> oneBand;
    for (int threads : {1, 2, 3, 7}) {
      harness::FlipResult r = harness::computeLdrFlip(a, b, harness::flipDefaultPixelsPerDegree(), threads);
      ASSERT_TRUE(r.ok) << r.error;
      ASSERT_EQ(r.errorMap.size(), expected.size());
      double worst = 0;
      size_t at = 0;
      for (size_t i = 0; i < expected.size(); ++i)
        if (double d = std::abs(double(r.errorMap[i]) - expected[i]); d > worst) worst = d, at = i;
      std::ostringstream where;
      where << std::setprecision(9) << threads << " threads: pixel (" << at % c.w << ", " << at / c.w << ") is "
            << r.errorMap[at] << ", plainly " << expected[at];
      EXPECT_LE(worst, 1e-4) << where.str();
      // The precision the fast evaluation has (about 1e-7 here: float filters of the difference, the
      // reference's colour in double), so that a change that loses some shows here before it
      // reaches 1e-4 on a larger image: filtering the reference's colour in float gives 1.2e-6.
      EXPECT_LE(worst, 5e-7) << where.str();
      if (threads == 1) oneBand = r.errorMap;
      else EXPECT_EQ(r.errorMap, oneBand) << threads << " threads";
    }
  }
  // An RGB image against a grey one.
  OIIO::ImageBuf rgb = awkwardPair(31, 17, 3, OIIO::TypeDesc::UINT8).first;
  OIIO::ImageBuf grey = awkwardPair(31, 17, 1, OIIO::TypeDesc::UINT8).second;
  std::vector<float> expected = plain::flipMap(rgb, grey, harness::flipDefaultPixelsPerDegree());
  harness::FlipResult r = harness::computeLdrFlip(rgb, grey);
  ASSERT_TRUE(r.ok) << r.error;
  for (size_t i = 0; i < expected.size(); ++i) ASSERT_NEAR(r.errorMap[i], expected[i], 1e-4) << "pixel " << i;
}

TEST(Flip, DiffCommandPrintsFlipAndWritesItsMap) {
  fs::path dir = fs::temp_directory_path() / ("parity-flip-test-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  OIIO::ImageBuf a = gradient(48, 32), b;
  b.copy(a);
  float white[3] = {1, 1, 1};
  OIIO::ImageBufAlgo::fill(b, white, OIIO::ROI(5, 15, 5, 15, 0, 1, 0, 3));
  ASSERT_TRUE(a.write((dir / "a.png").string()));
  ASSERT_TRUE(b.write((dir / "b.png").string()));
  auto r = harness::runProcess({PARITY_BINARY, "diff", (dir / "a.png").string(), (dir / "b.png").string(), "--flip",
                                "--flip-map", (dir / "map.png").string(), "--json"},
                               120);
  EXPECT_EQ(r.exitCode, 2) << r.err;
  nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_TRUE(j.contains("flip")) << r.out;
  EXPECT_GT(j["flip"]["mean"].get<double>(), 0.0);
  EXPECT_TRUE(fs::exists(dir / "map.png"));
  // Threshold on the FLIP mean alone: identical images pass, different ones fail.
  r = harness::runProcess({PARITY_BINARY, "diff", (dir / "a.png").string(), (dir / "a.png").string(), "--flip",
                           "--flip-fail", "0.01"},
                          120);
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("FLIP mean 0"), std::string::npos) << r.out;
  fs::remove_all(dir);
}

}  // namespace
