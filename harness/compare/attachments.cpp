#include "harness/compare/attachments.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <limits>
#include <optional>
#include <sstream>
#include <cmath>
#include <numbers>
#include <vector>

#include "platforms/common/platform.h"
#include "platforms/common/platform_params.h"
#include "platforms/x360/fixed16.h"
#include "platforms/x360/resolve.h"
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
    case NormalEncoding::HalfSphere: {
      const double hx = 2.0 * p[0] - 1.0, hy = channels > 1 ? 2.0 * p[1] - 1.0 : 0.0;
      const double z = std::sqrt(std::max(0.0, 1.0 - hx * hx - hy * hy));
      return {2.0 * z * hx, 2.0 * z * hy, 2.0 * z * z - 1.0};
    }
  }
  return {0, 0, 0};
}

// Texels of a two-channel logical target as its logical values (two per texel).
std::vector<float> logicalTwoChannel(const std::vector<float>& texels, int channels, const AttachmentClass& cls) {
  const size_t n = texels.size() / size_t(channels);
  std::vector<float> out(n * 2);
  for (size_t i = 0; i < n; ++i) {
    const float* t = &texels[i * channels];
    for (int c = 0; c < 2; ++c) {
      switch (cls.storage) {
        case TwoChannelStorage::None:
        case TwoChannelStorage::Plain: out[i * 2 + c] = c < channels ? t[c] : 0.0f; break;
        case TwoChannelStorage::Ps3Packed: {
          auto byte = [&](int k) { return k < channels ? std::lround(std::clamp(t[k], 0.0f, 1.0f) * 255.0f) : 0L; };
          out[i * 2 + c] = static_cast<float>(byte(2 * c) + byte(2 * c + 1) * 256) / 65535.0f;
          break;
        }
        case TwoChannelStorage::X360Fixed16: {
          const float f = c < channels ? t[c] : 0.0f;
          const auto s = static_cast<int16_t>(std::lround(std::clamp(f, -1.0f, 1.0f) * 32767.0f));
          const float encoded = platforms::x360::decodeFixed16(s);
          out[i * 2 + c] = (std::ldexp(encoded, -cls.dsfExpBias) - cls.dsfOffset) / cls.dsfScale;
          break;
        }
      }
    }
  }
  return out;
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

AttachmentClass classifyAttachment(const std::string& name, const std::string& formatName, const std::string& logicalFormat,
                                   const std::string& platform) {
  AttachmentClass c = classifyAttachment(name, formatName);
  if (logicalFormat != platforms::logicalFormatName(platforms::LogicalFormat::Rg16Unorm)) return c;
  c.storage = platform == "ps3" ? TwoChannelStorage::Ps3Packed
              : platform == "x360" ? TwoChannelStorage::X360Fixed16
                                   : TwoChannelStorage::Plain;
  if (c.storage == TwoChannelStorage::X360Fixed16) {
    const platforms::x360::DsfPathSpec path = platforms::x360::dsfPath(platforms::PlatformParams{}.dsfResolvePath);
    c.dsfScale = path.shaderScale;
    c.dsfOffset = path.shaderOffset;
    c.dsfExpBias = path.colorExpBias;
  }
  c.bits = 16;
  if (c.kind == AttachmentKind::Normals) c.normals = NormalEncoding::HalfSphere;
  else if (c.kind != AttachmentKind::Depth) c.kind = AttachmentKind::Quantised;  // unorm16 logical values
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
  if (cls.storage != TwoChannelStorage::None) {  // the logical values, as the shaders read them
    g = logicalTwoChannel(g, n, cls);
    v = logicalTwoChannel(v, n, cls);
    n = 2;
  }
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

std::string previewOf(const AttachmentClass& cls, const OIIO::ImageBuf& image, OIIO::ImageBuf* preview) {
  const OIIO::ImageSpec& in = image.spec();
  const int w = in.width, h = in.height, channels = in.nchannels;
  OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::UINT8);
  preview->reset(spec);
  std::vector<float> texels(size_t(w) * h * channels);
  image.get_pixels(OIIO::ROI(0, w, 0, h, 0, 1, 0, channels), OIIO::TypeDesc::FLOAT, texels.data());
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  if (cls.kind == AttachmentKind::Depth)
    for (size_t i = 0; i < size_t(w) * h; ++i)
      if (const float d = texels[i * channels]; std::isfinite(d) && d < 1.0f) {
        lo = std::min(lo, d);
        hi = std::max(hi, d);
      }
  // Float data is scaled by its own 99th percentile (of each texel's largest colour channel), so
  // that a platform's scaled storage (x360 keeps k_16_16_16_16 as s * 2^-15) shows as well as
  // the reference's float.
  float p99 = 0.0f;
  if (cls.kind == AttachmentKind::FloatData) {
    std::vector<float> peaks;
    for (size_t i = 0; i < size_t(w) * h; ++i) {
      float peak = 0.0f;
      for (int c = 0; c < std::min(channels, 3); ++c)
        if (std::isfinite(texels[i * channels + c])) peak = std::max(peak, texels[i * channels + c]);
      if (peak > 0.0f) peaks.push_back(peak);
    }
    if (!peaks.empty()) {
      auto at = peaks.begin() + std::ptrdiff_t(peaks.size() * 99 / 100);
      std::nth_element(peaks.begin(), at, peaks.end());
      p99 = *at;
    }
  }
  std::string mapping;
  std::vector<float> out(size_t(w) * h * 3, 0.0f);
  for (size_t i = 0; i < size_t(w) * h; ++i) {
    const float* t = &texels[i * channels];
    float* o = &out[i * 3];
    switch (cls.kind) {
      case AttachmentKind::Depth:
        o[0] = o[1] = o[2] = !(t[0] < 1.0f) ? 1.0f : hi > lo ? (t[0] - lo) / (hi - lo) : 0.0f;
        break;
      case AttachmentKind::Normals:
        for (int c = 0; c < 3 && c < channels; ++c)
          o[c] = cls.normals == NormalEncoding::Raw ? t[c] * 0.5f + 0.5f : t[c];
        if (channels == 2 || cls.normals == NormalEncoding::ScaledXY) o[2] = 0.0f;
        break;
      case AttachmentKind::FloatData:
      case AttachmentKind::Quantised:
        for (int c = 0; c < 3; ++c) {
          const float v = std::max(t[std::min(c, channels - 1)], 0.0f);
          o[c] = cls.kind == AttachmentKind::FloatData ? (p99 > 0.0f ? std::min(v / p99, 1.0f) : 0.0f) : v;
        }
        break;
    }
  }
  switch (cls.kind) {
    case AttachmentKind::Depth: {
      std::ostringstream s;
      s << "depth: " << lo << " to " << hi << " as black to white, the far plane (1) white";
      mapping = hi >= lo ? s.str() : "depth: every texel at the far plane (1), white";
      break;
    }
    case AttachmentKind::Normals:
      mapping = cls.normals == NormalEncoding::Raw ? "normals: n * 0.5 + 0.5 as RGB" : "normals: as stored, RGB";
      if (channels == 2 || cls.normals == NormalEncoding::ScaledXY) mapping += " (two encoded channels as R, G; B 0)";
      break;
    case AttachmentKind::FloatData: {
      std::ostringstream s;
      s << "float: c / " << p99 << " per channel (the 99th percentile of the largest channel) clamped to 1, alpha dropped";
      mapping = s.str();
      break;
    }
    case AttachmentKind::Quantised: mapping = "as stored, alpha dropped"; break;
  }
  preview->set_pixels(OIIO::ROI(0, w, 0, h, 0, 1, 0, 3), OIIO::TypeDesc::FLOAT, out.data());
  return mapping;
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
