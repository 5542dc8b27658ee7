// Goldens: golden/<technique>/<scene>/<platform>.png, one per platform and shared by both
// backends, with golden/manifest.json recording each one's provenance and the reason it was
// blessed. Goldens are only ever written by `parity bless`, atomically (temporary file in the
// same folder, then rename), never by `parity run`.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/io/atomic_file.h"
#include "harness/compare/attachments.h"
#include "harness/compare/diff.h"
#include "harness/run/budgets.h"
#include "harness/run/run.h"

namespace parity::harness {

// golden/<technique>/<scene>/<platform>.png
std::string goldenPath(const std::string& goldenDir, const std::string& technique, const std::string& scene,
                       const std::string& platform);
// "technique/scene/platform", the manifest key of a golden.
std::string goldenKey(const std::string& technique, const std::string& scene, const std::string& platform);

// The manifest ({"goldens": {key: {...}}}); an absent file reads as empty. False with a reason
// for an unreadable one.
bool readManifest(const std::string& goldenDir, nlohmann::json* manifest, std::string* error);

// Tolerances (golden/tolerances.json): {"default": {...}, "cases": {"glob": {...}}} where each
// entry may set golden_fail, golden_fail_percent, golden_hard_fail, parity_fail (the GL↔VK
// budget) and parity_fail_percent; values are per channel in [0, 1].
// Also golden_flip_mean (the LDR-FLIP mean that fails a golden comparison) and, for per-pass
// targets, attachment_normal_degrees, attachment_depth_absolute, attachment_float_relative,
// attachment_quantised_steps (steps of the target format's bits) and attachment_fail_percent.
// A target relaxed by name: "targets": {"CASE_GLOB": {"TARGET_GLOB": {attachment_* thresholds,
// "reason": "why (required)"}}}; the last matching entry wins over the case's attachment_*.
// Named budgets per device class and case glob: "budgets": [...] (harness/run/budgets.h).
struct TargetTolerance {
  std::string target;  // glob over the target's name, e.g. "gbuffer.*"
  AttachmentTolerance attachments;
  std::string reason;
  std::string source;  // "FILE: targets: CASE_GLOB: TARGET_GLOB"
};

struct Tolerance {
  DiffThresholds golden;  // rendered image vs golden
  DiffThresholds parity;  // GL vs Vulkan
  double flipMean = 0.01;
  AttachmentTolerance attachments;
  std::vector<TargetTolerance> targets;
  // The last budget matching the case's device and id: when set it judges the image against its
  // accepted images instead of `golden` and `flipMean`.
  std::optional<Budget> budget;
  std::string source = "built-in default";
  // The thresholds of target `name`: its last matching TargetTolerance, else `attachments`.
  const TargetTolerance* forTarget(const std::string& name) const;
};
bool loadTolerance(const std::string& file, const CaseKey& key, Tolerance* out, std::string* error);
// The whole file, every entry whether or not a case matches it: known keys only, numbers >= 0,
// percentages in [0, 100]. An absent file is valid (the built-in defaults). `parity run` checks
// it before anything renders, so a bad file fails the run before it writes any output.
bool checkTolerancesFile(const std::string& file, std::string* error);
bool checkTolerances(const nlohmann::json& tolerances, const std::string& file, std::string* error);

// Expectations (golden/expectations.json): {"expectations": [{"case": "glob over case ids",
// "driver": "optional glob over renderer and driver strings", "result": "Fail|Crash|Timeout|
// Nondeterministic|ParityWarning|Skip", "reason": "why (required)", "bug": "optional link",
// "expires": "optional YYYY-MM-DD"}]}.
struct Expectation {
  std::string casePattern, driverPattern, reason;
  CaseResult result = CaseResult::Fail;
  // Non-empty: the entry expects an error-level platform diagnostic whose code matches this glob
  // (e.g. "E_MRT_FORMAT_MISMATCH") instead of a result; such a diagnostic then does not fail the
  // case. Matched as narrowly as the problem: `target` (glob) must match one of the targets the
  // diagnostic names and `pass` (glob) the pass it fired in, when given.
  std::string diagnosticPattern, targetPattern, passPattern;
  // Optional: where the problem is tracked, and the last day (YYYY-MM-DD, UTC) the entry holds;
  // after it the entry still applies but is reported as expired (a failure under --strict), so a
  // known failure cannot stay expected unseen for ever.
  std::string bug, expires;
  bool expired = false;  // today (UTC, when the file was loaded) is after `expires`
  // Whether this diagnostic expectation matches a diagnostic (code, targets, pass).
  bool matchesDiagnostic(const std::string& code, const std::vector<std::string>& targets, const std::string& pass) const;
};
// Entries whose `expires` is before today (UTC) are marked expired.
bool loadExpectations(const std::string& file, std::vector<Expectation>* out, std::string* error);
// The entry as results.json and the reports show it: case, driver, result or diagnostic, reason,
// bug, expires, expired.
nlohmann::json toJson(const Expectation& e);
// First result expectation matching the case id and "renderer | driver"; null when none.
const Expectation* findExpectation(const std::vector<Expectation>& list, const std::string& caseId,
                                   const std::string& deviceText);
// Every diagnostic expectation matching the case id and "renderer | driver".
std::vector<const Expectation*> findDiagnosticExpectations(const std::vector<Expectation>& list, const std::string& caseId,
                                                           const std::string& deviceText);

struct BlessOptions {
  std::string from;       // a run's output folder (holds results.json)
  std::string goldenDir;  // default: the project's golden/
  RunFilters filters;
  // Explicit single-backend acceptance: bless from this backend's image even though the run did
  // not show GL and Vulkan agreeing bit-exactly. Needs `reason`.
  std::string backend;
  // Accept this device's images as accepted images of their groups (harness/run/accepted_images.h)
  // beside the primary golden, never over it. Needs `reason`.
  std::string device;
  std::string reason;
  // The claims every blessed golden needs (harness/run/evidence.h); default: GOLDEN/evidence.json.
  std::string evidenceFile;
  bool dryRun = false;
};
int blessGoldens(const BlessOptions& options);
// `parity bless --device D` (harness/run/bless_device.cpp); blessGoldens hands it such options.
int blessAcceptedImages(const BlessOptions& options);

}  // namespace parity::harness
