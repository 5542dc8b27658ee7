// Accepted images per device: besides its primary golden (golden/<technique>/<scene>/<platform>.png,
// the reference device's), a golden group may hold images accepted on other devices,
// golden/<technique>/<scene>/<platform>.<name>.png, each with a manifest entry under
// "accepted": {"<technique>/<scene>/<platform>": {"<name>": {...}}}:
//
//   "devices":      ["gl-zink", "vk-*nvidia*"]   globs over device names it was accepted on
//   "file", "width", "height", "pixel_sha1"       the image
//   "blessed", "reason", "blessed_from": {run, case, device, renderer, driver, api,
//                                         project_commit, rendered}
//   "evidence":     its measure against the primary golden at bless time (against, primary_sha1,
//                   diff, flip: mean, max, p50, p99, and the diagnosis)
//
// A case passes when its image matches the primary golden, or an accepted image whose devices
// match the case's device, under the case's judge: the device's budget (harness/run/budgets.h)
// when one matches, else its tolerance. Only `parity bless --device` writes accepted images; it
// never touches the primary golden nor its "goldens" entry.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/compare/diff.h"
#include "harness/compare/flip.h"
#include "harness/run/golden.h"

namespace parity::harness {

// golden/<technique>/<scene>/<platform>.<name>.png, for the group key "technique/scene/platform".
std::string acceptedImagePath(const std::string& goldenDir, const std::string& groupKey, const std::string& name);

// A name an accepted image may have: letters, digits, '-', '_' and inner dots (a device name).
bool isAcceptedName(const std::string& name);

// The manifest's "accepted" section, when present: objects of objects, names as above, each
// with a non-empty "devices" array of globs. False with "MANIFEST: accepted: KEY: NAME: reason".
bool checkAccepted(const nlohmann::json& accepted, const std::string& manifestPath, std::string* error);

// The accepted images of a group whose "devices" match `device`, by name.
std::vector<std::pair<std::string, nlohmann::json>> acceptedFor(const nlohmann::json& manifest, const std::string& groupKey,
                                                                 const std::string& device);

// One image against one accepted image under the case's judge. With a budget: its fuzzy rule
// and FLIP percentile; without: the tolerance's golden thresholds and FLIP mean.
struct ImageJudgement {
  DiffResult diff;    // under the tolerance's golden thresholds
  FlipResult flip;    // LDR-FLIP of the image against the accepted one (zero when identical)
  bool images = false;  // both read, of one size
  bool pass = false;
  nlohmann::json budget;  // when a budget judged: the budget, what it measured, whether it held
  std::string summary;    // one line: what was over, when it fails
};
ImageJudgement judgeImage(const std::string& image, const std::string& accepted, const Tolerance& tolerance);

// The plain p-th percentile (0 < p <= 100, nearest rank) of the per-pixel FLIP error.
double flipPercentile(const FlipResult& flip, double p);

}  // namespace parity::harness
