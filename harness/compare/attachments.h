// Per-attachment comparison: every target a technique declares (Technique::targets()) is
// compared with its per-pass golden by a metric that fits what it holds. Normals: angular error
// in degrees after decoding; depth: absolute error; float data (HDR colour, light buffers):
// relative error; 8-bit data: per-channel error with a tolerance derived from the bits.
#pragma once

#include <string>

#include <OpenImageIO/imagebuf.h>
#include <nlohmann/json.hpp>

namespace parity::harness {

enum class AttachmentKind { Normals, Depth, FloatData, Quantised };
const char* attachmentKindName(AttachmentKind k);

// How a normal target's texels decode to a vector.
enum class NormalEncoding {
  Scaled,      // unorm xyz = n * 0.5 + 0.5
  ScaledXY,    // unorm xy = n.xy * 0.5 + 0.5, z = sqrt(1 - x^2 - y^2) (two-channel targets)
  Raw,         // float / snorm xyz as stored
  HalfSphere,  // two channels n'.xy * 0.5 + 0.5 of the inferred-lighting half-sphere mapping
               // (shaders/include/normal_encoding.glsl), decoded by its eq. 2-3
};

// How the dumped attachment of a two-channel logical target (LogicalFormat::Rg16Unorm) stores its
// values on the case's platform; the comparison decodes them to the logical values first.
enum class TwoChannelStorage {
  None,         // not a two-channel logical target: texels compared as stored
  Plain,        // reference RG32F, dx10 RG16_UNORM: the values themselves
  Ps3Packed,    // A8R8G8B8 holding two little-endian 16-bit words (host r, g = X; b, a = Y)
  X360Fixed16,  // RG16_SNORM holding the k_16_16 int16 s of c = v * scale + offset (X2)
};

struct AttachmentClass {
  AttachmentKind kind = AttachmentKind::Quantised;
  NormalEncoding normals = NormalEncoding::Scaled;
  int bits = 8;  // per channel, for quantised data
  TwoChannelStorage storage = TwoChannelStorage::None;
  float dsfScale = 1.0f, dsfOffset = 0.0f;  // X360Fixed16: the DSF path's c = v * scale + offset
  int dsfExpBias = 0;                       // and its color_exp_bias
};

// Classifies a target by its logical name and RHI format name (rhi::formatInfo().name): names
// containing "normal" are normals, depth formats or names containing "depth" are depth, float
// formats are float data, the rest quantised. Decoding of normals follows the format.
AttachmentClass classifyAttachment(const std::string& name, const std::string& formatName);
// The same for a target the technique planned as `logicalFormat` (platforms' logicalFormatName,
// empty when unknown) on `platform`: a two-channel logical target is decoded from the platform's
// storage (default platform parameters, as `parity run` renders), and when it holds normals
// they are the half-sphere mapping.
AttachmentClass classifyAttachment(const std::string& name, const std::string& formatName, const std::string& logicalFormat,
                                   const std::string& platform);

struct AttachmentTolerance {
  double normalDegrees = 1.0;       // per-pixel angular error that counts as differing
  double depthAbsolute = 1e-5;      // per-pixel absolute depth error that counts as differing
  double floatRelative = 1e-3;      // per-pixel relative error that counts as differing
  double quantisedSteps = 1.5;      // per-channel error in steps of the format (1 / (2^bits - 1))
  double failPercent = 0.05;        // share of differing pixels allowed
};

struct AttachmentMetrics {
  bool ok = false;        // compared (same size)
  std::string error;      // when !ok
  AttachmentClass cls;
  std::string metric;     // "angular_error_deg", "absolute_error", "relative_error", "channel_error"
  double max = 0, mean = 0, threshold = 0;
  uint64_t pixels = 0, differing = 0;
  bool pass = false;
};

AttachmentMetrics compareAttachment(const AttachmentClass& cls, const OIIO::ImageBuf& golden, const OIIO::ImageBuf& image,
                                    const AttachmentTolerance& tolerance);

nlohmann::json toJson(const AttachmentMetrics& m);

// An 8-bit RGB view of a target whose data a PNG viewer would not show (float, depth, normals),
// for the report's thumbnails. Returns the mapping in words, e.g. "depth: 0.93 to 0.99 as black
// to white, the far plane (1) white":
//   depth      grey ramp over the texels' range below the far plane (1.0), which stays white;
//   normals    three channels n * 0.5 + 0.5 (float) or as stored (unorm); two-channel encoded
//              normals as (x, y, 0);
//   float data c / p per channel, clamped, p the 99th percentile of the texels' largest colour
//              channel (HDR colour, light buffers, whatever scale a platform stores them at).
std::string previewOf(const AttachmentClass& cls, const OIIO::ImageBuf& image, OIIO::ImageBuf* preview);

}  // namespace parity::harness
