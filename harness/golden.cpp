#include "harness/golden.h"

#include <fcntl.h>
#include <fnmatch.h>
#include <unistd.h>

#include <OpenImageIO/imagebufalgo.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <regex>
#include <sstream>

#include "harness/commands.h"
#include "harness/image_io.h"

namespace fs = std::filesystem;

namespace parity::harness {

std::string goldenPath(const std::string& goldenDir, const std::string& technique, const std::string& scene,
                       const std::string& platform) {
  return (fs::path(goldenDir) / technique / scene / (platform + ".png")).string();
}

std::string goldenKey(const std::string& technique, const std::string& scene, const std::string& platform) {
  return technique + "/" + scene + "/" + platform;
}

namespace {

bool readText(const std::string& path, std::string* text, std::string* error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    *error = path + ": cannot read";
    return false;
  }
  std::ostringstream s;
  s << in.rdbuf();
  *text = s.str();
  return true;
}

bool readJsonFile(const std::string& path, nlohmann::json* j, std::string* error) {
  std::string text;
  if (!readText(path, &text, error)) return false;
  try {
    *j = nlohmann::json::parse(text);
  } catch (const std::exception& e) {
    *error = path + ": not valid JSON: " + e.what();
    return false;
  }
  return true;
}

std::string tempSibling(const fs::path& target) {
  std::random_device rd;
  return (target.parent_path() / (".parity-tmp-" + std::to_string(::getpid()) + "-" + std::to_string(rd()) + "-" +
                                  target.filename().string()))
      .string();
}

std::string nowIso() {
  std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof(buf), "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

bool globMatch(const std::string& pattern, const std::string& text) {
  return pattern.empty() || ::fnmatch(pattern.c_str(), text.c_str(), 0) == 0;
}

std::string firstMatch(const std::string& text, const std::regex& re) {
  std::smatch m;
  return std::regex_search(text, m, re) ? m[1].str() : "";
}

bool inFilter(const std::vector<std::string>& filter, const std::string& value) {
  if (filter.empty()) return true;
  for (const std::string& f : filter)
    if (f == value) return true;
  return false;
}

}  // namespace

bool writeFileAtomic(const std::string& path, const std::string& text, std::string* error) {
  fs::path target(path);
  std::error_code ec;
  if (target.has_parent_path()) fs::create_directories(target.parent_path(), ec);
  std::string tmp = tempSibling(target.has_parent_path() ? target : fs::path(".") / target);
  int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    *error = path + ": cannot write";
    return false;
  }
  size_t done = 0;
  while (done < text.size()) {
    ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n <= 0) break;
    done += static_cast<size_t>(n);
  }
  bool ok = done == text.size() && ::fsync(fd) == 0;
  ok = (::close(fd) == 0) && ok;
  if (!ok || std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    *error = path + ": cannot write";
    return false;
  }
  return true;
}

bool copyFileAtomic(const std::string& from, const std::string& to, std::string* error) {
  std::string text;
  if (!readText(from, &text, error)) return false;
  return writeFileAtomic(to, text, error);
}

bool readManifest(const std::string& goldenDir, nlohmann::json* manifest, std::string* error) {
  std::string path = (fs::path(goldenDir) / "manifest.json").string();
  std::error_code ec;
  if (!fs::exists(path, ec)) {
    *manifest = nlohmann::json{{"goldens", nlohmann::json::object()}};
    return true;
  }
  if (!readJsonFile(path, manifest, error)) return false;
  if (!manifest->contains("goldens")) (*manifest)["goldens"] = nlohmann::json::object();
  return true;
}

namespace {

// Every key a tolerance entry may set, where it goes and the values it accepts. A key outside
// this table is refused: a misspelt threshold would otherwise leave the default in force unseen.
enum class Range { NonNegative, Percent };
struct ToleranceField {
  const char* name;
  Range range;
  double Tolerance::*top = nullptr;  // a field of Tolerance itself
  double DiffThresholds::*diff = nullptr;
  bool parity = false;  // `diff` of Tolerance::parity rather than Tolerance::golden
  double AttachmentTolerance::*attachment = nullptr;
};
const std::vector<ToleranceField>& toleranceFields() {
  static const std::vector<ToleranceField> fields = {
      {"golden_fail", Range::NonNegative, nullptr, &DiffThresholds::fail},
      {"golden_fail_percent", Range::Percent, nullptr, &DiffThresholds::failPercent},
      {"golden_hard_fail", Range::NonNegative, nullptr, &DiffThresholds::hardFail},
      {"parity_fail", Range::NonNegative, nullptr, &DiffThresholds::fail, true},
      {"parity_fail_percent", Range::Percent, nullptr, &DiffThresholds::failPercent, true},
      {"golden_flip_mean", Range::NonNegative, &Tolerance::flipMean},
      {"attachment_normal_degrees", Range::NonNegative, nullptr, nullptr, false, &AttachmentTolerance::normalDegrees},
      {"attachment_depth_absolute", Range::NonNegative, nullptr, nullptr, false, &AttachmentTolerance::depthAbsolute},
      {"attachment_float_relative", Range::NonNegative, nullptr, nullptr, false, &AttachmentTolerance::floatRelative},
      {"attachment_quantised_steps", Range::NonNegative, nullptr, nullptr, false, &AttachmentTolerance::quantisedSteps},
      {"attachment_fail_percent", Range::Percent, nullptr, nullptr, false, &AttachmentTolerance::failPercent},
  };
  return fields;
}

const ToleranceField* findToleranceField(const std::string& name) {
  for (const ToleranceField& f : toleranceFields())
    if (name == f.name) return &f;
  return nullptr;
}

std::string jsonTypeName(const nlohmann::json& j) { return j.type_name(); }

// One entry ("default" or a case pattern's): an object of known keys with numbers in range.
bool checkToleranceEntry(const nlohmann::json& e, const std::string& where, std::string* error) {
  if (!e.is_object()) {
    *error = where + ": must be an object of thresholds, not " + jsonTypeName(e);
    return false;
  }
  for (const auto& [name, value] : e.items()) {
    const ToleranceField* f = findToleranceField(name);
    if (!f) {
      std::string known;
      for (const ToleranceField& k : toleranceFields()) known += (known.empty() ? "" : ", ") + std::string(k.name);
      *error = where + ": unknown key '" + name + "' (known: " + known + ")";
      return false;
    }
    if (!value.is_number()) {
      *error = where + ": " + name + " must be a number, not " + jsonTypeName(value);
      return false;
    }
    double v = value.get<double>();
    std::ostringstream shown;
    shown << v;
    if (!std::isfinite(v) || v < 0) {
      *error = where + ": " + name + " is " + shown.str() + "; it must be a finite number >= 0";
      return false;
    }
    if (f->range == Range::Percent && v > 100) {
      *error = where + ": " + name + " is " + shown.str() + "; a percentage must lie in [0, 100]";
      return false;
    }
  }
  return true;
}

void applyToleranceEntry(const nlohmann::json& e, Tolerance* t) {
  for (const auto& [name, value] : e.items()) {
    const ToleranceField* f = findToleranceField(name);
    double v = value.get<double>();
    if (f->top) t->*(f->top) = v;
    if (f->diff) (f->parity ? t->parity : t->golden).*(f->diff) = v;
    if (f->attachment) t->attachments.*(f->attachment) = v;
  }
}

}  // namespace

bool checkTolerances(const nlohmann::json& j, const std::string& file, std::string* error) {
  if (!j.is_object()) {
    *error = file + ": must be an object with \"default\" and \"cases\", not " + jsonTypeName(j);
    return false;
  }
  for (const auto& [key, value] : j.items()) {
    if (key == "about") continue;
    if (key == "default") {
      if (!checkToleranceEntry(value, file + ": default", error)) return false;
    } else if (key == "cases") {
      if (!value.is_object()) {
        *error = file + ": cases must be an object mapping case globs to thresholds, not " + jsonTypeName(value);
        return false;
      }
      for (const auto& [pattern, entry] : value.items())
        if (!checkToleranceEntry(entry, file + ": cases: " + pattern, error)) return false;
    } else {
      *error = file + ": unknown key '" + key + "' (known: about, default, cases)";
      return false;
    }
  }
  return true;
}

bool checkTolerancesFile(const std::string& file, std::string* error) {
  std::error_code ec;
  if (file.empty() || !fs::exists(file, ec)) return true;
  nlohmann::json j;
  return readJsonFile(file, &j, error) && checkTolerances(j, file, error);
}

bool loadTolerance(const std::string& file, const CaseKey& key, Tolerance* out, std::string* error) {
  Tolerance t;
  // Goldens come from the same Mesa build here, where every image is reproducible bit for bit;
  // the default leaves room for one rounding step on a few edge pixels of another build.
  t.golden.fail = 1.5 / 255.0;
  t.golden.failPercent = 0.05;
  t.golden.hardFail = 24.0 / 255.0;
  t.golden.warn = 0.5 / 255.0;
  t.golden.warnPercent = 0.0;
  // GL and Vulkan are bit-identical on Mesa (docs/ARCHITECTURE.md), so the parity budget is zero.
  t.parity.fail = 0.5 / 255.0;
  t.parity.failPercent = 0.0;
  t.parity.warn = 0.5 / 255.0;
  std::error_code ec;
  if (!file.empty() && fs::exists(file, ec)) {
    nlohmann::json j;
    if (!readJsonFile(file, &j, error) || !checkTolerances(j, file, error)) return false;
    auto apply = [&](const nlohmann::json& e, const std::string& source) {
      applyToleranceEntry(e, &t);
      t.parity.warn = std::min(t.parity.warn, t.parity.fail);
      t.golden.warn = std::min(t.golden.warn, t.golden.fail);
      t.source = source;
    };
    if (j.contains("default")) apply(j["default"], file + ": default");
    if (j.contains("cases"))
      for (auto& [pattern, e] : j["cases"].items())
        if (globMatch(pattern, key.id())) apply(e, file + ": " + pattern);
  }
  *out = t;
  return true;
}

bool loadExpectations(const std::string& file, std::vector<Expectation>* out, std::string* error) {
  out->clear();
  std::error_code ec;
  if (file.empty() || !fs::exists(file, ec)) return true;
  nlohmann::json j;
  if (!readJsonFile(file, &j, error)) return false;
  if (!j.is_object()) {
    *error = file + ": must be an object with \"expectations\", not " + jsonTypeName(j);
    return false;
  }
  for (const auto& [key, value] : j.items())
    if (key != "about" && key != "expectations") {
      *error = file + ": unknown key '" + key + "' (known: about, expectations)";
      return false;
    }
  if (!j.contains("expectations")) return true;
  const nlohmann::json& list = j["expectations"];
  if (!list.is_array()) {
    *error = file + ": expectations must be an array, not " + jsonTypeName(list);
    return false;
  }
  for (size_t i = 0; i < list.size(); ++i) {
    const nlohmann::json& e = list[i];
    std::string where = file + ": expectations[" + std::to_string(i) + "]";
    if (!e.is_object()) {
      *error = where + ": must be an object, not " + jsonTypeName(e);
      return false;
    }
    for (const auto& [key, value] : e.items()) {
      if (key != "case" && key != "driver" && key != "result" && key != "reason") {
        *error = where + ": unknown key '" + key + "' (known: case, driver, result, reason)";
        return false;
      }
      if (!value.is_string()) {
        *error = where + ": " + key + " must be a string, not " + jsonTypeName(value);
        return false;
      }
    }
    if (!e.contains("case")) {
      *error = where + ": has no case";
      return false;
    }
    Expectation x;
    x.casePattern = e["case"].get<std::string>();
    x.driverPattern = e.value("driver", "");
    x.reason = e.value("reason", "");
    std::string result = e.value("result", "Fail");
    if (!parseResultName(result, &x.result)) {
      *error = file + ": unknown result '" + result + "' for " + x.casePattern;
      return false;
    }
    if (x.reason.empty()) {
      *error = file + ": expectation for " + x.casePattern + " has no reason";
      return false;
    }
    out->push_back(x);
  }
  return true;
}

const Expectation* findExpectation(const std::vector<Expectation>& list, const std::string& caseId,
                                   const std::string& deviceText) {
  for (const Expectation& e : list)
    if (globMatch(e.casePattern, caseId) && globMatch(e.driverPattern, deviceText)) return &e;
  return nullptr;
}

// Bless rule: a golden is written only when the run shows GL and Vulkan rendering bit-identical
// images of the group, each deterministic, in that same run (re-checked on the files); or with
// an explicit backend and a written reason. The reason goes into the manifest.
int blessGoldens(const BlessOptions& o) {
  std::string error;
  nlohmann::json results;
  if (!readJsonFile((fs::path(o.from) / "results.json").string(), &results, &error)) return reportError(error);
  std::string goldenDir = o.goldenDir.empty() ? defaultGoldenDir() : o.goldenDir;
  nlohmann::json manifest;
  if (!readManifest(goldenDir, &manifest, &error)) return reportError(error);
  if (!o.backend.empty() && o.reason.empty())
    return reportError("--backend needs --reason: say why this backend's image is right without GL/Vulkan agreement");

  // Cases of the run by group.
  std::map<std::string, std::map<std::string, nlohmann::json>> groups;
  for (const auto& c : results.value("cases", nlohmann::json::array())) {
    if (!inFilter(o.filters.techniques, c.value("technique", "")) || !inFilter(o.filters.scenes, c.value("scene", "")) ||
        !inFilter(o.filters.platforms, c.value("platform", "")))
      continue;
    groups[goldenKey(c["technique"], c["scene"], c["platform"])][c.value("backend", "")] = c;
  }
  if (groups.empty()) return reportError(o.from + ": no case of the run matches the filters");

  static const std::regex mesaRe(R"(Mesa ([0-9][0-9A-Za-z.\-]*))");
  static const std::regex llvmRe(R"(LLVM ([0-9][0-9.]*))");
  struct Planned {
    std::string key, source, target;
    nlohmann::json entry;
    std::vector<std::pair<std::string, std::string>> targets;  // per-pass goldens: from, to
  };
  std::vector<Planned> plan;
  int refused = 0;
  for (auto& group : groups) {
    // Named references, not a structured binding: lambdas below capture them (clang 14 cannot
    // capture structured bindings).
    const std::string& key = group.first;
    auto& byBackend = group.second;
    const nlohmann::json& any = byBackend.begin()->second;
    if (!platformHasRenderPath(any.value("platform", ""))) continue;  // nothing rendered there
    auto rendered = [&](const std::string& b) {
      auto it = byBackend.find(b);
      return it != byBackend.end() && it->second.contains("image") && it->second.value("deterministic", false);
    };
    std::string source, sourceBackend, reason, why;
    if (rendered("gl") && rendered("vk")) {
      std::string a = (fs::path(o.from) / byBackend["gl"]["image"].get<std::string>()).string();
      std::string b = (fs::path(o.from) / byBackend["vk"]["image"].get<std::string>()).string();
      DiffThresholds exact;
      exact.fail = 0.0;
      exact.warn = 0.0;
      DiffResult d = diffFiles(a, b, exact);
      if (d.verdict == DiffVerdict::Pass && d.maxError == 0.0) {
        source = a;
        sourceBackend = "gl";
        reason = "GL (" + byBackend["gl"].value("renderer", "") + ") and Vulkan (" + byBackend["vk"].value("renderer", "") +
                 ") rendered bit-identical images in the same run " + results.value("run_id", "") + ", each deterministic over " +
                 std::to_string(results.value("repeat", 2)) + " renders";
      } else {
        why = "GL and Vulkan images differ (" + summaryLine(d) + ")";
      }
    } else {
      why = "the run does not hold deterministic GL and Vulkan images of it";
    }
    if (source.empty() && !o.backend.empty()) {
      if (rendered(o.backend)) {
        source = (fs::path(o.from) / byBackend[o.backend]["image"].get<std::string>()).string();
        sourceBackend = o.backend;
        reason = "explicit, from " + o.backend + " only (" + why + "): " + o.reason;
      } else {
        why += "; and " + o.backend + " has no deterministic image in the run";
      }
    }
    if (source.empty()) {
      std::fprintf(stderr, "parity: bless: %s refused: %s (bless one backend with --backend B --reason TEXT)\n", key.c_str(),
                   why.c_str());
      ++refused;
      continue;
    }
    OIIO::ImageBuf img;
    if (!readImage(source, &img, &error)) return reportError(error);
    nlohmann::json entry;
    entry["file"] = key + ".png";
    entry["width"] = img.spec().width;
    entry["height"] = img.spec().height;
    entry["size"] = std::to_string(img.spec().width) + "x" + std::to_string(img.spec().height);
    entry["pixel_sha1"] = OIIO::ImageBufAlgo::computePixelHashSHA1(img);
    std::string mesa, llvm;
    for (auto& [b, bc] : byBackend) {
      if (!bc.contains("renderer")) continue;
      entry["backends"][b] = {{"renderer", bc.value("renderer", "")}, {"driver", bc.value("driver", "")},
                              {"api", bc.value("api", "")}};
      std::string text = bc.value("renderer", "") + " " + bc.value("driver", "");
      if (mesa.empty()) mesa = firstMatch(text, mesaRe);
      if (llvm.empty()) llvm = firstMatch(text, llvmRe);
    }
    entry["mesa_version"] = mesa;
    entry["llvm_version"] = llvm;
    entry["project_commit"] = results.value("project_commit", "");
    entry["rendered"] = results.value("started", "");
    entry["blessed"] = nowIso();
    entry["source_run"] = results.value("run_id", "");
    entry["gl_provider"] = results.value("gl_provider", "");
    entry["reason"] = reason;
    // Per-pass goldens, blessed alongside from the same backend's targets.
    std::vector<std::pair<std::string, std::string>> targets;
    for (const auto& t : byBackend[sourceBackend].value("targets", nlohmann::json::array())) {
      if (!t.contains("image") || !t["image"].is_string()) continue;
      fs::path from = fs::path(o.from) / t["image"].get<std::string>();
      targets.emplace_back(from.string(), (fs::path(goldenDir) / key / from.filename()).string());
      entry["targets"].push_back((fs::path(key) / from.filename()).string());
    }
    plan.push_back({key, source, (fs::path(goldenDir) / (key + ".png")).string(), entry, targets});
  }
  for (const Planned& p : plan) {
    std::printf("%s %s: %s\n", o.dryRun ? "would bless" : "blessed", p.target.c_str(), p.entry["reason"].get<std::string>().c_str());
    if (o.dryRun) continue;
    // Image first, then the manifest: both are replaced whole (rename), never half-written.
    if (!copyFileAtomic(p.source, p.target, &error)) return reportError(error);
    for (const auto& [from, to] : p.targets)
      if (!copyFileAtomic(from, to, &error)) return reportError(error);
    manifest["goldens"][p.key] = p.entry;
  }
  if (!o.dryRun && !plan.empty()) {
    manifest["format"] =
        "golden/<technique>/<scene>/<platform>.png, per-pass targets in golden/<technique>/<scene>/<platform>/; written only "
        "by `parity bless`";
    if (!writeFileAtomic((fs::path(goldenDir) / "manifest.json").string(), manifest.dump(2) + "\n", &error))
      return reportError(error);
  }
  if (refused) return reportError(std::to_string(refused) + " golden(s) refused (see above)");
  if (plan.empty()) return reportError(o.from + ": nothing to bless (no matching case was rendered)");
  return 0;
}

}  // namespace parity::harness
