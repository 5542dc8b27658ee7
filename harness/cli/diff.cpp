// `parity diff`: two images compared with idiff's thresholds and exit codes, and optionally FLIP,
// a heat map and the run's diagnosis of the difference.
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <optional>

#include "harness/cli/commands.h"
#include "harness/compare/diagnosis.h"
#include "harness/compare/diff.h"
#include "harness/compare/flip.h"
#include "harness/io/image_io.h"

namespace parity::harness {

namespace {

int fail(const std::string& message, int code = 2) { return reportError(message, code); }

struct FlipOptions {
  bool enabled = false;
  std::string map;                                           // magma error map to write
  double fail = std::numeric_limits<double>::infinity();     // FLIP mean that fails
};

int cmdDiff(const std::string& a, const std::string& b, const DiffThresholds& t, const std::string& heatmap, bool json,
            const FlipOptions& flipOptions, bool explain) {
  DiffResult r = diffFiles(a, b, t);
  bool sizesMatch = r.verdict != DiffVerdict::FileError && r.verdict != DiffVerdict::SizeMismatch;
  // --explain: the run's diagnosis on any two images, A taken as the expected one.
  std::optional<Diagnosis> diagnosis;
  if (explain && sizesMatch && r.verdict != DiffVerdict::Pass) {
    OIIO::ImageBuf ia, ib;
    std::string error;
    if (!readImage(a, &ia, &error) || !readImage(b, &ib, &error)) return fail(error, static_cast<int>(DiffVerdict::FileError));
    diagnosis = diagnose(ia, ib);
  }
  FlipResult flip;
  bool wantFlip = flipOptions.enabled || !flipOptions.map.empty() || std::isfinite(flipOptions.fail);
  if (wantFlip && sizesMatch) {
    OIIO::ImageBuf ia, ib;
    std::string error;
    if (!readImage(a, &ia, &error) || !readImage(b, &ib, &error)) return fail(error, static_cast<int>(DiffVerdict::FileError));
    flip = computeLdrFlip(ia, ib);
    if (!flip.ok) return fail(a + ": FLIP: " + flip.error, static_cast<int>(DiffVerdict::FileError));
    // The FLIP mean is one more failing condition next to idiff's.
    if (flip.mean > flipOptions.fail && r.verdict != DiffVerdict::Fail) r.verdict = DiffVerdict::Fail;
    if (!flipOptions.map.empty() && !writeFlipMap(flip, flipOptions.map, &error))
      return fail(error, static_cast<int>(DiffVerdict::FileError));
  }
  if (json) {
    nlohmann::json j = toJson(r);
    j["a"] = a;
    j["b"] = b;
    if (flip.ok) j["flip"] = toJson(flip);
    if (explain) j["diagnosis"] = diagnosis ? toJson(*diagnosis) : nlohmann::json();
    std::cout << j.dump(2) << std::endl;
  } else {
    std::printf("%s\n", summaryLine(r).c_str());
    if (flip.ok)
      std::printf("FLIP mean %.6g, weighted quartiles %.6g / %.6g / %.6g, min %.6g, max %.6g (%.2f pixels per degree)\n",
                  flip.mean, flip.weightedQuartile1, flip.weightedMedian, flip.weightedQuartile3, flip.min, flip.max,
                  flip.pixelsPerDegree);
    if (explain && r.verdict != DiffVerdict::Pass)
      std::printf("explain: %s\n", diagnosis ? (diagnosis->cause + " (" + diagnosis->detail + ")").c_str()
                                            : "no known porting bug explains the difference");
  }
  if (!heatmap.empty() && sizesMatch) {
    OIIO::ImageBuf ia, ib;
    std::string error;
    if (!readImage(a, &ia, &error) || !readImage(b, &ib, &error) || !writeHeatmap(ia, ib, heatmap, &error))
      return fail(error, static_cast<int>(DiffVerdict::FileError));
  }
  return static_cast<int>(r.verdict);
}


}  // namespace

void registerDiffCommand(CLI::App& app, CommandSet& commands) {
  struct DiffState {
    std::string a, b, heatmap;
    bool json = false, explain = false;
    DiffThresholds thresholds;
    FlipOptions flip;
  };
  auto diffState = std::make_shared<DiffState>();
  DiffThresholds& t = diffState->thresholds;
  CLI::App* diff = app.add_subcommand(
      "diff", "compare two images (idiff thresholds and exit codes: 0 pass, 1 warn, 2 fail, 3 size mismatch, 4 file error)");
  diff->add_option("a", diffState->a, "first image")->required();
  diff->add_option("b", diffState->b, "second image")->required();
  diff->add_option("--heatmap", diffState->heatmap, "write a heat map of the per-pixel difference");
  diff->add_flag("--json", diffState->json, "machine-readable output");
  diff->add_option("--fail", t.fail, "per-channel difference that fails")->capture_default_str();
  diff->add_option("--failpercent", t.failPercent, "percent of pixels allowed over --fail")->capture_default_str();
  diff->add_option("--hardfail", t.hardFail, "any pixel over this fails");
  diff->add_option("--warn", t.warn, "per-channel difference that warns")->capture_default_str();
  diff->add_option("--warnpercent", t.warnPercent, "percent of pixels allowed over --warn")->capture_default_str();
  diff->add_option("--hardwarn", t.hardWarn, "any pixel over this warns");
  diff->add_flag("--flip", diffState->flip.enabled,
                 "also compute LDR-FLIP (mean, weighted quartiles, min, max at 67 pixels per degree; inputs read as sRGB)");
  diff->add_option("--flip-map", diffState->flip.map, "write the FLIP error map (magma colours); implies --flip");
  diff->add_option("--flip-fail", diffState->flip.fail, "fail when the FLIP mean exceeds this; implies --flip");
  diff->add_flag("--explain", diffState->explain,
                 "name the porting bug that explains a difference (the run's diagnosis; A is the expected image)");
  commands.add(diff, [diffState] {
    return cmdDiff(diffState->a, diffState->b, diffState->thresholds, diffState->heatmap, diffState->json, diffState->flip,
                   diffState->explain);
  });

}

}  // namespace parity::harness
