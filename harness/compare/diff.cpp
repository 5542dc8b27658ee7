#include "harness/compare/diff.h"

#include <OpenImageIO/imagebufalgo.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "harness/io/image_io.h"

namespace parity::harness {

const char* verdictName(DiffVerdict v) {
  switch (v) {
    case DiffVerdict::Pass: return "PASS";
    case DiffVerdict::Warn: return "WARNING";
    case DiffVerdict::Fail: return "FAILURE";
    case DiffVerdict::SizeMismatch: return "SIZE MISMATCH";
    case DiffVerdict::FileError: return "FILE ERROR";
  }
  return "?";
}

namespace {

// NaN compares as no difference in OpenImageIO's statistics (and Inf makes every statistic
// infinite), so an image holding either cannot be judged: it is a file error naming the texel.
bool firstNonFinite(const OIIO::ImageBuf& image, const std::string& name, std::string* message) {
  OIIO::TypeDesc::BASETYPE type = static_cast<OIIO::TypeDesc::BASETYPE>(image.spec().format.basetype);
  if (type != OIIO::TypeDesc::FLOAT && type != OIIO::TypeDesc::HALF && type != OIIO::TypeDesc::DOUBLE) return false;
  const OIIO::ImageSpec& spec = image.spec();
  const int channels = spec.nchannels;
  std::vector<float> row(static_cast<size_t>(spec.width) * static_cast<size_t>(channels));
  for (int y = spec.y; y < spec.y + spec.height; ++y) {
    OIIO::ROI line(spec.x, spec.x + spec.width, y, y + 1, 0, 1, 0, channels);
    if (!image.get_pixels(line, OIIO::TypeDesc::FLOAT, row.data())) continue;
    for (size_t i = 0; i < row.size(); ++i)
      if (!std::isfinite(row[i])) {
        std::ostringstream s;
        s << name << ": texel (" << spec.x + static_cast<int>(i / channels) << ", " << y << ") channel "
          << i % channels << " is " << (std::isnan(row[i]) ? "NaN" : row[i] > 0 ? "+Inf" : "-Inf")
          << "; an image with non-finite values cannot be compared";
        *message = s.str();
        return true;
      }
  }
  return false;
}

DiffResult compareImages(const OIIO::ImageBuf& a, const OIIO::ImageBuf& b, const DiffThresholds& t,
                         const std::string& nameA, const std::string& nameB) {
  DiffResult r;
  const OIIO::ImageSpec& sa = a.spec();
  const OIIO::ImageSpec& sb = b.spec();
  r.width = sa.width;
  r.height = sa.height;
  r.channels = sa.nchannels;
  if (sa.width != sb.width || sa.height != sb.height || sa.nchannels != sb.nchannels) {
    r.verdict = DiffVerdict::SizeMismatch;
    r.message = "images differ in size: " + std::to_string(sa.width) + "x" + std::to_string(sa.height) + "x" +
                std::to_string(sa.nchannels) + " versus " + std::to_string(sb.width) + "x" +
                std::to_string(sb.height) + "x" + std::to_string(sb.nchannels);
    return r;
  }
  if (firstNonFinite(a, nameA, &r.message) || firstNonFinite(b, nameB, &r.message)) {
    r.verdict = DiffVerdict::FileError;
    return r;
  }
  r.pixels = static_cast<uint64_t>(sa.width) * static_cast<uint64_t>(sa.height);
  OIIO::ImageBufAlgo::CompareResults fail = OIIO::ImageBufAlgo::compare(a, b, t.fail, t.warn);
  // OIIO 2.4 also sets CompareResults::error when pixels merely differ; only an error message
  // on either image means the comparison itself failed.
  std::string compareError = a.geterror() + b.geterror();
  if (!compareError.empty()) {
    r.verdict = DiffVerdict::FileError;
    r.message = "cannot compare: " + compareError;
    return r;
  }
  r.maxError = fail.maxerror;
  r.meanError = fail.meanerror;
  r.rmsError = fail.rms_error;
  r.psnr = fail.PSNR;
  r.maxX = fail.maxx;
  r.maxY = fail.maxy;
  r.maxChannel = fail.maxc;
  r.failPixels = fail.nfail;
  r.warnPixels = fail.nwarn;
  const double total = static_cast<double>(r.pixels);
  if (static_cast<double>(r.failPixels) > t.failPercent / 100.0 * total || r.maxError > t.hardFail)
    r.verdict = DiffVerdict::Fail;
  else if (static_cast<double>(r.warnPixels) > t.warnPercent / 100.0 * total || r.maxError > t.hardWarn)
    r.verdict = DiffVerdict::Warn;
  return r;
}

}  // namespace

DiffResult diffImages(const OIIO::ImageBuf& a, const OIIO::ImageBuf& b, const DiffThresholds& t) {
  return compareImages(a, b, t, "first image", "second image");
}

DiffResult diffFiles(const std::string& pathA, const std::string& pathB, const DiffThresholds& t) {
  OIIO::ImageBuf a, b;
  std::string error;
  DiffResult r;
  if (!readImage(pathA, &a, &error) || !readImage(pathB, &b, &error)) {
    r.verdict = DiffVerdict::FileError;
    r.message = error;
    return r;
  }
  return compareImages(a, b, t, pathA, pathB);
}

bool writeHeatmap(const OIIO::ImageBuf& a, const OIIO::ImageBuf& b, const std::string& path, std::string* error) {
  OIIO::ImageBuf diff = OIIO::ImageBufAlgo::absdiff(a, b);
  OIIO::ImageBuf channelMax = OIIO::ImageBufAlgo::maxchan(diff);
  auto range = OIIO::ImageBufAlgo::computePixelStats(channelMax);
  float peak = range.max.empty() ? 0.0f : range.max[0];
  OIIO::ImageBuf scaled = peak > 0.0f ? OIIO::ImageBufAlgo::mul(channelMax, 1.0f / peak) : channelMax;
  OIIO::ImageBuf heat = OIIO::ImageBufAlgo::color_map(scaled, 0, "inferno");
  if (heat.has_error()) {
    *error = path + ": cannot build heat map: " + heat.geterror();
    return false;
  }
  return writeImage(path, heat, error);
}

nlohmann::json toJson(const DiffResult& r) {
  nlohmann::json j;
  j["verdict"] = verdictName(r.verdict);
  j["exit_code"] = static_cast<int>(r.verdict);
  if (!r.message.empty()) j["message"] = r.message;
  if (r.verdict == DiffVerdict::FileError || r.verdict == DiffVerdict::SizeMismatch) return j;
  j["width"] = r.width;
  j["height"] = r.height;
  j["channels"] = r.channels;
  j["max_error"] = r.maxError;
  j["max_error_at"] = {{"x", r.maxX}, {"y", r.maxY}, {"channel", r.maxChannel}};
  j["mean_error"] = r.meanError;
  j["rms_error"] = r.rmsError;
  j["psnr"] = std::isfinite(r.psnr) ? nlohmann::json(r.psnr) : nlohmann::json("inf");
  j["pixels"] = r.pixels;
  j["pixels_over_fail"] = r.failPixels;
  j["share_over_fail"] = r.failShare();
  j["pixels_over_warn"] = r.warnPixels;
  j["share_over_warn"] = r.warnShare();
  return j;
}

std::string summaryLine(const DiffResult& r) {
  std::ostringstream s;
  s << verdictName(r.verdict);
  if (r.verdict == DiffVerdict::FileError || r.verdict == DiffVerdict::SizeMismatch) {
    s << ": " << r.message;
    return s.str();
  }
  s << ": max " << r.maxError << " at (" << r.maxX << ", " << r.maxY << ", c" << r.maxChannel << "), mean "
    << r.meanError << ", RMS " << r.rmsError << ", PSNR " << r.psnr << " dB, " << r.failPixels << " of "
    << r.pixels << " pixels (" << 100.0 * r.failShare() << "%) over the fail threshold";
  return s.str();
}

}  // namespace parity::harness
