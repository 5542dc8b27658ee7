// Executes a parsed shader-test script (harness/scripts/script.h) on an rhi::Device, with
// Amber's conventions: DRAW_RECT/DRAW_GRID positions in framebuffer pixels with (0, 0) at the
// top-left (row 0), a default 250x250 framebuffer, each RUN in its own render pass that loads the
// attachments, CLEAR clearing colour, depth and stencil of a pipeline's attachments.
// Only the RHI is used: no GL or Vulkan type appears here.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "harness/scripts/script.h"
#include "rhi/rhi.h"

namespace parity::harness::script {

enum class Verdict { Pass, Fail, Skip };
const char* verdictName(Verdict v);  // "PASS", "FAIL", "SKIP"
Verdict verdictFromName(const std::string& name);  // verdictName's inverse; anything else is Fail

struct ExpectResult {
  int line = 0;
  bool pass = false;
  std::string message;  // what was checked; on failure the first failing pixel/element and values
  // A failed check that piglit calls "warn" (`probe warn`), not a failure (see RunResult::verdict).
  bool warning = false;
};

struct RunResult {
  // piglit's "warn" (a `probe warn` that failed, no check that failed) is no failure there, and
  // parity has no verdict of its own for it: it is a Pass whose reason names the warning
  // ("warn: ..."), and whose expects list the failed check with `warning` set.
  Verdict verdict = Verdict::Pass;
  std::string reason;  // Fail/Skip: one line; Pass: empty, or piglit's warning
  std::vector<ExpectResult> expects;
  // What the backend did off its usual path (rhi::Device::takeNotes), and what the script asked
  // for that reached no device (piglit's `hint`).
  std::vector<std::string> notes;
};

struct RunOptions {
  std::string platform = "reference";  // platform layer the script runs on
  // Where the device compiles no OpenGL GLSL itself (feature "openGlGlsl"): a device whose driver
  // does, asked whether an OpenGL GLSL shader that glslang cannot port is valid, in a context of
  // the script's profile. A shader it compiles is then a skip naming glslang's limit, one it
  // refuses a failure with its log. Unset, or returning null: such a shader is a failure.
  std::function<rhi::Device*()> openGlCompiler;
};

// The platforms a script runs on: those its REQUIRE platform lines name, else every platform.
std::vector<std::string> allowedPlatforms(const Script& script);

// Why the script cannot run on this backend/platform before any device exists (REQUIRE lines,
// unsupported constructs); empty when it can.
std::string skipReasonBeforeRun(const Script& script, const std::string& backend, const RunOptions& options);

// The first DEVICE_FEATURE or DEVICE_EXTENSION of the script the device does not offer, as a
// skip reason; empty when it offers them all.
std::string deviceRequirementMissing(const Script& script, const rhi::DeviceInfo& info);

// Whether the script runs in an OpenGL compatibility context (rhi::DeviceDesc::
// glCompatibilityProfile), as piglit's shader_runner runs a file that requires GLSL before 1.40:
// what those shaders read (gl_Color, gl_FragColor, gl_TexCoord ...) is there. A file requiring
// 1.40 or later runs in a core context, as there (Mesa offers some extensions, 64-bit floats
// among them, only in core contexts), and so does AmberScript.
bool compatibilityProfile(const Script& script);

// Runs the whole script. A construct found unsupported while running makes the result a Skip
// naming it; a broken shader, a failed resource creation or a failed EXPECT makes it a Fail.
RunResult runScript(const Script& script, rhi::Device& device, const RunOptions& options = {});

// ---------------------------------------------------------------------------------------------
// Cases: one script on one backend and one platform. `parity test` and `parity run` share these.
// ---------------------------------------------------------------------------------------------
struct ScriptCase {
  std::string script;    // path of the .amber file
  std::string backend;   // "gl" or "vk"
  std::string platform;  // "reference", "dx10", "ps3", "x360"
  bool expectFail = false;  // *.expect_fail.amber: passes only when the script fails
  std::string id() const;   // "<script>/<backend>/<platform>"
};

bool isExpectFail(const std::string& path);
// *.amber files of each folder (recursively, sorted) and each file named; `error` names a path
// that does not exist.
std::vector<std::string> collectScripts(const std::vector<std::string>& paths, std::string* error);
// Every script x backend x platform (platforms intersected with what each script allows; an empty
// `platforms` means all four). A script that does not parse still yields its cases (they fail).
std::vector<ScriptCase> listScriptCases(const std::vector<std::string>& paths, const std::vector<std::string>& backends,
                                        const std::vector<std::string>& platforms, std::string* error);
// Runs one case in this process: parses, creates the backend's device (an unavailable backend
// is a Skip), runs, and turns RHI validation errors into failures. *.expect_fail.amber is
// applied: Fail becomes Pass ("failed as expected: ...") and Pass becomes Fail. A caller that
// wants process isolation runs `parity test --in-process --backend B --platform P FILE`, which
// prints this result as one JSON line per platform.
RunResult runScriptCase(const ScriptCase& c);
// Applies the *.expect_fail.amber rule to a result.
RunResult applyExpectFail(RunResult r, bool expectFail);

}  // namespace parity::harness::script
