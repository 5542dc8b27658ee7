// The outputs of `parity run` and `parity merge`: DIR/results.json (machine), DIR/junit.xml (CI:
// one testcase per case) and DIR/report/index.html (people: a grid of results, and per group
// the golden and backend images side by side with heat maps, an A/B slider, zoom and metrics).
// The HTML references images relative to itself, so the folder opens from disk or as a CI
// artifact.
#pragma once

#include <map>
#include <string>

#include <nlohmann/json.hpp>

namespace parity::harness {

// Adds "counts" to the results and writes the three files atomically.
bool writeReports(const std::string& outDir, nlohmann::json& results, std::string* error);

std::string junitXml(const nlohmann::json& results);
std::string reportHtml(const nlohmann::json& results);
// One page per group (technique/scene/platform), keyed by file name under report/cases/: golden,
// backends, heat maps, FLIP maps, A/B slider, zoom, metrics, verdict, diagnosis, per-pass
// thumbnails with their metrics, and pass timings from device timestamps.
std::map<std::string, std::string> casePages(const nlohmann::json& results);

}  // namespace parity::harness
