// Executes a parsed shader-test script (harness/script_parser.h) on an rhi::Device, with
// Amber's conventions: DRAW_RECT/DRAW_GRID positions in framebuffer pixels with (0, 0) at the
// top-left (row 0), a default 250x250 framebuffer, each RUN in its own render pass that loads the
// attachments, CLEAR clearing colour, depth and stencil of a pipeline's attachments.
// Only the RHI is used: no GL or Vulkan type appears here.
#pragma once

#include <string>
#include <vector>

#include "harness/script_parser.h"
#include "rhi/rhi.h"

namespace parity::harness::script {

enum class Verdict { Pass, Fail, Skip };
const char* verdictName(Verdict v);  // "PASS", "FAIL", "SKIP"

struct ExpectResult {
  int line = 0;
  bool pass = false;
  std::string message;  // what was checked; on failure the first failing pixel/element and values
};

struct RunResult {
  Verdict verdict = Verdict::Pass;
  std::string reason;  // Fail/Skip: one line
  std::vector<ExpectResult> expects;
};

struct RunOptions {
  std::string platform = "reference";  // platform layer the script runs on
};

// Why the script cannot run on this backend/platform before any device exists (REQUIRE lines,
// unsupported constructs); empty when it can.
std::string skipReasonBeforeRun(const Script& script, const std::string& backend, const RunOptions& options);

// Runs the whole script. A construct found unsupported while running makes the result a Skip
// naming it; a broken shader, a failed resource creation or a failed EXPECT makes it a Fail.
RunResult runScript(const Script& script, rhi::Device& device, const RunOptions& options = {});

}  // namespace parity::harness::script
