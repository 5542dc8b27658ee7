// DX10 (feature level 10.0): depth is readable only through R24X8 (D1).
//
// The DXGI FL10.0 format table: D24_UNORM_S8_UINT is a depth/stencil target only;
// R24_UNORM_X8_TYPELESS supports shader ld, sample and sample_c but not MSAA load; the resource
// must be R24G8_TYPELESS to be viewed both ways. So depth is read through an R24X8 view of a
// single-sample R24G8_TYPELESS resource (the paper: "the depth surface must be resolved to an
// R24X8 texture before it can be read"), never from an MSAA depth surface, and a subresource
// bound as SRV and DSV has its SRV nulled by the runtime (reads return 0; read-only DSVs only
// arrive in D3D11). The value read is D24 / 16777215 with D24 = round(d * 16777215).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "platforms/common/diagnostics.h"
#include "platforms/common/platform.h"
#include "platforms/common/platform_params.h"

namespace parity::platforms::dx10 {

// DXGI_FORMAT values (FL10.0 table rows 44-47 and the float-depth family).
enum class DxgiFormat : uint8_t {
  R32_TYPELESS = 39,
  D32_FLOAT = 40,
  R32_FLOAT = 41,
  R24G8_TYPELESS = 44,
  D24_UNORM_S8_UINT = 45,
  R24_UNORM_X8_TYPELESS = 46,
  X24_TYPELESS_G8_UINT = 47,
};

std::string_view formatName(DxgiFormat format);

// Quantisation to 24-bit unorm: D24 = round(d * 16777215), d clamped to [0, 1].
uint32_t quantizeD24(float depth);
// R24_UNORM decode: D24 / 16777215, correctly rounded to fp32.
float decodeR24X8(uint32_t d24);

struct DepthRead {
  std::string resource;  // the depth resource's name
  DxgiFormat resourceFormat = DxgiFormat::R24G8_TYPELESS;
  DxgiFormat srvFormat = DxgiFormat::R24_UNORM_X8_TYPELESS;
  uint32_t sampleCount = 1;
  bool boundAsDsv = false;                // bound for depth writes while the SRV is bound
  bool resolvedSinceLastDepthWrite = true;  // copied to the R24X8 texture after the last depth write
};

enum class DepthReadOutcome : uint8_t {
  Allowed = 0,  // reads return D24 / 16777215
  Refused,      // the view cannot be created on FL10.0
  NulledSrv,    // the runtime replaced the SRV by NULL: reads return 0
};

// E_DX10_DEPTH_SRV_FORMAT, E_DX10_MSAA_DEPTH_READ, W_DX10_SRV_DSV_HAZARD, W_DX10_DEPTH_NOT_RESOLVED.
DepthReadOutcome checkDepthRead(const DepthRead& read, DiagnosticList& out);

// What a shader reads for a stored D24 under `outcome` (0 when the SRV was nulled or refused).
float sampleDepth(uint32_t d24, DepthReadOutcome outcome);

}  // namespace parity::platforms::dx10
