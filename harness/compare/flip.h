// LDR-FLIP (Andersson et al., "FLIP: A Difference Evaluator for Alternating Images", HPG 2020):
// a per-pixel perceptual error in [0, 1] between a reference and a test image, both read as
// sRGB-encoded colour in [0, 1] (alpha ignored, float images clamped). Pooled like the paper's
// tool: mean, min, max and weighted percentiles (each pixel weighted by its own error, so the
// weighted median is the error below which half of the total error lies).
//
// Written here because Debian ships no FLIP library; validated against the reference tool's
// published values for a test pair (tests/flip_test.cpp).
#pragma once

#include <string>
#include <vector>

#include <OpenImageIO/imagebuf.h>
#include <nlohmann/json.hpp>

namespace parity::harness {

// 0.7 m from a 0.7 m wide display of 3840 pixels: the paper's default viewing condition.
double flipDefaultPixelsPerDegree();

struct FlipResult {
  bool ok = false;
  std::string error;  // one line when !ok
  int width = 0, height = 0;
  double pixelsPerDegree = 0;
  double mean = 0, min = 0, max = 0;
  double weightedQuartile1 = 0, weightedMedian = 0, weightedQuartile3 = 0;
  std::vector<float> errorMap;  // width x height, row 0 first
};

// threads: how many bands of rows are evaluated at once, each by a thread of its own (0: one per
// hardware thread, as the image's height allows); the map does not depend on it.
FlipResult computeLdrFlip(const OIIO::ImageBuf& reference, const OIIO::ImageBuf& test,
                          double pixelsPerDegree = flipDefaultPixelsPerDegree(), int threads = 0);

// The error below which `share` (0..1) of the summed error lies (the pooling of the FLIP tool).
double flipWeightedPercentile(std::vector<float> values, double share);

// The error map through the magma colour map (black: no error, yellow-white: 1). False with a reason.
bool writeFlipMap(const FlipResult& result, const std::string& path, std::string* error);

nlohmann::json toJson(const FlipResult& r);

}  // namespace parity::harness
