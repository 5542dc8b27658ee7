// The cases of a run: filters, shards, scripts by name, and `parity run --list` / --ctest.
#include "harness/run/devices.h"
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

namespace fs = std::filesystem;

namespace parity::harness {


// ---------------------------------------------------------------------------------------------
// Names, keys, filters, shards

bool parseShard(const std::string& text, Shard* out, std::string* error) {
  size_t slash = text.find('/');
  try {
    if (slash == std::string::npos) throw std::invalid_argument("no slash");
    size_t ui = 0, un = 0;
    int i = std::stoi(text.substr(0, slash), &ui);
    int n = std::stoi(text.substr(slash + 1), &un);
    if (ui != slash || un != text.size() - slash - 1 || n < 1 || i < 0 || i >= n) throw std::invalid_argument("range");
    *out = Shard{i, n};
    return true;
  } catch (const std::exception&) {
    *error = "shard '" + text + "' is not INDEX/COUNT with 0 <= INDEX < COUNT (e.g. 0/4)";
    return false;
  }
}

bool shardFromEnvironment(Shard* out, std::string* error) {
  const char* index = std::getenv("GTEST_SHARD_INDEX");
  const char* total = std::getenv("GTEST_TOTAL_SHARDS");
  if (!index || !total) return true;
  if (!parseShard(std::string(index) + "/" + total, out, error)) {
    *error = "GTEST_SHARD_INDEX/GTEST_TOTAL_SHARDS: " + *error;
    return false;
  }
  return true;
}

namespace {


bool checkNames(const std::vector<std::string>& filter, const std::vector<std::string>& known, const std::string& what,
                std::string* error) {
  for (const std::string& f : filter)
    if (std::find(known.begin(), known.end(), f) == known.end()) {
      std::string list;
      for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
      *error = "unknown " + what + " '" + f + "' (" + scene::didYouMean(f, known) + "known: " + list + ")";
      return false;
    }
  return true;
}

}  // namespace

bool scriptsByName(const RunFilters& f, std::map<std::string, std::string>* byName, std::string* error) {
  std::vector<std::string> roots = f.scripts;
  if (roots.empty()) roots.push_back((fs::path(rhi::dataDirectory()) / "tests" / "scripts").string());
  error->clear();
  std::vector<std::string> files = script::collectScripts(roots, error);
  if (!error->empty()) return false;
  byName->clear();
  for (const std::string& file : files) {
    std::string name = fs::path(file).filename().string();
    name = name.substr(0, name.size() - std::string(".amber").size());
    auto [it, added] = byName->emplace(name, file);
    if (!added) {
      *error = file + ": another script has the name '" + name + "' (" + it->second + "); case ids need distinct names";
      return false;
    }
  }
  return true;
}

std::vector<CaseKey> enumerateCases(const RunFilters& f, const Shard& shard, std::string* error) {
  std::vector<std::string> techniques, scenes = scene::sceneNames(), backends = rhi::compiledBackends();
  for (const auto& t : techniques::techniqueRegistry()) techniques.push_back(t.name);
  error->clear();
  if (!f.devices.empty()) {
    // Each named device's backend must be compiled in; the child resolves the rest (a device
    // missing there is unavailable, with the child's reason).
    for (const std::string& d : f.devices)
      if (backendOfDevice(d).empty()) {
        *error = "unknown device '" + d + "' (devices are named BACKEND-DRIVER, e.g. gl-zink; `parity list` lists them)";
        return {};
      }
    backends = f.devices;
  }
  bool allScenes = f.scenes.size() == 1 && f.scenes[0] == "all";
  // Scripts join the matrix unless the technique filter leaves them out.
  bool scriptCaseNamed = std::any_of(f.cases.begin(), f.cases.end(),
                                     [](const std::string& id) { return id.rfind(std::string(kScriptTechnique) + "/", 0) == 0; });
  bool wantScripts = f.techniques.empty() || inFilter(f.techniques, kScriptTechnique) || scriptCaseNamed;
  std::map<std::string, std::string> scripts;
  std::vector<std::string> knownTechniques = techniques, knownScenes = scenes;
  knownTechniques.push_back(kScriptTechnique);
  if (wantScripts) {
    if (!scriptsByName(f, &scripts, error)) return {};
    for (const auto& entry : scripts) knownScenes.push_back(entry.first);
  }
  if (!checkNames(f.techniques, knownTechniques, "technique", error) ||
      (!allScenes && !checkNames(f.scenes, knownScenes, "scene", error)) ||
      !checkNames(f.platforms, platformNames(), "platform", error) || !checkNames(f.backends, backends, "backend", error))
    return {};
  std::set<std::string> wanted(f.cases.begin(), f.cases.end());
  for (const std::string& id : f.cases) {
    CaseKey k;
    if (!CaseKey::parse(id, &k, error)) return {};
    if (!checkNames({k.technique}, knownTechniques, "technique", error) ||
        !checkNames({k.scene}, k.technique == kScriptTechnique ? knownScenes : scenes, "scene", error) ||
        !checkNames({k.platform}, platformNames(), "platform", error) || !checkNames({k.backend}, backends, "backend", error))
      return {};
  }
  std::sort(techniques.begin(), techniques.end());
  std::sort(scenes.begin(), scenes.end());
  // The default matrix is what the project checks in: the default scene and every scene with a
  // golden. Other available scenes (the shared asset models) are rendered when named, or with
  // `--scene all`; without goldens they would only report "no golden".
  RunFilters filters = f;
  if (filters.scenes.empty() && filters.cases.empty()) {
    filters.scenes.push_back("default");
    std::error_code ec;
    for (const std::string& s : scenes)
      for (const std::string& t : techniques)
        if (fs::is_directory(fs::path(defaultGoldenDir()) / t / s, ec)) {
          filters.scenes.push_back(s);
          break;
        }
  } else if (filters.scenes.size() == 1 && filters.scenes[0] == "all") {
    filters.scenes.clear();
  }
  std::vector<CaseKey> cases;
  size_t groupIndex = 0;
  for (const std::string& t : techniques) {
    if (!inFilter(filters.techniques, t)) continue;
    for (const std::string& s : scenes) {
      if (!inFilter(filters.scenes, s)) continue;
      for (const std::string& p : platformNames()) {
        if (!inFilter(f.platforms, p)) continue;
        // Shards split the matrix by group, so both backends of a group land in one shard.
        bool mine = static_cast<int>(groupIndex++ % static_cast<size_t>(shard.count)) == shard.index;
        for (const std::string& b : backends) {
          CaseKey k{t, s, p, b};
          if (!inFilter(f.backends, b) || (!wanted.empty() && !wanted.count(k.id()))) continue;
          if (mine) cases.push_back(k);
        }
      }
    }
  }
  if (!wantScripts) return cases;
  // Scripts: a scene filter names scripts; without one (or with "all") every script is taken.
  std::vector<std::string> paths;
  std::map<std::string, std::string> nameOf;
  for (const auto& [name, path] : scripts)
    if (f.scenes.empty() || allScenes || inFilter(f.scenes, name)) {
      paths.push_back(path);
      nameOf[path] = name;
    }
  if (paths.empty()) return cases;
  // Each script x platform it allows x backend, grouped by script and platform (in name order).
  std::map<std::pair<std::string, std::string>, std::vector<std::string>> groups;
  for (const script::ScriptCase& c : script::listScriptCases(paths, backends, f.platforms, error))
    groups[{nameOf[c.script], c.platform}].push_back(c.backend);
  if (!error->empty()) return {};
  for (const auto& [group, groupBackends] : groups) {
    bool mine = static_cast<int>(groupIndex++ % static_cast<size_t>(shard.count)) == shard.index;
    for (const std::string& b : groupBackends) {
      CaseKey k{kScriptTechnique, group.first, group.second, b};
      if (!inFilter(f.backends, b) || (!wanted.empty() && !wanted.count(k.id()))) continue;
      if (mine) cases.push_back(k);
    }
  }
  return cases;
}

std::string defaultGoldenDir() { return (fs::path(rhi::dataDirectory()) / "golden").string(); }

int listCases(const RunFilters& filters, const Shard& shard, bool ctest, const std::string& binary,
              const std::string& outRoot) {
  std::string error;
  std::vector<CaseKey> keys = enumerateCases(filters, shard, &error);
  if (!error.empty()) return reportError(error);
  for (const CaseKey& k : keys) {
    if (!ctest) {
      std::printf("%s\n", k.id().c_str());
      continue;
    }
    std::string name = "parity." + k.technique + "." + k.scene + "." + k.platform + "." + k.backend;
    std::string out = (fs::path(outRoot) / (k.technique + "." + k.scene + "." + k.platform + "." + k.backend)).string();
    std::printf("add_test([==[%s]==] [==[%s]==] run --case [==[%s]==] --out [==[%s]==] --jobs 1 --no-progress)\n",
                name.c_str(), binary.c_str(), k.id().c_str(), out.c_str());
    // A case that would render but has no checked-in golden is registered disabled (CTest lists
    // it as "Not Run (Disabled)"): `parity run` reports it as a Fail saying how to bless it.
    std::error_code ec;
    bool noGolden = k.technique != kScriptTechnique && platformHasRenderPath(k.platform) &&
                    !fs::exists(goldenPath(defaultGoldenDir(), k.technique, k.scene, k.platform), ec);
    std::printf("set_tests_properties([==[%s]==] PROPERTIES LABELS \"case;%s;%s;%s;%s\" SKIP_RETURN_CODE 77 TIMEOUT 300%s)\n",
                name.c_str(), k.backend.c_str(), k.platform.c_str(), k.technique.c_str(), k.scene.c_str(),
                noGolden ? " DISABLED TRUE" : "");
  }
  return 0;
}

}  // namespace parity::harness
