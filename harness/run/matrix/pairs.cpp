// Every pair of backends of a group, whatever their names (parity's gl and vk, another engine's
// d3d12, metal, vulkan): which agree, and the odd one out with the diagnosis of its difference.
#include "harness/run/matrix/state.h"

#include <algorithm>
#include <optional>

#include "harness/compare/diagnosis.h"
#include "harness/compare/diff.h"
#include "harness/io/image_io.h"

namespace parity::harness::matrix {

namespace {

// Mesa's drivers run one compiler (NIR, llvmpipe/lavapipe here) behind every API, so two of them
// render the same bits; any other pair of drivers may round differently.
bool isMesa(const nlohmann::json& device) {
  for (const char* field : {"renderer", "driver", "api"}) {
    const std::string s = device.value(field, "");
    for (const char* name : {"Mesa", "llvmpipe", "lavapipe"})
      if (s.find(name) != std::string::npos) return true;
  }
  return false;
}

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (size_t i = 0; i < names.size(); ++i) s += (i == 0 ? "" : i + 1 == names.size() ? " and " : ", ") + names[i];
  return s;
}

}  // namespace

std::optional<std::string> oddOneOut(const std::vector<std::string>& backends, const nlohmann::json& pairs) {
  // With two backends nothing says which of them is wrong (the golden may: the gl/vk verdict).
  if (backends.size() < 3) return std::nullopt;
  for (const std::string& candidate : backends) {
    bool odd = true;
    for (const nlohmann::json& p : pairs) {
      const bool involves = p["backends"][0] == candidate || p["backends"][1] == candidate;
      // Every pair with the candidate differs, every pair without it agrees.
      if (involves == p["agree"].get<bool>()) odd = false;
    }
    if (odd) return candidate;
  }
  return std::nullopt;
}

std::string Comparisons::comparePairs(const std::vector<CaseState*>& rendered, const DiffResult* glVk, nlohmann::json* g) {
  std::map<std::string, std::string> images;
  std::vector<std::string> names;
  for (const CaseState* c : rendered) {
    names.push_back(c->key.backend);
    images[c->key.backend] = (caseDir(c->key) / (c->key.backend + ".png")).string();
  }
  nlohmann::json pairs = nlohmann::json::array();
  for (size_t i = 0; i < rendered.size(); ++i)
    for (size_t j = i + 1; j < rendered.size(); ++j) {
      const CaseState& a = *rendered[i];
      const CaseState& b = *rendered[j];
      const bool glAndVk = (a.key.backend == "gl" && b.key.backend == "vk") || (a.key.backend == "vk" && b.key.backend == "gl");
      // gl/vk keep the parity budget they always had; other pairs have it only when both are Mesa.
      const bool bitIdentity = glAndVk || (isMesa(a.device) && isMesa(b.device));
      nlohmann::json p{{"backends", {a.key.backend, b.key.backend}},
                       {"rule", bitIdentity ? "parity budget (one Mesa compiler behind both)" : "golden tolerance (different drivers)"}};
      DiffResult d = glVk && glAndVk ? *glVk
                                     : diffFiles(images[a.key.backend], images[b.key.backend],
                                                 bitIdentity ? a.tolerance.parity : a.tolerance.golden);
      p["agree"] = d.verdict == DiffVerdict::Pass || d.verdict == DiffVerdict::Warn;
      p["metrics"] = toJson(d);
      if (glAndVk && g->contains("parity") && (*g)["parity"].contains("heatmap")) {
        p["heatmap"] = (*g)["parity"]["heatmap"];
      } else if (d.maxError > 0 && d.verdict != DiffVerdict::SizeMismatch && d.verdict != DiffVerdict::FileError) {
        OIIO::ImageBuf ia, ib;
        std::string err;
        const std::string heat = (caseDir(a.key) / ("diff-" + a.key.backend + "-" + b.key.backend + ".png")).string();
        if (readImage(images[a.key.backend], &ia, &err) && readImage(images[b.key.backend], &ib, &err) &&
            writeHeatmap(ia, ib, heat, &err))
          p["heatmap"] = rel(heat);
      }
      pairs.push_back(p);
    }
  (*g)["pairs"] = pairs;
  const bool allAgree = std::all_of(pairs.begin(), pairs.end(), [](const nlohmann::json& p) { return p["agree"].get<bool>(); });
  if (allAgree) return "backends agree (" + joined(names) + ")";
  const std::optional<std::string> odd = oddOneOut(names, pairs);
  if (!odd) return "backends differ (no odd one out)";
  std::vector<std::string> others;
  for (const std::string& n : names)
    if (n != *odd) others.push_back(n);
  // The others agree with each other: any of them stands for what the odd one should have drawn.
  nlohmann::json o{{"backend", *odd}, {"differs_from", others}, {"compared_with", others.front()}};
  std::string verdict = *odd + " differs from " + joined(others) + ", which agree";
  OIIO::ImageBuf expected, image;
  std::string err;
  std::optional<Diagnosis> dx;
  if (readImage(images[others.front()], &expected, &err) && readImage(images[*odd], &image, &err))
    dx = diagnose(expected, image);
  if (dx) {
    o["diagnosis"] = toJson(*dx);
    verdict += " (likely cause: " + dx->cause + ")";
  } else {
    verdict += " (no porting bug explains the difference)";
  }
  (*g)["odd_one_out"] = o;
  return verdict;
}

}  // namespace parity::harness::matrix
