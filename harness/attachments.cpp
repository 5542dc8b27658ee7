#include "harness/attachments.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <limits>
#include <optional>
#include <cmath>
#include <numbers>
#include <vector>

#include "rhi/rhi.h"

namespace parity::harness {

const char* attachmentKindName(AttachmentKind k) {
  switch (k) {
    case AttachmentKind::Normals: return "normals";
    case AttachmentKind::Depth: return "depth";
    case AttachmentKind::FloatData: return "float";
    case AttachmentKind::Quantised: return "quantised";
  }
  return "?";
}

namespace {

bool contains(std::string text, const char* word) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text.find(word) != std::string::npos;
}

std::vector<float> pixels(const OIIO::ImageBuf& img) {
  const OIIO::ImageSpec& s = img.spec();
  std::vector<float> px(static_cast<size_t>(s.width) * s.height * s.nchannels);
  img.get_pixels(OIIO::ROI(0, s.width, 0, s.height, 0, 1, 0, s.nchannels), OIIO::TypeDesc::FLOAT, px.data());
  return px;
}

std::array<double, 3> decodeNormal(const float* p, int channels, NormalEncoding e) {
  auto unscale = [&](int c) { return c < channels ? 2.0 * p[c] - 1.0 : 0.0; };
  switch (e) {
    case NormalEncoding::Scaled: return {unscale(0), unscale(1), unscale(2)};
    case NormalEncoding::ScaledXY: {
      double x = unscale(0), y = unscale(1);
      return {x, y, std::sqrt(std::max(0.0, 1.0 - x * x - y * y))};
    }
    case NormalEncoding::Raw: return {p[0], channels > 1 ? p[1] : 0.0, channels > 2 ? p[2] : 0.0};
  }
  return {0, 0, 0};
}

}  // namespace

AttachmentClass classifyAttachment(const std::string& name, const std::string& formatName) {
  AttachmentClass c;
  std::optional<rhi::Format> format = rhi::formatFromName(formatName);
  rhi::FormatKind kind = format ? rhi::formatInfo(*format).kind : rhi::FormatKind::Unorm;
  uint32_t channels = format ? rhi::formatInfo(*format).channels : 4;
  if (format && channels > 0 && kind != rhi::FormatKind::Depth && kind != rhi::FormatKind::DepthStencil)
    c.bits = static_cast<int>(rhi::formatInfo(*format).bytesPerTexel * 8 / channels);
  bool isFloat = kind == rhi::FormatKind::Float;
  if (contains(name, "normal")) {
    c.kind = AttachmentKind::Normals;
    c.normals = isFloat || kind == rhi::FormatKind::Snorm ? NormalEncoding::Raw
                : channels == 2                           ? NormalEncoding::ScaledXY
                                                          : NormalEncoding::Scaled;
  } else if (kind == rhi::FormatKind::Depth || kind == rhi::FormatKind::DepthStencil || contains(name, "depth")) {
    c.kind = AttachmentKind::Depth;
  } else if (isFloat) {
    c.kind = AttachmentKind::FloatData;
  }
  return c;
}

AttachmentMetrics compareAttachment(const AttachmentClass& cls, const OIIO::ImageBuf& golden, const OIIO::ImageBuf& image,
                                    const AttachmentTolerance& t) {
  AttachmentMetrics m;
  m.cls = cls;
  const OIIO::ImageSpec& a = golden.spec();
  const OIIO::ImageSpec& b = image.spec();
  if (a.width != b.width || a.height != b.height || a.nchannels != b.nchannels) {
    m.error = "size differs: " + std::to_string(a.width) + "x" + std::to_string(a.height) + "x" + std::to_string(a.nchannels) +
              " versus " + std::to_string(b.width) + "x" + std::to_string(b.height) + "x" + std::to_string(b.nchannels);
    return m;
  }
  std::vector<float> g = pixels(golden), v = pixels(image);
  int n = a.nchannels;
  m.pixels = static_cast<uint64_t>(a.width) * a.height;
  double sum = 0;
  for (size_t i = 0; i < m.pixels; ++i) {
    const float* pg = &g[i * n];
    const float* pv = &v[i * n];
    double e = 0;
    switch (cls.kind) {
      case AttachmentKind::Normals: {
        auto x = decodeNormal(pg, n, cls.normals), y = decodeNormal(pv, n, cls.normals);
        double lx = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        double ly = std::sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
        // Texels without a normal (background) in both: nothing to compare; in one only: 180.
        if (lx < 1e-3 && ly < 1e-3) e = 0;
        else if (lx < 1e-3 || ly < 1e-3) e = 180;
        else {
          double cosine = (x[0] * y[0] + x[1] * y[1] + x[2] * y[2]) / (lx * ly);
          e = std::acos(std::clamp(cosine, -1.0, 1.0)) * 180.0 / std::numbers::pi;
        }
        m.threshold = t.normalDegrees;
        break;
      }
      case AttachmentKind::Depth:
        e = std::abs(static_cast<double>(pg[0]) - pv[0]);
        m.threshold = t.depthAbsolute;
        break;
      case AttachmentKind::FloatData:
        for (int c = 0; c < n; ++c) {
          double d = std::abs(static_cast<double>(pg[c]) - pv[c]);
          // Relative to the larger magnitude, with a floor so near-black texels do not explode.
          double scale = std::max({std::abs(static_cast<double>(pg[c])), std::abs(static_cast<double>(pv[c])), 1e-3});
          e = std::max(e, d / scale);
        }
        m.threshold = t.floatRelative;
        break;
      case AttachmentKind::Quantised:
        for (int c = 0; c < n; ++c) e = std::max(e, std::abs(static_cast<double>(pg[c]) - pv[c]));
        m.threshold = t.quantisedSteps / (std::ldexp(1.0, std::min(cls.bits, 24)) - 1.0);
        break;
    }
    if (!std::isfinite(e)) e = std::numeric_limits<double>::infinity();
    sum += std::isfinite(e) ? e : 0;
    m.max = std::max(m.max, e);
    m.differing += e > m.threshold;
  }
  m.metric = cls.kind == AttachmentKind::Normals  ? "angular_error_deg"
             : cls.kind == AttachmentKind::Depth  ? "absolute_error"
             : cls.kind == AttachmentKind::FloatData ? "relative_error"
                                                      : "channel_error";
  m.mean = m.pixels ? sum / static_cast<double>(m.pixels) : 0;
  m.pass = static_cast<double>(m.differing) <= t.failPercent / 100.0 * static_cast<double>(m.pixels);
  m.ok = true;
  return m;
}

nlohmann::json toJson(const AttachmentMetrics& m) {
  if (!m.ok) return {{"error", m.error}, {"pass", false}};
  return {{"kind", attachmentKindName(m.cls.kind)},
          {"metric", m.metric},
          {"max", std::isfinite(m.max) ? nlohmann::json(m.max) : nlohmann::json("inf")},
          {"mean", m.mean},
          {"threshold", m.threshold},
          {"pixels", m.pixels},
          {"differing", m.differing},
          {"pass", m.pass}};
}

}  // namespace parity::harness
