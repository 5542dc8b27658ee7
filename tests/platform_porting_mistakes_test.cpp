// Porting mistakes, each planted alone in a small deferred technique (tests/mini_port.h) and
// rendered through the frame path every parity command uses (techniques::renderFrameTexels: the
// technique draws through a PlatformDevice) on every platform, on both backends. Each mistake
// raises its rule's codes on the platforms where it breaks and nothing elsewhere; the clean
// technique raises nothing anywhere. So every rule below fires from a real render, on the
// technique's own calls (docs/HARNESS.md, "What each diagnostic code means").
//
// Some mistakes break the host too, and the RHI's validation layer says so with its own ids (a
// bilinear sampler on an integer depth texture, a depth surface sampled by the pass it is
// attached to, mixed sample counts); those are expected per row as well.
#include <gtest/gtest.h>

#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "mini_port.h"
#include "platforms/common/platform_params.h"
#include "techniques/frame.h"
#include "test_support.h"

using namespace parity;
using platforms::PlatformId;

namespace {

using Codes = std::set<std::string>;

struct Row {
  std::string mistake;  // a MistakeInfo name
  std::vector<std::pair<std::string, std::string>> params;  // platform parameters of the row
  std::map<PlatformId, Codes> codes;  // the platform diagnostics expected, per platform (absent: none)
  Codes host;                          // RHI validation ids expected on every platform
  uint32_t width = 80, height = 48;    // a size every platform's tiles (80x16) and resolves (8) divide
  // Driver validation messages the row's host calls may raise (their VUIDs), where the host
  // itself cannot do what the mistake asks: lavapipe cannot blend RG16_SNORM, x360's k_16_16
  // storage. Any other driver message fails the test.
  Codes driver = {};
};

constexpr PlatformId kRef = PlatformId::Reference, kDx10 = PlatformId::Dx10, kPs3 = PlatformId::Ps3,
                     kX360 = PlatformId::X360;
const PlatformId kPlatforms[] = {kRef, kDx10, kPs3, kX360};
const std::vector<std::pair<std::string, std::string>> kPathA = {{"x360.dsf_resolve_path", "naive-a"}};
const std::vector<std::pair<std::string, std::string>> kHdr7e3 = {{"x360.hdr_format", "k_2_10_10_10_float"}};

const std::vector<Row>& rows() {
  static const std::vector<Row> table = {
      {"clean", {}, {}, {}},
      {"clean", kPathA, {{kX360, {"W_RESOLVE_PRECISION", "W_FIXED16_PRECISION"}}}, {}},
      {"clean", kHdr7e3, {}, {}},
      {"clean", {{"ps3.mrt_rule", "same-bpp"}}, {}, {}},
      {"packed-blend",
       {},
       // dx10 only allows blending R16G16_UNORM (optional at feature level 10.0).
       {{kPs3, {"E_PACKED_BLEND"}}, {kX360, {"W_FIXED16_MULT_BLEND"}}, {kDx10, {"W_CAP_OPTIONAL"}}},
       {},
       80,
       48,
       {"VUID-VkGraphicsPipelineCreateInfo-renderPass-06062"}},
      {"packed-filter", {}, {{kPs3, {"W_PACKED_VIEW_MISMATCH", "W_PACKED_FILTER"}}, {kX360, {"E_EDRAM_NOT_READABLE"}}}, {}},
      {"packed-writemask", {}, {{kPs3, {"W_PACKED_PARTIAL_WRITEMASK"}}}, {}},
      {"hdr-above-32", {}, {{kX360, {"W_FIXED16_RANGE_CLAMP"}}}, {}},
      {"hdr-above-32", kHdr7e3, {{kX360, {"W_FLOAT7E3_RANGE_CLAMP"}}}, {}},
      {"hdr-nan", {}, {{kX360, {"W_FIXED16_NAN"}}}, {}},
      {"hdr-nan", kHdr7e3, {{kX360, {"W_FLOAT7E3_RANGE_CLAMP"}}}, {}},
      {"hdr-multiply-blend", {}, {{kX360, {"W_FIXED16_MULT_BLEND"}}}, {}},
      {"depth-feedback", {}, {{kPs3, {"W_DEPTH_FEEDBACK"}}}, {}},
      // The host cannot filter the integer texture the other platforms read depth through.
      {"depth-filtered",
       {},
       {{kPs3, {"W_DEPTH_AS_COLOR_FILTER"}}},
       {"E_BINDING_FILTER_FORMAT"}},
      {"depth-surface-sampled",
       {},
       {{kDx10, {"W_DX10_DEPTH_NOT_RESOLVED"}}, {kX360, {"E_EDRAM_NOT_READABLE"}}},
       {}},
      {"depth-sampled-while-bound",
       {},
       {{kDx10, {"W_DX10_SRV_DSV_HAZARD", "W_DX10_DEPTH_NOT_RESOLVED"}}, {kX360, {"E_EDRAM_NOT_READABLE"}}},
       {"E_BINDING_FEEDBACK"}},
      // A depth texture of the technique's own is a render target too: on x360 an EDRAM surface.
      {"own-float-depth-sampled",
       {},
       {{kDx10, {"E_DX10_DEPTH_SRV_FORMAT", "W_DX10_DEPTH_NOT_RESOLVED"}}, {kX360, {"E_EDRAM_NOT_READABLE"}}},
       {}},
      {"msaa-depth-sampled",
       {},
       {{kDx10, {"E_DX10_MSAA_DEPTH_READ", "W_DX10_DEPTH_NOT_RESOLVED"}}, {kX360, {"E_EDRAM_NOT_READABLE"}}},
       {}},
      {"sample-before-resolve", {}, {{kX360, {"E_EDRAM_NOT_READABLE"}}}, {}},
      {"sample-edram-surface", {}, {{kX360, {"E_EDRAM_NOT_READABLE"}}}, {}},
      {"stale-resolve", {}, {{kX360, {"E_EDRAM_NOT_READABLE"}}}, {}},
      {"mixed-mrt", {}, {{kPs3, {"E_MRT_FORMAT_MISMATCH"}}}, {}},
      {"mixed-mrt", {{"ps3.mrt_rule", "same-bpp"}}, {{kPs3, {"E_MRT_BPP_MISMATCH"}}}, {}},
      {"shared-blend", {}, {{kPs3, {"W_MRT_SHARED_BLEND"}}}, {}},
      // The pack's code, and the capability table's row for the format (ps3 renders no Y16_X16).
      {"own-rg16-target", {}, {{kPs3, {"E_RSX_NO_RG16_SURFACE", "E_CAP_RENDER_FORMAT"}}}, {}},
      // Every 4x target is W_CAP_OPTIONAL on dx10, where multisampling is optional.
      {"packed-msaa-resolve", {}, {{kPs3, {"E_PACKED_MSAA_RESOLVE"}}, {kDx10, {"W_CAP_OPTIONAL"}}}, {}},
      {"unaligned-resolve", {}, {{kX360, {"E_RESOLVE_ALIGNMENT"}}}, {}},
      {"d3d10-centres", {}, {{kX360, {"W_D3D9_PIXEL_CENTER"}}}, {}},
      {"quad-d3d10-centres", {}, {{kX360, {"W_D3D9_PIXEL_CENTER"}}}, {}},
      {"mixed-centres", {}, {{kX360, {"W_D3D9_PIXEL_CENTER", "I_HALFPIXEL_MODE_CHANGE"}}}, {}},
      {"lbuffer-before-resolve", {}, {{kX360, {"E_USE_BEFORE_RESOLVE"}}}, {}},
      {"lbuffer-over-depth", {}, {{kX360, {"E_LBUF_DEPTH_ALIAS", "W_RT_SAME_BASE"}}}, {}},
      {"gbuffer-same-base", {}, {{kX360, {"W_RT_SAME_BASE", "E_GBUF_OVERLAP"}}}, {}},
      {"scratch-over-depth", {}, {{kX360, {"E_EDRAM_OVERLAP"}}}, {}},
      // A surface beyond EDRAM also overflows the budget of the pass that binds it; and at 960x544
      // the frame colour, placed after the G-buffer and the light buffer, wraps past tile 2047.
      {"surface-too-large",
       {},
       {{kX360, {"E_EDRAM_SURFACE_TOO_LARGE", "E_EDRAM_OVERLAP", "W_EDRAM_WRAP", "E_CAP_EDRAM_BYTES"}},
        {kDx10, {"W_CAP_OPTIONAL"}}},
       {},
       960,
       544},
      {"own-target-sampled", {}, {{kX360, {"E_EDRAM_NOT_READABLE"}}}, {}},
      {"mrt-msaa-mismatch",
       {},
       {{kX360, {"E_MRT_SURFACE_INFO_MISMATCH"}}, {kDx10, {"W_CAP_OPTIONAL"}}},
       {"E_PASS_ATTACHMENT_SAMPLES"}},
      {"normal-out-of-range",
       kPathA,
       {{kX360, {"W_RESOLVE_SIGN_LOSS", "W_RESOLVE_RANGE_CLAMP", "W_RESOLVE_PRECISION", "W_FIXED16_PRECISION"}}},
       {}},
  };
  return table;
}

std::string joined(const Codes& codes) {
  std::string s;
  for (const std::string& c : codes) s += (s.empty() ? "" : " ") + c;
  return s.empty() ? "-" : s;
}

std::string rowName(const Row& r) {
  std::string name = r.mistake;
  for (const auto& [k, v] : r.params) name += " (" + k + "=" + v + ")";
  return name;
}

class PortingMistakes : public ::testing::TestWithParam<std::string> {};

// Every row on every platform: the platform's codes, exactly, and the host's validation ids.
TEST_P(PortingMistakes, EachMistakeRaisesItsRulesWhereItBreaksAndNothingElsewhere) {
  test::registerMiniPorts();
  std::set<std::string> host;  // the validation ids of the current render
  const Row* current = nullptr;
  rhi::DeviceDesc desc;
  desc.backend = GetParam();
  desc.debug = true;
  desc.onValidationError = [&](const std::string& id, const std::string&) { host.insert(id); };
  desc.log = [&](const std::string& message) {
    for (const std::string& vuid : current ? current->driver : Codes{})
      if (message.find(vuid) != std::string::npos) return;
    ADD_FAILURE() << "driver debug message: " << message;
  };
  std::unique_ptr<rhi::Device> device = test::makeDeviceWith(desc);
  if (!device) return;
  std::ostringstream table;  // the note's table: mistake x platform -> codes
  table << "| mistake | reference | dx10 | ps3 | x360 | host validation |\n|---|---|---|---|---|---|\n";
  for (const Row& row : rows()) {
    current = &row;
    table << "| " << rowName(row);
    Codes hostSeen;
    for (PlatformId platform : kPlatforms) {
      techniques::FrameRequest r;
      r.technique = row.mistake == "clean" ? "mini-port" : "mini-port:" + row.mistake;
      r.platform = platform;
      r.width = row.width;
      r.height = row.height;
      for (const auto& [name, value] : row.params) {
        std::string error;
        ASSERT_TRUE(platforms::setParameter(r.platformParams, name, value, &error)) << error;
      }
      host.clear();
      techniques::FrameResult result = techniques::renderFrameTexels(*device, r);
      ASSERT_TRUE(result.ok) << rowName(row) << " on " << platforms::platformName(platform) << ": " << result.error;
      Codes fired;
      for (const platforms::Diagnostic& d : result.diagnostics) {
        fired.insert(d.code);
        // Every diagnostic of a technique's call names where it fired and what.
        EXPECT_FALSE(d.targets.empty() && d.pass.empty()) << d.format();
      }
      const auto expected = row.codes.find(platform);
      EXPECT_EQ(joined(fired), joined(expected == row.codes.end() ? Codes{} : expected->second))
          << rowName(row) << " on " << platforms::platformName(platform);
      hostSeen.insert(host.begin(), host.end());
      table << " | " << joined(fired);
    }
    EXPECT_EQ(joined(hostSeen), joined(row.host)) << rowName(row) << ": the host's validation ids";
    table << " | " << joined(hostSeen) << " |\n";
  }
  std::printf("%s", table.str().c_str());
}

INSTANTIATE_TEST_SUITE_P(Backends, PortingMistakes, ::testing::ValuesIn(test::allBackends()), test::BackendName());

}  // namespace
