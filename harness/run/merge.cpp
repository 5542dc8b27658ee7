// `parity merge`: shards' results.json files, checked field by field, into one run.
#include "harness/run/run.h"

#include <fnmatch.h>
#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>

#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <new>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <thread>

#include "harness/cli/report_error.h"
#include "harness/compare/attachments.h"
#include "harness/run/baseline.h"
#include "harness/compare/diagnosis.h"
#include "harness/run/expectations.h"
#include "harness/run/external_images.h"
#include "harness/compare/diff.h"
#include "harness/compare/flip.h"
#include "harness/run/golden.h"
#include "harness/io/image_io.h"
#include "harness/io/text.h"
#include "rhi/timing_device.h"
#include "harness/run/process.h"
#include "harness/run/render.h"
#include "harness/run/report.h"
#include "harness/scripts/runner.h"
#include "platforms/common/platform.h"
#include "rhi/rhi.h"
#include "scene/scene.h"
#include "techniques/technique.h"

namespace fs = std::filesystem;

namespace parity::harness {

namespace {

// What `parity merge` and the reports read from a results.json, which may come from another
// machine or an older version: a field of the wrong type is refused up front, naming the file
// and the field, instead of throwing halfway through writing the merged output.
enum class JsonKind { String, Number, Metric, Bool, Object, Array };

bool kindMatches(const nlohmann::json& v, JsonKind kind) {
  switch (kind) {
    case JsonKind::String: return v.is_string();
    case JsonKind::Number: return v.is_number();
    case JsonKind::Metric: return v.is_number() || (v.is_string() && v.get<std::string>() == "inf");  // "inf": not finite
    case JsonKind::Bool: return v.is_boolean();
    case JsonKind::Object: return v.is_object();
    case JsonKind::Array: return v.is_array();
  }
  return false;
}

const char* kindName(JsonKind kind) {
  switch (kind) {
    case JsonKind::String: return "a string";
    case JsonKind::Number: return "a number";
    case JsonKind::Metric: return "a number";
    case JsonKind::Bool: return "true or false";
    case JsonKind::Object: return "an object";
    case JsonKind::Array: return "an array";
  }
  return "?";
}

using FieldKinds = std::initializer_list<std::pair<const char*, JsonKind>>;

class ResultsChecker {
 public:
  ResultsChecker(std::string file, std::string* error) : file_(std::move(file)), error_(error) {}

  bool check(const nlohmann::json& r) {
    if (!r.is_object()) return fail("", std::string("must be an object, not ") + r.type_name());
    if (!fields(r, "", {{"cases", JsonKind::Array}, {"groups", JsonKind::Array}, {"backends", JsonKind::Array},
                        {"timing", JsonKind::Object}, {"run_id", JsonKind::String}, {"shard", JsonKind::String},
                        {"project_commit", JsonKind::String}, {"size", JsonKind::String}, {"started", JsonKind::String},
                        {"finished", JsonKind::String}, {"gl_provider", JsonKind::String}, {"golden_dir", JsonKind::String},
                        {"repeat", JsonKind::Number}, {"retries", JsonKind::Number}, {"policy", JsonKind::Object},
                        {"expired_expectations", JsonKind::Array}}))
      return false;
    if (r.contains("timing") &&
        !fields(r["timing"], "timing", {{"wall_s", JsonKind::Number}, {"child_process_s", JsonKind::Number},
                                        {"render_s", JsonKind::Number}, {"setup_s", JsonKind::Number},
                                        {"device_s", JsonKind::Number}, {"write_s", JsonKind::Number},
                                        {"worker_s", JsonKind::Number}, {"compare_s", JsonKind::Number},
                                        {"jobs", JsonKind::Number}}))
      return false;
    if (r.contains("cases") && !eachObject(r["cases"], "cases", [&](const nlohmann::json& c, const std::string& at) {
          return checkCase(c, at);
        }))
      return false;
    if (r.contains("groups") && !eachObject(r["groups"], "groups", [&](const nlohmann::json& g, const std::string& at) {
          return fields(g, at, {{"group", JsonKind::String}, {"verdict", JsonKind::String}, {"parity", JsonKind::Object},
                                {"results", JsonKind::Object}, {"pairs", JsonKind::Array},
                                {"odd_one_out", JsonKind::Object}}) &&
                 (!g.contains("parity") || diffMetrics(g["parity"], at + ".parity"));
        }))
      return false;
    if (r.contains("backends") && !eachObject(r["backends"], "backends", [&](const nlohmann::json& b, const std::string& at) {
          return fields(b, at, {{"name", JsonKind::String}, {"available", JsonKind::Bool}, {"renderer", JsonKind::String},
                                {"driver", JsonKind::String}, {"api", JsonKind::String}, {"reason", JsonKind::String}});
        }))
      return false;
    return true;
  }

 private:
  bool fail(const std::string& where, const std::string& what) {
    *error_ = file_ + ": " + (where.empty() ? "" : where + " ") + what;
    return false;
  }

  bool fields(const nlohmann::json& j, const std::string& where, FieldKinds kinds) {
    for (const auto& [key, kind] : kinds) {
      if (!j.contains(key)) continue;
      const nlohmann::json& v = j[key];
      if (!kindMatches(v, kind))
        return fail("", (where.empty() ? "" : where + ".") + key + " must be " + kindName(kind) + ", not " +
                            (v.is_string() ? "\"" + oneLine(v.get<std::string>()).substr(0, 40) + "\"" : v.type_name()));
    }
    return true;
  }

  template <typename Check>
  bool eachObject(const nlohmann::json& list, const std::string& where, Check check) {
    for (size_t i = 0; i < list.size(); ++i) {
      std::string at = where + "[" + std::to_string(i) + "]";
      if (!list[i].is_object()) return fail("", at + " must be an object, not " + std::string(list[i].type_name()));
      if (!check(list[i], at)) return false;
    }
    return true;
  }

  bool numbers(const nlohmann::json& list, const std::string& where) {
    for (size_t i = 0; i < list.size(); ++i)
      if (!list[i].is_number())
        return fail("", where + "[" + std::to_string(i) + "] must be a number, not " + list[i].type_name());
    return true;
  }

  bool diffMetrics(const nlohmann::json& m, const std::string& where) {
    return fields(m, where, {{"verdict", JsonKind::String}, {"message", JsonKind::String}, {"exit_code", JsonKind::Number},
                             {"width", JsonKind::Number}, {"height", JsonKind::Number}, {"channels", JsonKind::Number},
                             {"max_error", JsonKind::Metric}, {"mean_error", JsonKind::Metric},
                             {"rms_error", JsonKind::Metric}, {"psnr", JsonKind::Metric}, {"pixels", JsonKind::Number},
                             {"pixels_over_fail", JsonKind::Number}, {"share_over_fail", JsonKind::Metric},
                             {"pixels_over_warn", JsonKind::Number}, {"share_over_warn", JsonKind::Metric}});
  }

  bool checkCase(const nlohmann::json& c, const std::string& at) {
    if (!c.contains("id")) return fail("", at + " has no id");
    if (!c.contains("result")) return fail("", at + " has no result");
    if (!fields(c, at, {{"id", JsonKind::String}, {"result", JsonKind::String}, {"technique", JsonKind::String},
                        {"scene", JsonKind::String}, {"platform", JsonKind::String}, {"backend", JsonKind::String},
                        {"reason", JsonKind::String}, {"image", JsonKind::String}, {"renderer", JsonKind::String},
                        {"driver", JsonKind::String}, {"api", JsonKind::String}, {"stderr", JsonKind::String},
                        {"child_s", JsonKind::Number}, {"deterministic", JsonKind::Bool}, {"render_ms", JsonKind::Array},
                        {"pass_ms", JsonKind::Array}, {"targets", JsonKind::Array}, {"golden", JsonKind::Object},
                        {"attempts", JsonKind::Array}, {"passes", JsonKind::Array}, {"setup_ms", JsonKind::Number},
                        {"device_ms", JsonKind::Number}, {"write_ms", JsonKind::Number}, {"worker_ms", JsonKind::Number}}))
      return false;
    if (c.contains("render_ms") && !numbers(c["render_ms"], at + ".render_ms")) return false;
    if (c.contains("pass_ms") && !eachObject(c["pass_ms"], at + ".pass_ms", [&](const nlohmann::json& t, const std::string& in) {
          return fields(t, in, {{"pass", JsonKind::String}, {"ms", JsonKind::Number}});
        }))
      return false;
    if (c.contains("targets") && !eachObject(c["targets"], at + ".targets", [&](const nlohmann::json& t, const std::string& in) {
          return fields(t, in, {{"name", JsonKind::String}, {"format", JsonKind::String}, {"kind", JsonKind::String},
                                {"image", JsonKind::String}, {"metrics", JsonKind::Object},
                                {"preview", JsonKind::Object}}) &&
                 (!t.contains("metrics") ||
                  fields(t["metrics"], in + ".metrics", {{"metric", JsonKind::String}, {"max", JsonKind::Metric},
                                                         {"mean", JsonKind::Metric}, {"pass", JsonKind::Bool}}));
        }))
      return false;
    if (c.contains("golden")) {
      const nlohmann::json& g = c["golden"];
      std::string in = at + ".golden";
      if (!fields(g, in, {{"golden", JsonKind::String}, {"golden_copy", JsonKind::String}, {"heatmap", JsonKind::String},
                          {"flip_map", JsonKind::String}, {"verdict", JsonKind::String}, {"missing", JsonKind::Bool},
                          {"metrics", JsonKind::Object}, {"flip", JsonKind::Object}, {"diagnosis", JsonKind::Object},
                          {"first_diverging_pass", JsonKind::Object}}))
        return false;
      if (g.contains("metrics") && !diffMetrics(g["metrics"], in + ".metrics")) return false;
      if (g.contains("flip") &&
          !fields(g["flip"], in + ".flip", {{"mean", JsonKind::Metric}, {"weighted_median", JsonKind::Metric},
                                            {"weighted_quartile_1", JsonKind::Metric}, {"weighted_quartile_3", JsonKind::Metric},
                                            {"min", JsonKind::Metric}, {"max", JsonKind::Metric}}))
        return false;
      if (g.contains("diagnosis") &&
          !fields(g["diagnosis"], in + ".diagnosis", {{"cause", JsonKind::String}, {"detail", JsonKind::String}}))
        return false;
      if (g.contains("first_diverging_pass") &&
          !fields(g["first_diverging_pass"], in + ".first_diverging_pass",
                  {{"pass", JsonKind::String}, {"target", JsonKind::String}}))
        return false;
    }
    return true;
  }

  std::string file_;
  std::string* error_;
};

}  // namespace

int mergeRuns(const std::vector<std::string>& inputs, const std::string& outDir, const std::string& baselineDir) {
  // Every input is read and checked before the output folder is created, so a bad input fails
  // the merge with one line and leaves nothing behind.
  std::vector<nlohmann::json> runs;
  std::set<std::string> ids;
  for (const std::string& in : inputs) {
    std::string file = (fs::path(in) / "results.json").string();
    std::ifstream f(file);
    if (!f) return reportError(in + ": no results.json (not a `parity run` output folder)");
    nlohmann::json r;
    try {
      f >> r;
    } catch (const std::exception& e) {
      return reportError(file + ": not valid JSON: " + e.what());
    }
    std::string error;
    if (!ResultsChecker(file, &error).check(r)) return reportError(error);
    for (const auto& c : r.value("cases", nlohmann::json::array()))
      if (!ids.insert(c["id"].get<std::string>()).second)
        return reportError(file + ": case " + c["id"].get<std::string>() + " appears in more than one input");
    runs.push_back(std::move(r));
  }
  nlohmann::json baseline;
  if (std::string error; !baselineDir.empty() && !loadBaseline(baselineDir, &baseline, &error)) return reportError(error);

  std::error_code ec;
  bool existed = fs::exists(outDir, ec);
  // Output this merge created is removed again when the merge fails partway.
  auto failMerge = [&](const std::string& message) {
    if (!existed) fs::remove_all(outDir, ec);
    return reportError(message);
  };
  fs::create_directories(fs::path(outDir) / "cases", ec);
  if (ec) return failMerge(outDir + ": cannot create output folder: " + ec.message());
  nlohmann::json merged{{"schema", "parity-results/1"}, {"merged_from", nlohmann::json::array()}};
  std::map<std::string, nlohmann::json> backends;
  std::set<std::string> required;  // the inputs' exit policies, joined
  bool strict = false;
  nlohmann::json expired = nlohmann::json::array();  // the inputs' expired expectations, each once
  double wall = 0;
  // Summed over the inputs (each input's wall time is its own: the merge keeps the longest).
  std::map<std::string, double> timing{{"child_process_s", 0}, {"render_s", 0}, {"setup_s", 0}, {"device_s", 0},
                                       {"write_s", 0},         {"worker_s", 0}, {"compare_s", 0}};
  for (size_t i = 0; i < inputs.size(); ++i) {
    const std::string& in = inputs[i];
    const nlohmann::json& r = runs[i];
    for (const char* field : {"project_commit", "size", "gl_provider", "repeat", "retries", "golden_dir", "run_id", "started"})
      if (!merged.contains(field) && r.contains(field)) merged[field] = r[field];
    merged["merged_from"].push_back({{"folder", in}, {"run_id", r.value("run_id", "")}, {"shard", r.value("shard", "")}});
    for (const auto& c : r.value("cases", nlohmann::json::array())) merged["cases"].push_back(c);
    for (const auto& g : r.value("groups", nlohmann::json::array())) merged["groups"].push_back(g);
    const nlohmann::json policy = r.value("policy", nlohmann::json::object());
    for (const auto& b : policy.value("require_backends", nlohmann::json::array()))
      if (b.is_string()) required.insert(b.get<std::string>());
    strict = strict || policy.value("strict", false) == true;
    for (const auto& e : r.value("expired_expectations", nlohmann::json::array()))
      if (std::find(expired.begin(), expired.end(), e) == expired.end()) expired.push_back(e);
    for (const auto& b : r.value("backends", nlohmann::json::array())) {
      std::string name = b.value("name", "");
      if (!backends.count(name) || b.value("available", false)) backends[name] = b;
    }
    const nlohmann::json& t = r.value("timing", nlohmann::json::object());
    for (auto& [field, seconds] : timing) seconds += t.value(field, 0.0);
    wall = std::max(wall, t.value("wall_s", 0.0));
    // Image by image, each replaced whole: a merge killed midway leaves every image old or new.
    // Links are not followed (an input's link could point anywhere), and an input's own
    // temporaries are not copied.
    const fs::path cases = fs::path(in) / "cases";
    if (fs::is_directory(cases, ec)) {
      for (fs::recursive_directory_iterator it(cases, ec), end; !ec && it != end; it.increment(ec)) {
        if (it->is_symlink() || !it->is_regular_file() || it->path().filename().string().rfind(".parity-tmp-", 0) == 0)
          continue;
        std::string copyError;
        if (!copyFileAtomic(it->path().string(), (fs::path(outDir) / "cases" / fs::relative(it->path(), cases)).string(),
                            &copyError))
          return failMerge(in + ": cannot copy its images: " + copyError);
      }
    }
    if (ec) return failMerge(in + ": cannot copy its images: " + ec.message());
  }
  for (auto& [name, b] : backends) merged["backends"].push_back(b);
  // A required backend fails the merge unless some input rendered with it.
  merged["policy"] = {{"require_backends", std::vector<std::string>(required.begin(), required.end())}, {"strict", strict}};
  for (const std::string& b : required)
    if (!backends.count(b) || !backends[b].value("available", false))
      merged["policy"]["unavailable"][b] = backends.count(b) ? backends[b].value("reason", "unavailable") : "no case of it rendered";
  merged["timing"] = {{"wall_s", wall}};
  for (const auto& [field, seconds] : timing) merged["timing"][field] = seconds;
  merged["finished"] = nowIso();
  merged["expired_expectations"] = expired;
  if (!baselineDir.empty()) merged["baseline"] = compareWithBaseline(baselineDir, baseline, merged);
  std::string error;
  try {
    if (!writeReports(outDir, merged, &error)) return failMerge(error);
  } catch (const std::exception& e) {
    // The checks above cover what the reports read; this keeps anything they missed one line.
    return failMerge(outDir + ": cannot write the merged report: " + e.what());
  }
  bool bad = merged["policy"].contains("unavailable") || (strict && !expired.empty());
  std::map<std::string, int> counts;
  for (const auto& c : merged.value("cases", nlohmann::json::array())) {
    CaseResult r = CaseResult::Fail;
    parseResultName(c.value("result", ""), &r);
    bad = bad || isBadResult(r, strict);
    counts[c.value("result", "?")]++;
  }
  std::string line;
  for (const auto& [name, n] : counts) line += (line.empty() ? "" : ", ") + std::to_string(n) + " " + name;
  if (!expired.empty()) line += ", " + std::to_string(expired.size()) + " expired expectation" + (expired.size() == 1 ? "" : "s");
  const std::string against = merged.contains("baseline") ? "; " + baselineSummary(merged["baseline"]) : "";
  std::printf("parity merge: %zu inputs, %s%s; report %s\n", inputs.size(), line.c_str(), against.c_str(),
              (fs::path(outDir) / "report" / "index.html").c_str());
  if (merged.contains("baseline")) printBaselineChanges("parity merge", merged["baseline"]);
  return bad ? 2 : 0;
}


}  // namespace parity::harness
