#include "harness/report.h"

#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "harness/golden.h"
#include "harness/run.h"

namespace fs = std::filesystem;

namespace parity::harness {

namespace {

std::string xmlEscape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default:
        // XML 1.0 forbids most control characters.
        if (static_cast<unsigned char>(c) < 0x20 && c != '\n' && c != '\t' && c != '\r') out += ' ';
        else out += c;
    }
  }
  return out;
}

std::string str(const nlohmann::json& j, const char* key) {
  return j.contains(key) && j[key].is_string() ? j[key].get<std::string>() : "";
}

std::string num(const nlohmann::json& j, const char* key) {
  if (!j.contains(key)) return "";
  const nlohmann::json& v = j[key];
  if (v.is_string()) return v.get<std::string>();
  std::ostringstream s;
  s.precision(6);
  s << v.get<double>();
  return s.str();
}

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
  std::string a = "g-" + group;
  for (char& c : a)
    if (c == '/') c = '-';
  return a;
}

}  // namespace

std::string junitXml(const nlohmann::json& results) {
  std::map<std::string, std::vector<const nlohmann::json*>> byTechnique;
  const nlohmann::json cases = results.value("cases", nlohmann::json::array());
  for (const auto& c : cases) byTechnique[str(c, "technique")].push_back(&c);
  int failures = 0, errors = 0, skipped = 0;
  for (const auto& c : cases) {
    CaseResult r = CaseResult::Fail;
    parseResultName(str(c, "result"), &r);
    if (r == CaseResult::Crash || r == CaseResult::Timeout) ++errors;
    else if (isBadResult(r)) ++failures;
    else if (r == CaseResult::Skip) ++skipped;
  }
  std::ostringstream x;
  x << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  x << "<testsuites name=\"parity\" tests=\"" << cases.size() << "\" failures=\"" << failures << "\" errors=\"" << errors
    << "\" skipped=\"" << skipped << "\">\n";
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
      if (r == CaseResult::Crash || r == CaseResult::Timeout)
        x << "      <error type=\"" << result << "\" message=\"" << xmlEscape(str(*c, "reason")) << "\">"
          << xmlEscape(detail + "\n" + str(*c, "stderr")) << "</error>\n";
      else if (isBadResult(r))
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
<style>
body{font-family:system-ui,sans-serif;margin:1.5em;color:#222}
table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:3px 6px;font-size:13px;vertical-align:top}
table.grid td.cell{color:#fff;text-align:center;min-width:90px}table.grid td.cell a{color:#fff}
.imgs{display:flex;flex-wrap:wrap;gap:10px}.imgs figure{margin:0}.imgs img{image-rendering:pixelated;border:1px solid #888;cursor:zoom-in}
.imgs img.zoom{width:auto!important;transform:scale(3);transform-origin:top left;position:relative;z-index:2;cursor:zoom-out}
figcaption{font-size:12px}.ab{position:relative;display:inline-block}.ab img{display:block}
.ab .top{position:absolute;left:0;top:0;overflow:hidden;border-right:2px solid #f0f}
section{border-top:2px solid #ddd;margin-top:1.5em;padding-top:.5em}.res{color:#fff;padding:1px 5px;border-radius:3px}
</style></head><body>
<h1>parity report</h1>
)";
  h << "<p>run " << xmlEscape(str(results, "run_id")) << ", commit " << xmlEscape(str(results, "project_commit")) << ", size "
    << xmlEscape(str(results, "size")) << ", finished " << xmlEscape(str(results, "finished")) << "</p>\n<p>";
  const nlohmann::json counts = results.value("counts", nlohmann::json::object());
  for (const auto& item : counts.items())
    h << "<span class=\"res\" style=\"background:" << colour(item.key()) << "\">" << item.value().get<int>() << " "
      << item.key() << "</span> ";
  h << "</p>\n<h2>Backends</h2><table><tr><th>backend</th><th>renderer</th><th>driver</th><th>status</th></tr>\n";
  for (const auto& b : results.value("backends", nlohmann::json::array()))
    h << "<tr><td>" << xmlEscape(str(b, "name")) << "</td><td>" << xmlEscape(str(b, "renderer")) << "</td><td>"
      << xmlEscape(str(b, "driver")) << "</td><td>" << (b.value("available", false) ? "available" : xmlEscape(str(b, "reason")))
      << "</td></tr>\n";
  h << "</table>\n";
  const nlohmann::json timing = results.value("timing", nlohmann::json::object());
  h << "<p>wall " << num(timing, "wall_s") << " s; child processes " << num(timing, "child_process_s") << " s, of which rendering "
    << num(timing, "render_s") << " s</p>\n";

  // The grid: rows technique/scene, columns platform × backend.
  h << "<h2>Results</h2><table class=\"grid\" id=\"grid\"><tr><th rowspan=\"2\">technique / scene</th>";
  for (const std::string& p : platforms) h << "<th colspan=\"" << backends.size() << "\">" << p << "</th>";
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
        h << "<td class=\"cell\" data-result=\"" << result << "\" style=\"background:" << colour(result) << "\" title=\""
          << xmlEscape(str(*c, "reason")) << "\"><a href=\"#" << anchor(row + "/" + p) << "\">" << result << "</a></td>";
      }
    h << "</tr>\n";
  }
  h << "</table>\n";

  // One section per group that rendered something or failed in an interesting way.
  for (const auto& [group, members] : groups) {
    bool anyImage = false;
    for (const auto& [b, c] : members) anyImage = anyImage || c->contains("image") || str(*c, "result") != "Skip";
    if (!anyImage) continue;
    h << "<section id=\"" << anchor(group) << "\"><h3>" << xmlEscape(group) << "</h3>\n";
    auto gi = groupInfo.find(group);
    if (gi != groupInfo.end()) h << "<p>verdict: <b>" << xmlEscape(str(gi->second, "verdict")) << "</b></p>\n";
    std::string goldenImg;
    for (const auto& [b, c] : members)
      if (c->contains("golden") && (*c)["golden"].contains("golden_copy")) goldenImg = (*c)["golden"]["golden_copy"];
    h << "<div class=\"imgs\">";
    auto figure = [&](const std::string& path, const std::string& caption) {
      h << "<figure><img src=\"../" << xmlEscape(path) << "\" width=\"320\" onclick=\"this.classList.toggle('zoom')\"><figcaption>"
        << xmlEscape(caption) << "</figcaption></figure>";
    };
    if (!goldenImg.empty()) figure(goldenImg, "golden");
    for (const auto& [b, c] : members) {
      if (c->contains("image")) figure(str(*c, "image"), b + " (" + str(*c, "renderer") + ")");
      if (c->contains("golden") && (*c)["golden"].contains("heatmap")) figure((*c)["golden"]["heatmap"], "golden vs " + b);
    }
    if (gi != groupInfo.end() && gi->second.contains("parity") && gi->second["parity"].contains("heatmap"))
      figure(gi->second["parity"]["heatmap"], "gl vs vk");
    h << "</div>\n";
    // A/B slider: golden over each backend.
    for (const auto& [b, c] : members)
      if (!goldenImg.empty() && c->contains("image")) {
        h << "<p>A/B golden | " << xmlEscape(b) << ": <input type=\"range\" min=\"0\" max=\"100\" value=\"50\" "
          << "oninput=\"this.nextElementSibling.querySelector('.top').style.width=this.value+'%'\"><span class=\"ab\">"
          << "<img src=\"../" << xmlEscape(str(*c, "image")) << "\" width=\"640\"><span class=\"top\" style=\"width:50%\">"
          << "<img src=\"../" << xmlEscape(goldenImg) << "\" width=\"640\" style=\"max-width:none\"></span></span></p>\n";
      }
    h << "<table><tr><th>backend</th><th>result</th><th>reason</th><th>max</th><th>mean</th><th>RMS</th><th>PSNR</th>"
         "<th>pixels over</th><th>render ms</th><th>attempts</th></tr>\n";
    for (const auto& [b, c] : members) {
      nlohmann::json m = c->contains("golden") ? (*c)["golden"].value("metrics", nlohmann::json::object()) : nlohmann::json::object();
      std::string ms;
      for (const auto& t : c->value("render_ms", nlohmann::json::array())) {
        std::ostringstream s;
        s.precision(4);
        s << t.get<double>();
        ms += (ms.empty() ? "" : ", ") + s.str();
      }
      std::string result = str(*c, "result");
      h << "<tr><td>" << xmlEscape(b) << "</td><td><span class=\"res\" style=\"background:" << colour(result) << "\">" << result
        << "</span></td><td>" << xmlEscape(str(*c, "reason")) << "</td><td>" << num(m, "max_error") << "</td><td>"
        << num(m, "mean_error") << "</td><td>" << num(m, "rms_error") << "</td><td>" << num(m, "psnr") << "</td><td>"
        << num(m, "pixels_over_fail") << "</td><td>" << ms << "</td><td>" << c->value("attempts", nlohmann::json::array()).size()
        << "</td></tr>\n";
    }
    if (gi != groupInfo.end() && gi->second.contains("parity")) {
      const nlohmann::json& p = gi->second["parity"];
      h << "<tr><td>gl vs vk</td><td>" << xmlEscape(str(p, "verdict")) << "</td><td>parity budget</td><td>"
        << num(p, "max_error") << "</td><td>" << num(p, "mean_error") << "</td><td>" << num(p, "rms_error") << "</td><td>"
        << num(p, "psnr") << "</td><td>" << num(p, "pixels_over_fail") << "</td><td></td><td></td></tr>\n";
    }
    h << "</table></section>\n";
  }
  h << "</body></html>\n";
  return h.str();
}

bool writeReports(const std::string& outDir, nlohmann::json& results, std::string* error) {
  nlohmann::json counts = nlohmann::json::object();
  for (const auto& c : results.value("cases", nlohmann::json::array())) {
    std::string r = c.value("result", "?");
    counts[r] = counts.value(r, 0) + 1;
  }
  results["counts"] = counts;
  std::error_code ec;
  fs::create_directories(fs::path(outDir) / "report", ec);
  return writeFileAtomic((fs::path(outDir) / "results.json").string(), results.dump(2) + "\n", error) &&
         writeFileAtomic((fs::path(outDir) / "junit.xml").string(), junitXml(results), error) &&
         writeFileAtomic((fs::path(outDir) / "report" / "index.html").string(), reportHtml(results), error);
}

}  // namespace parity::harness
