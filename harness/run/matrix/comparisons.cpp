// Golden comparisons, cross-backend groups and expectations of a run.
#include "harness/run/matrix/state.h"

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
#include "harness/run/accepted_images.h"
#include "harness/compare/diagnosis.h"
#include "harness/run/expectations.h"
#include "harness/run/external_images.h"
#include "harness/compare/diff.h"
#include "harness/compare/flip.h"
#include "harness/run/golden.h"
#include "harness/io/image_io.h"
#include "rhi/timing_device.h"
#include "harness/run/process.h"
#include "harness/run/render.h"
#include "harness/run/report.h"
#include "harness/scripts/runner.h"
#include "platforms/common/platform.h"
#include "rhi/rhi.h"
#include "scene/scene.h"
#include "techniques/technique.h"

namespace parity::harness::matrix {

CaseResult Comparisons::compareGolden(CaseState& c, const std::string& image, const nlohmann::json& worker, nlohmann::json* out,
                                      std::string* reason) {
  std::string golden = goldenPath(goldenDir_, c.key.technique, c.key.scene, c.key.platform);
  fs::path dir = caseDir(c.key);
  nlohmann::json& j = *out;
  j["golden"] = goldenKey(c.key.technique, c.key.scene, c.key.platform) + ".png";
  j["tolerance"] = {{"fail", c.tolerance.golden.fail}, {"fail_percent", c.tolerance.golden.failPercent},
                    {"hard_fail", std::isfinite(c.tolerance.golden.hardFail) ? nlohmann::json(c.tolerance.golden.hardFail)
                                                                               : nlohmann::json("inf")},
                    {"flip_mean", c.tolerance.flipMean},
                    {"source", c.tolerance.source}};
  compareTargets(c, worker, &j);
  std::error_code ec;
  if (!fs::exists(golden, ec)) {
    j["missing"] = true;
    *reason = "no golden golden/" + j["golden"].get<std::string>() + ": check the images of this run, then create it with "
              "`parity bless --technique " + c.key.technique + " --scene " + c.key.scene + " --platform " +
              c.key.platform + " --from " + o_.outDir + "`";
    return CaseResult::Fail;
  }
  std::string copy = (dir / "golden.png").string();
  {
    std::lock_guard<std::mutex> lock(mutex_);  // both backends of a group copy the same golden
    std::string err;
    if (!fs::exists(copy, ec) && !copyFileAtomic(golden, copy, &err)) {
      *reason = err;
      return CaseResult::Fail;
    }
  }
  j["golden_copy"] = rel(copy);
  const ImageJudgement primary = judgeImage(image, golden, c.tolerance);
  const DiffResult& d = primary.diff;
  j["metrics"] = toJson(d);
  if (c.tolerance.budget) j["budget"] = primary.budget;
  OIIO::ImageBuf a, b;
  std::string err;
  bool images = primary.images && readImage(image, &a, &err) && readImage(golden, &b, &err);
  if (images && d.maxError > 0) {
    std::string heat = (dir / ("diff-golden-" + c.key.backend + ".png")).string();
    if (writeHeatmap(a, b, heat, &err)) j["heatmap"] = rel(heat);
  }
  if (images) {
    j["flip"] = toJson(primary.flip);
    std::string map = (dir / ("flip-golden-" + c.key.backend + ".png")).string();
    if (primary.flip.ok && primary.flip.max > 0 && writeFlipMap(primary.flip, map, &err)) j["flip_map"] = rel(map);
  }
  std::string why;
  if (c.tolerance.budget) {
    why = primary.summary;
  } else {
    why = summaryLine(d);
    if (j.contains("flip") && j["flip"].contains("mean")) {
      std::ostringstream f;
      f << "; FLIP mean " << j["flip"]["mean"].get<double>() << " (tolerance " << c.tolerance.flipMean << ")";
      why += f.str();
    }
  }
  bool fails = !primary.pass;
  // Not the primary golden: an image accepted on this case's device may still match it.
  if (fails) {
    for (const auto& [name, entry] : acceptedFor(manifest_, c.key.group(), c.key.backend)) {
      const std::string path = acceptedImagePath(goldenDir_, c.key.group(), name);
      const ImageJudgement v = judgeImage(image, path, c.tolerance);
      nlohmann::json record = {{"name", name},     {"golden", fs::relative(path, goldenDir_).string()},
                               {"devices", entry["devices"]}, {"metrics", toJson(v.diff)}, {"pass", v.pass}};
      if (v.images) record["flip"] = {{"mean", v.flip.mean}, {"max", v.flip.max}};
      if (c.tolerance.budget) record["budget"] = v.budget;
      j["accepted"].push_back(record);
      if (v.pass) {
        j["matched"] = {{"image", "accepted"}, {"name", name}, {"golden", record["golden"]}};
        fails = false;
        break;
      }
      why += "; nor accepted image " + name + ": " + (c.tolerance.budget ? v.summary : summaryLine(v.diff));
    }
  } else {
    j["matched"] = {{"image", "primary"}, {"golden", j["golden"]}};
  }
  if (!fails && !j.contains("first_diverging_pass")) return CaseResult::Pass;
  if (!fails) {
    // The image passes, an intermediate target does not: a regression the final image hides.
    *reason = "pass " + j["first_diverging_pass"]["pass"].get<std::string>() + ": " +
              j["first_diverging_pass"]["detail"].get<std::string>();
    return CaseResult::Fail;
  }
  *reason = "differs from golden/" + j["golden"].get<std::string>() + ": " + why;
  if (images)
    if (std::optional<Diagnosis> dx = diagnose(b, a)) {
      j["diagnosis"] = toJson(*dx);
      *reason += "; likely cause: " + dx->cause;
    }
  if (j.contains("first_diverging_pass"))
    *reason += "; first diverging pass: " + j["first_diverging_pass"]["pass"].get<std::string>() + " (target " +
               j["first_diverging_pass"]["target"].get<std::string>() + ")";
  return CaseResult::Fail;
}

// The platform layer's diagnostics of the case's real targets and resolves reach the verdict:
// an error-level one fails a case whose image passed, unless golden/expectations.json expects
// its code for the case ({"case", "diagnostic", "reason"}): then the case is an ExpectedFail.
// An expected diagnostic that no longer fires makes a passing case an UnexpectedPass. Each
// diagnostic is kept in the case's golden comparison, marked with its expectation.
CaseResult Comparisons::judgeDiagnostics(const CaseState& c, CaseResult r, const nlohmann::json& worker, nlohmann::json* golden,
                                         std::string* reason) const {
  nlohmann::json diagnostics = worker.value("diagnostics", nlohmann::json::array());
  std::string device = worker.value("renderer", "") + " | " + worker.value("driver", "");
  std::vector<const Expectation*> expected = findDiagnosticExpectations(expectations_, c.key.id(), device);
  std::vector<std::string> unexpected, expectedFired;
  std::set<const Expectation*> used;
  for (nlohmann::json& d : diagnostics) {
    if (d.value("severity", "") != "error") continue;
    const std::string code = d.value("code", "");
    const std::vector<std::string> targets = d.value("targets", std::vector<std::string>{});
    const std::string pass = d.value("pass", "");
    auto e = std::find_if(expected.begin(), expected.end(),
                          [&](const Expectation* x) { return x->matchesDiagnostic(code, targets, pass); });
    if (e != expected.end()) {
      d["expected"] = (*e)->reason;
      used.insert(*e);
      const std::string fired = code + " (" + (*e)->reason + ")";
      if (std::find(expectedFired.begin(), expectedFired.end(), fired) == expectedFired.end()) expectedFired.push_back(fired);
    } else {
      unexpected.push_back(code + ": " + d.value("message", ""));
    }
  }
  (*golden)["diagnostics"] = diagnostics;
  (*golden)["image_matches"] = r == CaseResult::Pass;  // the group verdict is about images
  auto joined = [](const std::vector<std::string>& v) {
    std::string s;
    for (const std::string& x : v) s += (s.empty() ? "" : "; ") + x;
    return s;
  };
  if (r != CaseResult::Pass) {
    if (!unexpected.empty()) *reason += "; platform diagnostics: " + joined(unexpected);
    return r;
  }
  if (!unexpected.empty()) {
    *reason = "platform diagnostic " + joined(unexpected);
    return CaseResult::Fail;
  }
  if (!expectedFired.empty()) {
    *reason = "expected platform diagnostic " + joined(expectedFired) + "; the image matches its golden";
    return CaseResult::ExpectedFail;
  }
  for (const Expectation* e : expected)
    if (!used.count(e)) {
      *reason = "expected platform diagnostic " + e->diagnosticPattern + " (" + e->reason +
                ") did not fire: remove the expectation";
      return CaseResult::UnexpectedPass;
    }
  return r;
}

// Each target the child wrote against golden/<technique>/<scene>/<platform>/<file>, with the
// metric of its kind; the first pass (in the technique's order) writing a differing target is
// where the case starts to diverge.
void Comparisons::compareTargets(CaseState& c, const nlohmann::json& worker, nlohmann::json* out) {
  fs::path dir = caseDir(c.key);
  fs::path goldenTargets = fs::path(goldenDir_) / c.key.technique / c.key.scene / c.key.platform;
  std::map<std::string, bool> targetPass;
  std::map<std::string, std::string> targetDetail;
  for (const auto& t : worker.value("targets", nlohmann::json::array())) {
    std::string name = t.value("name", ""), file = t.value("file", "");
    nlohmann::json e{{"name", name}, {"format", t.value("format", "")}, {"image", rel(dir / file)}};
    AttachmentClass cls = classifyAttachment(name, t.value("format", ""), t.value("logical", ""), c.key.platform);
    e["kind"] = attachmentKindName(cls.kind);
    // Read once: compared with its golden, and EXR data also shown as a PNG with the mapping stated.
    OIIO::ImageBuf image;
    std::string readError;
    const bool readable = readImage((dir / file).string(), &image, &readError);
    if (readable && fs::path(file).extension() == ".exr") {
      OIIO::ImageBuf preview;
      std::string err;
      const fs::path png = dir / (fs::path(file).replace_extension(".preview.png"));
      const std::string mapping = previewOf(cls, image, &preview);
      if (writeImage(png.string(), preview, &err)) e["preview"] = {{"image", rel(png)}, {"mapping", mapping}};
    }
    fs::path golden = goldenTargets / fs::path(file).filename();
    std::error_code ec;
    if (fs::exists(golden, ec)) {
      OIIO::ImageBuf g;
      std::string err = readError;
      AttachmentMetrics m;
      const TargetTolerance* relaxed = c.tolerance.forTarget(name);
      if (readable && readImage(golden.string(), &g, &err))
        m = compareAttachment(cls, g, image, relaxed ? relaxed->attachments : c.tolerance.attachments);
      else
        m.error = err;
      e["golden"] = (fs::path(c.key.technique) / c.key.scene / c.key.platform / fs::path(file).filename()).string();
      e["metrics"] = toJson(m);
      if (relaxed) e["tolerance"] = {{"source", relaxed->source}, {"reason", relaxed->reason}};
      targetPass[name] = m.ok && m.pass;
      std::ostringstream detail;
      if (!m.ok)
        detail << "target " << name << " not compared with its golden: " << m.error;
      else
        detail << "target " << name << " differs from golden/" << e["golden"].get<std::string>() << ": " << m.metric
               << " max " << m.max << " over " << m.threshold << " in " << m.differing << " of " << m.pixels
               << " pixels";
      targetDetail[name] = detail.str();
    } else {
      e["golden"] = nullptr;  // the technique declares it, no per-pass golden blessed yet
    }
    (*out)["targets"].push_back(e);
  }
  for (const auto& p : worker.value("passes", nlohmann::json::array()))
    for (const auto& t : p.value("targets", nlohmann::json::array())) {
      auto it = targetPass.find(t.get<std::string>());
      if (it != targetPass.end() && !it->second) {
        (*out)["first_diverging_pass"] = {
            {"pass", p.value("name", "")}, {"target", it->first}, {"detail", targetDetail[it->first]}};
        return;
      }
    }
  // A differing target no pass lists still fails the case.
  for (const auto& [name, pass] : targetPass)
    if (!pass) {
      (*out)["first_diverging_pass"] = {{"pass", "(not in the technique's pass list)"}, {"target", name},
                                        {"detail", targetDetail[name]}};
      return;
    }
}

// GL↔Vulkan per group, the triangulated verdict, and ParityWarning.
void Comparisons::compareGroups() {
  std::map<std::string, std::vector<CaseState*>> groups;
  for (CaseState& c : cases_) groups[c.key.group()].push_back(&c);
  for (auto& [name, members] : groups) {
    nlohmann::json g{{"group", name}};
    if (members.front()->key.technique == kScriptTechnique) {
      for (CaseState* c : members) g["results"][c->key.backend] = resultName(c->result);
      g["verdict"] = "script (each backend checks the script's own expectations)";
      groups_.push_back(g);
      continue;
    }
    CaseState* gl = nullptr;
    CaseState* vk = nullptr;
    std::vector<CaseState*> rendered;
    for (CaseState* c : members) {
      if (c->key.backend == "gl") gl = c;
      if (c->key.backend == "vk") vk = c;
      if (c->rendered) rendered.push_back(c);
      g["results"][c->key.backend] = resultName(c->result);
    }
    bool both = gl && vk && gl->rendered && vk->rendered;
    DiffResult d;
    if (both) {
      fs::path dir = caseDir(gl->key);
      std::string a = (dir / "gl.png").string(), b = (dir / "vk.png").string();
      d = diffFiles(a, b, gl->tolerance.parity);
      g["parity"] = toJson(d);
      if (d.maxError > 0) {
        OIIO::ImageBuf ia, ib;
        std::string err;
        std::string heat = (dir / "diff-gl-vk.png").string();
        if (readImage(a, &ia, &err) && readImage(b, &ib, &err) && d.verdict != DiffVerdict::SizeMismatch &&
            writeHeatmap(ia, ib, heat, &err))
          g["parity"]["heatmap"] = rel(heat);
      }
      bool parityOk = d.verdict == DiffVerdict::Pass || d.verdict == DiffVerdict::Warn;
      auto goldenOk = [](const CaseState* c) {
        return c->raw == CaseResult::Pass || c->raw == CaseResult::Flake || c->golden.value("image_matches", false);
      };
      auto goldenMissing = [](const CaseState* c) { return c->golden.value("missing", false); };
      std::string verdict;
      if (goldenMissing(gl)) verdict = parityOk ? "no golden (backends agree)" : "no golden (backends differ)";
      else if (goldenOk(gl) && goldenOk(vk)) verdict = parityOk ? "pass" : "parity warning";
      else if (goldenOk(gl) && !goldenOk(vk)) verdict = "vk regression";
      else if (!goldenOk(gl) && goldenOk(vk)) verdict = "gl regression";
      else if (parityOk) verdict = staleGolden(*gl) ? "stale golden" : "technique regression";
      else verdict = "gl and vk regression";
      g["verdict"] = verdict;
      if (verdict == "parity warning")
        for (CaseState* c : {gl, vk})
          if (c->result == CaseResult::Pass) {
            c->result = c->raw = CaseResult::ParityWarning;
            c->reason = "matches the golden, but GL and Vulkan differ beyond the parity budget: " + summaryLine(d);
          }
      for (CaseState* c : {gl, vk}) c->golden["verdict"] = verdict;
    }
    if (rendered.size() >= 2) {
      const std::string pairsVerdict = comparePairs(rendered, both ? &d : nullptr, &g);
      // A gl/vk group keeps its triangulated verdict; more backends add what their pairs say.
      if (!both) g["verdict"] = pairsVerdict;
      else if (rendered.size() > 2) g["verdict"] = g["verdict"].get<std::string>() + "; " + pairsVerdict;
      for (CaseState* c : rendered) c->golden["verdict"] = g["verdict"];
    } else {
      g["verdict"] = "no comparison (fewer than two backends rendered)";
    }
    groups_.push_back(g);
  }
}

// Both backends differ from the golden the same way: the golden is stale when it was made on
// another driver than the one this run used; otherwise the technique changed.
bool Comparisons::staleGolden(const CaseState& c) const {
  const std::string key = c.key.group();
  if (!manifest_["goldens"].contains(key)) return false;
  const nlohmann::json prov = manifest_["goldens"][key].value("backends", nlohmann::json::object());
  if (!prov.is_object()) return false;
  if (!prov.contains(c.key.backend)) return false;
  return prov[c.key.backend].value("renderer", "") != c.device.value("renderer", "") ||
         prov[c.key.backend].value("driver", "") != c.device.value("driver", "");
}

void Comparisons::applyExpectation(CaseState& c) {
  const Expectation* e = expectedFor(c);
  if (!e) return;
  c.expectationEntry = e;
  c.expectation = e->reason;
  c.expected = resultName(e->result);
  if (c.raw == e->result && c.result != CaseResult::Flake) {
    if (c.result != CaseResult::Skip) {
      c.reason = "expected " + c.expected + " (" + e->reason + "): " + c.reason;
      c.result = CaseResult::ExpectedFail;
    }
  } else if (c.result == CaseResult::Pass) {
    c.result = CaseResult::UnexpectedPass;
    c.reason = "expected " + c.expected + " (" + e->reason + ") but it passed: remove the expectation";
  } else if (c.result != CaseResult::Skip) {
    c.reason = "expected " + c.expected + " (" + e->reason + "), got " + resultName(c.raw) + ": " + c.reason;
  }
}

}  // namespace parity::harness::matrix
