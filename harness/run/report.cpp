#include "harness/run/report.h"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "harness/io/atomic_file.h"
#include "harness/run/baseline.h"
#include "harness/run/diagnostic_groups.h"
#include "harness/run/golden.h"
#include "harness/run/report_sections.h"
#include "harness/run/run.h"

namespace fs = std::filesystem;

namespace parity::harness {

namespace {

using report::num;
using report::str;
using report::xmlEscape;

const char* colour(const std::string& result) {
  static const std::map<std::string, const char*> colours = {
      {"Pass", "#3c9d4e"},         {"Fail", "#d2402f"},          {"ParityWarning", "#e0a526"},
      {"Crash", "#7d1f9e"},        {"Timeout", "#9e4f1f"},       {"Skip", "#9a9a9a"},
      {"ExpectedFail", "#6f8fb3"}, {"UnexpectedPass", "#c25fb0"}, {"Flake", "#b8b83a"},
      {"Nondeterministic", "#e0662a"}};
  auto it = colours.find(result);
  return it == colours.end() ? "#444" : it->second;
}

std::string anchor(const std::string& group) {
  // Used as an id, in links and as a file name (report/cases/<anchor>.html): only characters
  // that are safe in all three survive, so a hostile scene or technique name cannot break out.
  std::string a = "g-" + group;
  for (char& c : a) {
    bool safe = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' || c == '_' || c == '-';
    if (c == '/') c = '-';
    else if (!safe) c = '_';
  }
  // A name that lost characters (two groups could then meet) or that is too long for a file
  // name (255 bytes, less the temporary prefix of atomic writes) keeps a readable head and a
  // hash of the whole group.
  constexpr size_t kMaxLength = 100;
  bool lossy = false;
  for (size_t i = 2; i < a.size(); ++i) lossy = lossy || (a[i] != group[i - 2] && !(a[i] == '-' && group[i - 2] == '/'));
  if (lossy || a.size() > kMaxLength) {
    uint32_t h = 2166136261u;  // FNV-1a: stable across runs and builds
    for (unsigned char c : group) h = (h ^ c) * 16777619u;
    char hex[12];
    std::snprintf(hex, sizeof(hex), "-%08x", h);
    a = a.substr(0, std::min(a.size(), kMaxLength)) + hex;
  }
  return a;
}


using Members = std::map<std::string, const nlohmann::json*>;

bool groupRendered(const Members& members) {
  for (const auto& [b, c] : members)
    if (c->contains("image") || str(*c, "result") != "Skip") return true;
  return false;
}

std::string fmt(const nlohmann::json& v) {
  if (v.is_string()) return v.get<std::string>();
  if (!v.is_number()) return "";
  std::ostringstream s;
  s.precision(6);
  s << v.get<double>();
  return s.str();
}

const char* kStyle = R"(<style>
body{font-family:system-ui,sans-serif;margin:1.5em;color:#222}
table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:3px 6px;font-size:13px;vertical-align:top}
table.grid td.cell{color:#fff;text-align:center;min-width:90px}table.grid td.cell a{color:#fff}
.imgs{display:flex;flex-wrap:wrap;gap:10px}.imgs figure{margin:0}.imgs img{image-rendering:pixelated;border:1px solid #888;cursor:zoom-in}
.imgs img.zoom{width:auto!important;transform:scale(3);transform-origin:top left;position:relative;z-index:2;cursor:zoom-out}
figcaption{font-size:12px}.ab{position:relative;display:inline-block}.ab img{display:block}
.ab .top{position:absolute;left:0;top:0;overflow:hidden;border-right:2px solid #f0f}
section{border-top:2px solid #ddd;margin-top:1.5em;padding-top:.5em}.res{color:#fff;padding:1px 5px;border-radius:3px}
.thumbs img{width:160px}
</style>)";

// The platform diagnostics of a case (results.json: golden.diagnostics), a line per code
// (diagnostic_groups.h): "error E_MRT_FORMAT_MISMATCH [P1]: ...; pass store; targets a, b
// (expected: reason)".
std::vector<std::string> diagnosticLines(const nlohmann::json& c) {
  std::vector<std::string> lines;
  if (!c.contains("golden") || !c["golden"].contains("diagnostics")) return lines;
  for (const DiagnosticGroup& g : groupDiagnostics(c["golden"]["diagnostics"])) lines.push_back(g.line());
  return lines;
}

// Images, A/B sliders and metrics of one group (both backends of technique/scene/platform).
// `up` leads from the page to the output folder; `full` adds FLIP maps, targets and timings.
std::string groupBody(const Members& members, const nlohmann::json* info, const std::string& up, bool full) {
  std::ostringstream h;
  // The verdict is the grid's: each backend's case result (the image comparison across backends
  // is the group's, shown beside it).
  h << "<p>verdict:";
  for (const auto& [b, c] : members)
    h << " " << xmlEscape(b) << " <b class=\"verdict res\" style=\"background:" << colour(str(*c, "result")) << "\">"
      << xmlEscape(str(*c, "result")) << "</b>";
  if (info) h << "; images across backends: " << xmlEscape(str(*info, "verdict"));
  h << "</p>\n";
  if (info) h << report::pairsHtml(*info);
  std::string goldenImg;
  for (const auto& [b, c] : members)
    if (c->contains("golden") && (*c)["golden"].contains("golden_copy")) goldenImg = (*c)["golden"]["golden_copy"];
  for (const auto& [b, c] : members)
    if (c->contains("golden") && (*c)["golden"].contains("diagnosis"))
      h << "<p class=\"diagnosis\">" << xmlEscape(b) << ": likely cause <b>"
        << xmlEscape(str((*c)["golden"]["diagnosis"], "cause")) << "</b> (" << xmlEscape(str((*c)["golden"]["diagnosis"], "detail"))
        << ")</p>\n";
  for (const auto& [b, c] : members)
    if (c->contains("golden") && (*c)["golden"].contains("first_diverging_pass"))
      h << "<p>" << xmlEscape(b) << ": first diverging pass <b>"
        << xmlEscape(str((*c)["golden"]["first_diverging_pass"], "pass")) << "</b> (target "
        << xmlEscape(str((*c)["golden"]["first_diverging_pass"], "target")) << ")</p>\n";
  for (const auto& [b, c] : members)
    if (c->contains("lost_light")) {
      const nlohmann::json& l = (*c)["lost_light"];
      h << "<p class=\"lost-light\">" << xmlEscape(b) << ": <b>" << num(l, "pixels") << "</b> of " << num(l, "of")
        << " pixels lost light (at most " << num(l, "max_per_pixel") << " per pixel; target "
        << xmlEscape(str(l, "target")) << ")</p>\n";
    }
  // The port's own paths (techniques/technique.h, PortPath): both backends take the same ones.
  if (!members.empty() && members.begin()->second->contains("port_paths"))
    for (const auto& p : (*members.begin()->second)["port_paths"])
      if (p.is_string()) h << "<p class=\"port-path\">port path: " << xmlEscape(p.get<std::string>()) << "</p>\n";
  // Platform diagnostics grouped by code; once for every backend that raised the same.
  std::vector<std::pair<std::string, std::vector<std::string>>> byLines;  // backends, their lines
  for (const auto& [b, c] : members) {
    std::vector<std::string> lines = diagnosticLines(*c);
    if (lines.empty()) continue;
    auto same = std::find_if(byLines.begin(), byLines.end(), [&](const auto& e) { return e.second == lines; });
    if (same != byLines.end()) same->first += ", " + b;
    else byLines.push_back({b, lines});
  }
  for (const auto& [backends, lines] : byLines) {
    h << "<p>" << xmlEscape(backends) << ": platform diagnostics of the technique's calls</p><ul class=\"diagnostics\">";
    for (const std::string& l : lines) h << "<li>" << xmlEscape(l) << "</li>";
    h << "</ul>\n";
  }
  // Script cases: the file and each EXPECT's outcome per backend (they have no image).
  for (const auto& [b, c] : members) {
    if (!full || !c->contains("expects") || !(*c)["expects"].is_array()) continue;
    h << "<p class=\"script\">" << xmlEscape(b) << ": script <code>" << xmlEscape(str(*c, "script"))
      << "</code></p>\n<table class=\"expects\"><tr><th>line</th><th>" << xmlEscape(b) << "</th><th>expectation</th></tr>";
    for (const auto& e : (*c)["expects"]) {
      bool pass = e.contains("pass") && e["pass"].is_boolean() && e["pass"].get<bool>();
      h << "<tr><td>" << (e.contains("line") && e["line"].is_number() ? std::to_string(e["line"].get<long long>()) : "")
        << "</td><td>" << (pass ? "pass" : "<b>fail</b>") << "</td><td>" << xmlEscape(str(e, "message")) << "</td></tr>";
    }
    h << "</table>\n";
  }
  h << "<div class=\"imgs\">";
  auto figure = [&](const std::string& path, const std::string& caption) {
    h << "<figure><img src=\"" << xmlEscape(up + path) << "\" width=\"320\" onclick=\"this.classList.toggle('zoom')\"><figcaption>"
      << xmlEscape(caption) << "</figcaption></figure>";
  };
  if (!goldenImg.empty()) figure(goldenImg, "golden");
  for (const auto& [b, c] : members) {
    if (c->contains("image")) figure(str(*c, "image"), b + " (" + str(*c, "renderer") + ")");
    if (c->contains("golden") && (*c)["golden"].contains("heatmap")) figure((*c)["golden"]["heatmap"], "golden vs " + b);
    if (full && c->contains("golden") && (*c)["golden"].contains("flip_map"))
      figure((*c)["golden"]["flip_map"], "FLIP golden vs " + b);
  }
  if (info && info->contains("parity") && (*info)["parity"].contains("heatmap")) figure((*info)["parity"]["heatmap"], "gl vs vk");
  // The other pairs' heat maps (gl vs vk's is the one above).
  if (info && info->contains("pairs") && (*info)["pairs"].is_array())
    for (const auto& p : (*info)["pairs"]) {
      const std::string label = report::pairLabel(p);
      if (p.contains("heatmap") && label != "gl vs vk" && label != "vk vs gl") figure(str(p, "heatmap"), label);
    }
  h << "</div>\n";
  // A/B slider: golden over each backend.
  for (const auto& [b, c] : members)
    if (!goldenImg.empty() && c->contains("image")) {
      h << "<p>A/B golden | " << xmlEscape(b) << ": <input type=\"range\" min=\"0\" max=\"100\" value=\"50\" "
        << "oninput=\"this.nextElementSibling.querySelector('.top').style.width=this.value+'%'\"><span class=\"ab\">"
        << "<img src=\"" << xmlEscape(up + str(*c, "image")) << "\" width=\"640\"><span class=\"top\" style=\"width:50%\">"
        << "<img src=\"" << xmlEscape(up + goldenImg) << "\" width=\"640\" style=\"max-width:none\"></span></span></p>\n";
    }
  h << "<table class=\"metrics\"><tr><th>backend</th><th>result</th><th>reason</th><th>max</th><th>mean</th><th>RMS</th>"
       "<th>PSNR</th><th>pixels over</th><th>FLIP mean</th><th>FLIP weighted median</th><th>render ms</th><th>attempts</th></tr>\n";
  for (const auto& [b, c] : members) {
    nlohmann::json g = c->value("golden", nlohmann::json::object());
    nlohmann::json m = g.value("metrics", nlohmann::json::object());
    nlohmann::json f = g.value("flip", nlohmann::json::object());
    std::string ms;
    for (const auto& t : c->value("render_ms", nlohmann::json::array())) ms += (ms.empty() ? "" : ", ") + fmt(t);
    std::string result = str(*c, "result");
    h << "<tr><td>" << xmlEscape(b) << "</td><td><span class=\"res\" style=\"background:" << colour(result) << "\">"
      << xmlEscape(result) << "</span></td><td>" << xmlEscape(str(*c, "reason")) << "</td><td>" << num(m, "max_error")
      << "</td><td>" << num(m, "mean_error") << "</td><td>" << num(m, "rms_error") << "</td><td>" << num(m, "psnr")
      << "</td><td>" << num(m, "pixels_over_fail") << "</td><td>" << num(f, "mean") << "</td><td>" << num(f, "weighted_median")
      << "</td><td>" << ms << "</td><td>" << c->value("attempts", nlohmann::json::array()).size() << "</td></tr>\n";
  }
  if (info && info->contains("parity")) {
    const nlohmann::json& p = (*info)["parity"];
    h << "<tr><td>gl vs vk</td><td>" << xmlEscape(str(p, "verdict")) << "</td><td>parity budget</td><td>" << num(p, "max_error")
      << "</td><td>" << num(p, "mean_error") << "</td><td>" << num(p, "rms_error") << "</td><td>" << num(p, "psnr")
      << "</td><td>" << num(p, "pixels_over_fail") << "</td><td></td><td></td><td></td><td></td></tr>\n";
  }
  h << "</table>\n";
  // A child that crashed, timed out or failed says why on its stderr: shown here, escaped.
  for (const auto& [b, c] : members)
    if (!str(*c, "stderr").empty())
      h << "<p>" << xmlEscape(b) << " stderr:</p><pre class=\"stderr\">" << xmlEscape(str(*c, "stderr")) << "</pre>\n";
  if (!full) return h.str();

  // Per-pass targets: thumbnails (PNG as written; EXR data through its stated preview mapping)
  // with their metrics, and timings.
  for (const auto& [b, c] : members) {
    const nlohmann::json targets = c->value("targets", nlohmann::json::array());
    if (!targets.empty()) {
      h << "<h4>" << xmlEscape(b) << " targets</h4><div class=\"imgs thumbs\">";
      for (const auto& t : targets) {
        std::string image = str(t, "image");
        h << "<figure>";
        const nlohmann::json preview = t.value("preview", nlohmann::json::object());
        if (image.size() > 4 && image.compare(image.size() - 4, 4, ".png") == 0)
          h << "<img src=\"" << xmlEscape(up + image) << "\" onclick=\"this.classList.toggle('zoom')\">";
        else if (preview.contains("image"))
          h << "<img src=\"" << xmlEscape(up + str(preview, "image")) << "\" onclick=\"this.classList.toggle('zoom')\">";
        h << "<figcaption>" << xmlEscape(str(t, "name")) << " (" << xmlEscape(str(t, "format")) << ", "
          << xmlEscape(str(t, "kind")) << ")";
        if (preview.contains("mapping")) h << "<br>shown as " << xmlEscape(str(preview, "mapping"));
        if (t.contains("metrics")) {
          const nlohmann::json& m = t["metrics"];
          h << "<br>" << xmlEscape(str(m, "metric")) << " max " << fmt(m.value("max", nlohmann::json())) << ", mean "
            << fmt(m.value("mean", nlohmann::json())) << (m.value("pass", false) ? ", pass" : ", FAIL");
        } else {
          h << "<br>no per-pass golden";
        }
        h << "</figcaption></figure>";
      }
      h << "</div>\n";
    }
    const nlohmann::json timings = c->value("pass_ms", nlohmann::json::array());
    if (!timings.empty()) {
      h << "<table class=\"timings\"><tr><th>" << xmlEscape(b) << " pass</th><th>GPU ms (device timestamps)</th></tr>";
      for (const auto& t : timings)
        h << "<tr><td>" << xmlEscape(str(t, "pass")) << "</td><td>" << fmt(t.value("ms", nlohmann::json())) << "</td></tr>";
      h << "</table>\n";
    }
  }
  return h.str();
}

}  // namespace

std::string junitXml(const nlohmann::json& results) {
  std::map<std::string, std::vector<const nlohmann::json*>> byTechnique;
  const nlohmann::json cases = results.value("cases", nlohmann::json::array());
  for (const auto& c : cases) byTechnique[str(c, "technique")].push_back(&c);
  // The run's exit policy (results.json "policy"): --strict makes ParityWarning and Flake
  // failures here too; each required backend is a test case that fails when it was unavailable.
  const nlohmann::json policy = results.value("policy", nlohmann::json::object());
  const bool strict = policy.value("strict", false);
  const nlohmann::json required = policy.value("require_backends", nlohmann::json::array());
  const nlohmann::json unavailable = policy.value("unavailable", nlohmann::json::object());
  const nlohmann::json expired = results.value("expired_expectations", nlohmann::json::array());
  int failures = static_cast<int>(unavailable.size()) + (strict ? static_cast<int>(expired.size()) : 0), errors = 0,
      skipped = 0;
  for (const auto& c : cases) {
    CaseResult r = CaseResult::Fail;
    parseResultName(str(c, "result"), &r);
    if (r == CaseResult::Crash || r == CaseResult::Timeout) ++errors;
    else if (isBadResult(r, strict)) ++failures;
    else if (r == CaseResult::Skip) ++skipped;
  }
  std::ostringstream x;
  x << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  x << "<testsuites name=\"parity\" tests=\"" << cases.size() + required.size() + expired.size() << "\" failures=\"" << failures
    << "\" errors=\"" << errors << "\" skipped=\"" << skipped << "\">\n";
  if (!required.empty() || strict) {
    x << "  <testsuite name=\"parity.policy\" tests=\"" << required.size() << "\">\n";
    x << "    <properties>\n      <property name=\"strict\" value=\"" << (strict ? "true" : "false") << "\"/>\n";
    for (const auto& b : required)
      x << "      <property name=\"require_backend\" value=\"" << xmlEscape(b.get<std::string>()) << "\"/>\n";
    x << "    </properties>\n";
    for (const auto& b : required) {
      const std::string name = b.get<std::string>();
      x << "    <testcase classname=\"parity.policy\" name=\"backend " << xmlEscape(name) << " available\">\n";
      if (unavailable.contains(name))
        x << "      <failure type=\"RequiredBackendUnavailable\" message=\""
          << xmlEscape(unavailable[name].get<std::string>()) << "\"/>\n";
      x << "    </testcase>\n";
    }
    x << "  </testsuite>\n";
  }
  // The run against its baseline, in one line (each case says its own change above).
  if (results.contains("baseline") && results["baseline"].is_object()) {
    x << "  <testsuite name=\"parity.baseline\" tests=\"0\">\n    <properties>\n      <property name=\"baseline\" value=\""
      << xmlEscape(baselineSummary(results["baseline"])) << "\"/>\n";
    for (const auto& c : results["baseline"].value("vanished", nlohmann::json::array()))
      x << "      <property name=\"vanished\" value=\"" << xmlEscape(str(c, "id")) << " (" << xmlEscape(str(c, "before"))
        << " before)\"/>\n";
    x << "    </properties>\n  </testsuite>\n";
  }
  // An expectation past its date: a failure under --strict, a note otherwise.
  if (!expired.empty()) {
    x << "  <testsuite name=\"parity.expectations\" tests=\"" << expired.size() << "\">\n";
    for (const auto& e : expired) {
      const std::string message = "expired on " + str(e, "expires") + " (" + str(e, "reason") +
                                  (str(e, "bug").empty() ? "" : "; bug " + str(e, "bug")) + "): renew its date or remove it";
      x << "    <testcase classname=\"parity.expectations\" name=\"expectation " << xmlEscape(str(e, "case")) << "\">\n";
      if (strict) x << "      <failure type=\"ExpiredExpectation\" message=\"" << xmlEscape(message) << "\"/>\n";
      else x << "      <system-out>" << xmlEscape(message) << "</system-out>\n";
      x << "    </testcase>\n";
    }
    x << "  </testsuite>\n";
  }
  for (const auto& [technique, list] : byTechnique) {
    x << "  <testsuite name=\"parity." << xmlEscape(technique) << "\" tests=\"" << list.size() << "\">\n";
    for (const nlohmann::json* c : list) {
      std::string result = str(*c, "result");
      CaseResult r = CaseResult::Fail;
      parseResultName(result, &r);
      x << "    <testcase classname=\"parity." << xmlEscape(technique) << "\" name=\"" << xmlEscape(str(*c, "id"))
        << "\" time=\"" << num(*c, "child_s") << "\">\n";
      std::string detail = result + ": " + str(*c, "reason");
      if (c->contains("golden") && (*c)["golden"].contains("verdict"))
        detail += "\nverdict: " + (*c)["golden"]["verdict"].get<std::string>();
      if (c->contains("golden") && (*c)["golden"].contains("metrics"))
        detail += "\nmetrics vs golden: " + (*c)["golden"]["metrics"].dump();
      const std::vector<std::string> diagnostics = diagnosticLines(*c);
      for (const std::string& l : diagnostics) detail += "\nplatform diagnostic: " + l;
      // How the case changed since the baseline run (--baseline), if it did.
      const std::string change =
          results.contains("baseline") ? baselineChange(results["baseline"], str(*c, "id")) : std::string();
      if (!change.empty()) detail += "\nagainst baseline: " + change;
      if (!diagnostics.empty() || !change.empty()) {
        x << "      <properties>\n";
        for (const std::string& l : diagnostics) x << "        <property name=\"diagnostic\" value=\"" << xmlEscape(l) << "\"/>\n";
        if (!change.empty()) x << "        <property name=\"baseline\" value=\"" << xmlEscape(change) << "\"/>\n";
        x << "      </properties>\n";
      }
      if (r == CaseResult::Crash || r == CaseResult::Timeout)
        x << "      <error type=\"" << result << "\" message=\"" << xmlEscape(str(*c, "reason")) << "\">"
          << xmlEscape(detail + "\n" + str(*c, "stderr")) << "</error>\n";
      else if (isBadResult(r, strict))
        x << "      <failure type=\"" << result << "\" message=\"" << xmlEscape(str(*c, "reason")) << "\">"
          << xmlEscape(detail) << "</failure>\n";
      else if (r == CaseResult::Skip)
        x << "      <skipped message=\"" << xmlEscape(str(*c, "reason")) << "\"/>\n";
      else if (r != CaseResult::Pass)
        x << "      <system-out>" << xmlEscape(detail) << "</system-out>\n";
      x << "    </testcase>\n";
    }
    x << "  </testsuite>\n";
  }
  x << "</testsuites>\n";
  return x.str();
}

std::string reportHtml(const nlohmann::json& results) {
  const nlohmann::json cases = results.value("cases", nlohmann::json::array());
  // group -> backend -> case; axes of the grid.
  std::map<std::string, std::map<std::string, const nlohmann::json*>> groups;
  std::set<std::string> rows, backends;
  std::vector<std::string> platforms = platformNames();
  for (const auto& c : cases) {
    groups[str(c, "technique") + "/" + str(c, "scene") + "/" + str(c, "platform")][str(c, "backend")] = &c;
    rows.insert(str(c, "technique") + "/" + str(c, "scene"));
    backends.insert(str(c, "backend"));
  }
  std::map<std::string, nlohmann::json> groupInfo;
  for (const auto& g : results.value("groups", nlohmann::json::array())) groupInfo[str(g, "group")] = g;

  std::ostringstream h;
  h << R"(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>parity report</title>
)" << kStyle << R"(</head><body>
<h1>parity report</h1>
)";
  h << "<p>run " << xmlEscape(str(results, "run_id")) << ", commit " << xmlEscape(str(results, "project_commit")) << ", size "
    << xmlEscape(str(results, "size")) << ", finished " << xmlEscape(str(results, "finished")) << "</p>\n<p>";
  const nlohmann::json counts = results.value("counts", nlohmann::json::object());
  for (const auto& item : counts.items())
    h << "<span class=\"res\" style=\"background:" << colour(item.key()) << "\">" << item.value().get<int>() << " "
      << xmlEscape(item.key()) << "</span> ";
  h << "</p>\n<h2>Backends</h2><table><tr><th>backend</th><th>renderer</th><th>driver</th><th>status</th></tr>\n";
  for (const auto& b : results.value("backends", nlohmann::json::array()))
    h << "<tr><td>" << xmlEscape(str(b, "name")) << "</td><td>" << xmlEscape(str(b, "renderer")) << "</td><td>"
      << xmlEscape(str(b, "driver")) << "</td><td>" << (b.value("available", false) ? "available" : xmlEscape(str(b, "reason")))
      << "</td></tr>\n";
  h << "</table>\n";
  h << report::expiredExpectationsHtml(results) << report::baselineHtml(results);
  const nlohmann::json timing = results.value("timing", nlohmann::json::object());
  h << "<p>wall " << num(timing, "wall_s") << " s; child processes " << num(timing, "child_process_s") << " s, of which rendering "
    << num(timing, "render_s") << " s, device creation " << num(timing, "device_s") << " s, writing images "
    << num(timing, "write_s") << " s</p>\n";

  // The grid: rows technique/scene, columns platform × backend.
  h << "<h2>Results</h2><table class=\"grid\" id=\"grid\"><tr><th rowspan=\"2\">technique / scene</th>";
  for (const std::string& p : platforms) h << "<th colspan=\"" << backends.size() << "\">" << xmlEscape(p) << "</th>";
  h << "</tr><tr>";
  for (size_t i = 0; i < platforms.size(); ++i)
    for (const std::string& b : backends) h << "<th>" << xmlEscape(b) << "</th>";
  h << "</tr>\n";
  for (const std::string& row : rows) {
    h << "<tr><th>" << xmlEscape(row) << "</th>";
    for (const std::string& p : platforms)
      for (const std::string& b : backends) {
        auto g = groups.find(row + "/" + p);
        const nlohmann::json* c = nullptr;
        if (g != groups.end() && g->second.count(b)) c = g->second.at(b);
        if (!c) {
          h << "<td></td>";
          continue;
        }
        std::string result = str(*c, "result");
        h << "<td class=\"cell\" data-result=\"" << xmlEscape(result) << "\" style=\"background:" << colour(result) << "\" title=\""
          << xmlEscape(str(*c, "reason")) << "\"><a href=\"cases/" << anchor(row + "/" + p) << ".html\">" << xmlEscape(result)
          << "</a></td>";
      }
    h << "</tr>\n";
  }
  h << "</table>\n";

  // One section per group that rendered something or failed in an interesting way; each also
  // has its own page (report/cases/<group>.html) with FLIP maps, targets and pass timings.
  for (const auto& [group, members] : groups) {
    if (!groupRendered(members)) continue;
    auto gi = groupInfo.find(group);
    h << "<section id=\"" << anchor(group) << "\"><h3><a href=\"cases/" << anchor(group) << ".html\">" << xmlEscape(group)
      << "</a></h3>\n";
    h << groupBody(members, gi == groupInfo.end() ? nullptr : &gi->second, "../", false);
    h << "</section>\n";
  }
  h << "</body></html>\n";
  return h.str();
}

std::map<std::string, std::string> casePages(const nlohmann::json& results) {
  const nlohmann::json cases = results.value("cases", nlohmann::json::array());  // outlives the pointers below
  std::map<std::string, Members> groups;
  for (const auto& c : cases)
    groups[str(c, "technique") + "/" + str(c, "scene") + "/" + str(c, "platform")][str(c, "backend")] = &c;
  std::map<std::string, nlohmann::json> groupInfo;
  for (const auto& g : results.value("groups", nlohmann::json::array())) groupInfo[str(g, "group")] = g;
  std::map<std::string, std::string> pages;
  for (const auto& [group, members] : groups) {
    auto gi = groupInfo.find(group);
    std::ostringstream h;
    h << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" << xmlEscape(group) << "</title>\n"
      << kStyle << "</head><body>\n<p><a href=\"../index.html\">all results</a></p><h1 class=\"case\">" << xmlEscape(group)
      << "</h1>\n";
    h << groupBody(members, gi == groupInfo.end() ? nullptr : &gi->second, "../../", true);
    h << "</body></html>\n";
    pages[anchor(group) + ".html"] = h.str();
  }
  return pages;
}

bool writeReports(const std::string& outDir, nlohmann::json& results, std::string* error) {
  nlohmann::json counts = nlohmann::json::object();
  for (const auto& c : results.value("cases", nlohmann::json::array())) {
    std::string r = c.value("result", "?");
    counts[r] = counts.value(r, 0) + 1;
  }
  results["counts"] = counts;
  std::error_code ec;
  // What an earlier writer killed mid-write left behind (its images included) goes first.
  removeStaleTemporaries(outDir, true);
  fs::create_directories(fs::path(outDir) / "report", ec);
  for (const auto& [name, html] : casePages(results))
    if (!writeFileAtomic((fs::path(outDir) / "report" / "cases" / name).string(), html, error)) return false;
  return writeFileAtomic((fs::path(outDir) / "results.json").string(), results.dump(2) + "\n", error) &&
         writeFileAtomic((fs::path(outDir) / "junit.xml").string(), junitXml(results), error) &&
         writeFileAtomic((fs::path(outDir) / "report" / "index.html").string(), reportHtml(results), error);
}

}  // namespace parity::harness
