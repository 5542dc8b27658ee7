#include "platforms/dx10/depth_read.h"

#include <algorithm>
#include <cmath>

namespace parity::platforms::dx10 {

std::string_view formatName(DxgiFormat format) {
  switch (format) {
    case DxgiFormat::R32_TYPELESS: return "R32_TYPELESS";
    case DxgiFormat::D32_FLOAT: return "D32_FLOAT";
    case DxgiFormat::R32_FLOAT: return "R32_FLOAT";
    case DxgiFormat::R24G8_TYPELESS: return "R24G8_TYPELESS";
    case DxgiFormat::D24_UNORM_S8_UINT: return "D24_UNORM_S8_UINT";
    case DxgiFormat::R24_UNORM_X8_TYPELESS: return "R24_UNORM_X8_TYPELESS";
    case DxgiFormat::X24_TYPELESS_G8_UINT: return "X24_TYPELESS_G8_UINT";
  }
  return "?";
}

uint32_t quantizeD24(float depth) {
  double d = std::clamp(std::isnan(depth) ? 0.0 : static_cast<double>(depth), 0.0, 1.0);
  return static_cast<uint32_t>(std::floor(d * 16777215.0 + 0.5));
}

float decodeR24X8(uint32_t d24) { return static_cast<float>(static_cast<double>(d24 & 0xFFFFFFu) / 16777215.0); }

DepthReadOutcome checkDepthRead(const DepthRead& r, DiagnosticList& out) {
  DepthReadOutcome outcome = DepthReadOutcome::Allowed;
  if (r.resourceFormat != DxgiFormat::R24G8_TYPELESS || r.srvFormat != DxgiFormat::R24_UNORM_X8_TYPELESS) {
    out.report("E_DX10_DEPTH_SRV_FORMAT", {r.resource},
               "depth " + r.resource + " is a " + std::string(formatName(r.resourceFormat)) + " resource read through a " +
                   std::string(formatName(r.srvFormat)) +
                   " view; FL10.0 reads depth only as R24_UNORM_X8_TYPELESS of an R24G8_TYPELESS resource (D1)");
    outcome = DepthReadOutcome::Refused;
  }
  if (r.sampleCount > 1) {
    out.report("E_DX10_MSAA_DEPTH_READ", {r.resource},
               "depth " + r.resource + " has " + std::to_string(r.sampleCount) +
                   " samples; FL10.0 has no MSAA load of R24_UNORM_X8_TYPELESS: resolve it to a single-sample "
                   "R24X8 texture with a draw first (D1)");
    outcome = DepthReadOutcome::Refused;
  }
  if (r.boundAsDsv) {
    out.report("W_DX10_SRV_DSV_HAZARD", {r.resource},
               "depth " + r.resource + " is bound as SRV and DSV at once: the runtime nulls the SRV and reads return "
                                       "0 (D1)");
    if (outcome == DepthReadOutcome::Allowed) outcome = DepthReadOutcome::NulledSrv;
  }
  if (!r.resolvedSinceLastDepthWrite) {
    out.report("W_DX10_DEPTH_NOT_RESOLVED", {r.resource},
               "depth " + r.resource + " is read without being copied to R24X8 after its last depth write (D1)");
  }
  return outcome;
}

float sampleDepth(uint32_t d24, DepthReadOutcome outcome) {
  return outcome == DepthReadOutcome::Allowed ? decodeR24X8(d24) : 0.0f;
}

}  // namespace parity::platforms::dx10
