// Image comparison with idiff's thresholds and exit codes (OpenImageIO's compare does the
// statistics): fail when more than failPercent % of pixels differ by more than `fail` in any
// channel, or any pixel by more than `hardFail`; likewise for warnings. An image with a NaN or
// Inf texel is a FileError naming the image (the file, for diffFiles) and the first such texel:
// the statistics would otherwise count NaN as no difference.
#pragma once

#include <limits>
#include <string>

#include <OpenImageIO/imagebuf.h>
#include <nlohmann/json.hpp>

namespace parity::harness {

struct DiffThresholds {
  double fail = 1e-6;         // per-channel difference counted as failing (values in [0,1] for 8-bit)
  double failPercent = 0.0;   // share of pixels allowed over `fail`
  double hardFail = std::numeric_limits<double>::infinity();  // any pixel over this fails
  double warn = 1e-6;
  double warnPercent = 0.0;
  double hardWarn = std::numeric_limits<double>::infinity();
};

// idiff's exit codes.
enum class DiffVerdict { Pass = 0, Warn = 1, Fail = 2, SizeMismatch = 3, FileError = 4 };
const char* verdictName(DiffVerdict v);

struct DiffResult {
  DiffVerdict verdict = DiffVerdict::Pass;
  std::string message;  // one line: the reason for SizeMismatch / FileError
  int width = 0, height = 0, channels = 0;
  double maxError = 0, meanError = 0, rmsError = 0, psnr = 0;
  int maxX = 0, maxY = 0, maxChannel = 0;
  uint64_t pixels = 0, failPixels = 0, warnPixels = 0;
  double failShare() const { return pixels ? static_cast<double>(failPixels) / static_cast<double>(pixels) : 0; }
  double warnShare() const { return pixels ? static_cast<double>(warnPixels) / static_cast<double>(pixels) : 0; }
};

DiffResult diffImages(const OIIO::ImageBuf& a, const OIIO::ImageBuf& b, const DiffThresholds& t);
DiffResult diffFiles(const std::string& pathA, const std::string& pathB, const DiffThresholds& t);

// Per-pixel largest channel difference, scaled so the largest difference is full scale, mapped
// through the "inferno" colour map (black: identical). Returns false with a reason.
bool writeHeatmap(const OIIO::ImageBuf& a, const OIIO::ImageBuf& b, const std::string& path, std::string* error);

nlohmann::json toJson(const DiffResult& r);
std::string summaryLine(const DiffResult& r);

}  // namespace parity::harness
