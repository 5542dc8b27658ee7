#include "harness/run/golden.h"

#include <OpenImageIO/imagebufalgo.h>

#include <cstdio>
#include <ctime>
#include <filesystem>
#include <map>
#include <regex>

#include "harness/io/atomic_file.h"
#include "harness/run/accepted_images.h"
#include "harness/compare/diagnosis.h"
#include "harness/compare/diff.h"
#include "harness/cli/report_error.h"
#include "harness/run/evidence.h"
#include "harness/run/expectations.h"
#include "harness/io/image_io.h"
#include "harness/io/text.h"

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

std::string firstMatch(const std::string& text, const std::regex& re) {
  std::smatch m;
  return std::regex_search(text, m, re) ? m[1].str() : "";
}


// "reference forward/default/reference (max 0.0039 <= 0.004), tests 2 found": a line of what bless checked.
std::string evidenceSummary(const nlohmann::json& claims) {
  std::string text;
  for (const auto& c : claims) {
    std::string one;
    if (c.value("kind", "") == "tests") {
      one = "tests " + std::to_string(c["tests"].size()) + " found";
    } else {
      one = "reference " + c.value("reference", std::string());
      if (c.contains("measured") && c["measured"].contains("diagnosis"))
        one += " (" + c["measured"].value("diagnosis", std::string()) + ")";
      else if (c.contains("measured"))
        one += " (max " + std::to_string(c["measured"].value("max", 0.0)).substr(0, 8) + ")";
    }
    text += (text.empty() ? "" : ", ") + one;
  }
  return text;
}

}  // namespace

// A golden beside its reference image (the run's, else the checked-in golden): for a console
// platform the reference platform's image of the same technique and scene, for the reference
// platform the reference technique's (forward). Identical, or how they differ and which cause
// the diagnosis names (x360's D3D9 pixel centres: "half-pixel shift ... in rasterisation").
// Recorded in the manifest so that a reader sees what the platform or the technique changed;
// null when there is no reference image to compare with.
nlohmann::json referenceComparison(const std::string& image, const std::string& referenceImage,
                                   const std::string& referenceName) {
  OIIO::ImageBuf a, b;
  std::string error;
  if (!fs::exists(referenceImage) || !readImage(referenceImage, &a, &error) || !readImage(image, &b, &error))
    return nullptr;
  DiffThresholds exact;
  exact.fail = exact.warn = 0.0;
  DiffResult d = diffImages(a, b, exact);
  nlohmann::json j = {{"reference", referenceName}, {"identical", d.verdict == DiffVerdict::Pass && d.maxError == 0.0},
                      {"summary", summaryLine(d)}};
  if (!j["identical"].get<bool>()) {
    std::optional<Diagnosis> why = diagnose(a, b);
    j["diagnosis"] = why ? toJson(*why) : nlohmann::json();
  }
  return j;
}

bool readManifest(const std::string& goldenDir, nlohmann::json* manifest, std::string* error) {
  std::string path = (fs::path(goldenDir) / "manifest.json").string();
  std::error_code ec;
  if (!fs::exists(path, ec)) {
    *manifest = nlohmann::json{{"goldens", nlohmann::json::object()}};
    return true;
  }
  if (!readJsonFile(path, manifest, error)) return false;
  // A manifest cut short or of another shape is refused whole: provenance silently lost would
  // let a stale golden pass for a fresh one.
  if (!manifest->is_object()) {
    *error = path + ": not a golden manifest (an object with \"goldens\" expected)";
    return false;
  }
  if (!manifest->contains("goldens")) (*manifest)["goldens"] = nlohmann::json::object();
  if (!(*manifest)["goldens"].is_object()) {
    *error = path + ": \"goldens\" must be an object mapping technique/scene/platform to provenance";
    return false;
  }
  for (const auto& [key, entry] : (*manifest)["goldens"].items())
    if (!entry.is_object()) {
      *error = path + ": golden " + key + ": provenance must be an object";
      return false;
    }
  return !manifest->contains("accepted") || checkAccepted((*manifest)["accepted"], path, error);
}

int blessGoldens(const BlessOptions& o) {
  if (!o.device.empty()) return blessAcceptedImages(o);
  std::string error;
  nlohmann::json results;
  if (!readJsonFile((fs::path(o.from) / "results.json").string(), &results, &error)) return reportError(error);
  std::string goldenDir = o.goldenDir.empty() ? defaultGoldenDir() : o.goldenDir;
  nlohmann::json manifest;
  if (!readManifest(goldenDir, &manifest, &error)) return reportError(error);
  if (!o.backend.empty() && o.reason.empty())
    return reportError("--backend needs --reason: say why this backend's image is right without GL/Vulkan agreement");

  const std::string evidenceFile =
      o.evidenceFile.empty() ? (fs::path(goldenDir) / "evidence.json").string() : o.evidenceFile;
  EvidenceFile evidence;
  if (!loadEvidence(evidenceFile, &evidence, &error)) return reportError(error);

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
  // The image of a case for comparisons: the run's deterministic render, else its golden.
  auto imageOf = [&](const std::string& key) -> std::string {
    auto group = groups.find(key);
    if (group != groups.end())
      for (const auto& [b, c] : group->second)
        if (c.contains("image") && c.value("deterministic", false))
          return (fs::path(o.from) / c["image"].get<std::string>()).string();
    const std::string golden = (fs::path(goldenDir) / (key + ".png")).string();
    return fs::exists(golden) ? golden : "";
  };
  const EvidenceContext evidenceContext{evidence.testsRoot, imageOf};
  for (auto& group : groups) {
    // Named references, not a structured binding: lambdas below capture them (clang 14 cannot
    // capture structured bindings).
    const std::string& key = group.first;
    auto& byBackend = group.second;
    const nlohmann::json& any = byBackend.begin()->second;
    // Nothing rendered there, unless another program's images are what the run judged.
    if (!platformHasRenderPath(any.value("platform", "")) && !any.contains("external")) continue;
    if (any.value("technique", "") == kScriptTechnique) continue;      // scripts have no image
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
    nlohmann::json claims;
    if (!checkEvidence(evidence.claims, key, source, evidenceContext, &claims, &why)) {
      std::fprintf(stderr, "parity: bless: %s refused: %s\n", key.c_str(), why.c_str());
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
    entry["evidence"] = claims;
    // Independent of GL == Vulkan: a console golden beside its technique's reference-platform
    // image, a reference-platform golden beside the reference technique's (forward) image.
    const bool onReference = any.value("platform", "") == "reference";
    if (!onReference || any.value("technique", "") != "forward") {
      const std::string refKey = onReference ? goldenKey("forward", any["scene"], "reference")
                                             : goldenKey(any["technique"], any["scene"], "reference");
      entry["reference_comparison"] = referenceComparison(source, imageOf(refKey), refKey);
    }
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
  // All or nothing: a bless that refuses any golden writes none, so that a folder never holds
  // half of a group's goldens from one run and half from another.
  if (refused) return reportError(std::to_string(refused) + " golden(s) refused (see above); nothing written");
  if (plan.empty()) return reportError(o.from + ": nothing to bless (no matching case was rendered)");
  // What an earlier bless killed mid-write left behind goes first; goldens themselves were only
  // ever replaced whole.
  if (!o.dryRun) removeStaleTemporaries(goldenDir, true);
  for (const Planned& p : plan) {
    std::printf("%s %s: %s; evidence: %s\n", o.dryRun ? "would bless" : "blessed", p.target.c_str(),
                p.entry["reason"].get<std::string>().c_str(), evidenceSummary(p.entry["evidence"]).c_str());
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
  return 0;
}

}  // namespace parity::harness
