// `parity bless --device D`: the images a run's cases rendered on device D become accepted images
// of their groups (harness/run/accepted_images.h), beside the primary golden, never over it.
#include <OpenImageIO/imagebufalgo.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

#include "harness/cli/report_error.h"
#include "harness/compare/diagnosis.h"
#include "harness/io/atomic_file.h"
#include "harness/io/image_io.h"
#include "harness/io/text.h"
#include "harness/run/accepted_images.h"
#include "harness/run/expectations.h"

namespace fs = std::filesystem;

namespace parity::harness {

namespace {

// The accepted image beside the primary golden, measured as a reviewer would: the channel
// difference, LDR-FLIP (mean, max, the plain 50th and 99th percentiles) and what the diagnosis
// names. The size of the difference is recorded, not bounded (a device's image is accepted
// because someone says why, --reason); its kind gates: a difference the diagnosis explains as a
// porting mistake (a flip, a shift, a swizzle, sRGB, a value range) is a wrong image, not
// another device's, and is refused. Precision loss is what devices differ by, and passes.
bool measureAgainstPrimary(const std::string& primary, const std::string& image, nlohmann::json* evidence,
                           std::string* why) {
  OIIO::ImageBuf a, b;
  if (!readImage(primary, &a, why) || !readImage(image, &b, why)) return false;
  DiffThresholds step;
  step.fail = step.warn = 0.5 / 255.0;
  const DiffResult d = diffImages(a, b, step);
  if (d.verdict == DiffVerdict::SizeMismatch || d.verdict == DiffVerdict::FileError) {
    *why = "against the primary golden: " + d.message;
    return false;
  }
  if (d.maxError == 0) {
    *why = "identical to the primary golden, which it already matches";
    return false;
  }
  const FlipResult flip = computeLdrFlip(a, b);
  if (!flip.ok) {
    *why = "no FLIP against the primary golden: " + flip.error;
    return false;
  }
  const std::optional<Diagnosis> diagnosis = diagnose(a, b);
  if (diagnosis && diagnosis->cause.rfind("precision loss", 0) != 0) {
    *why = "its difference from the primary golden is a porting mistake, " + diagnosis->cause + " (" + diagnosis->detail +
           "): a wrong image, not another device's";
    return false;
  }
  *evidence = {{"primary_sha1", OIIO::ImageBufAlgo::computePixelHashSHA1(a)},
               {"diff",
                {{"max", d.maxError},
                 {"mean", d.meanError},
                 {"max_difference", std::lround(d.maxError * 255.0)},
                 {"differing_pixels", d.failPixels},
                 {"summary", summaryLine(d)}}},
               {"flip",
                {{"mean", flip.mean},
                 {"max", flip.max},
                 {"p50", flipPercentile(flip, 50)},
                 {"p99", flipPercentile(flip, 99)}}},
               {"diagnosis", diagnosis ? toJson(*diagnosis) : nlohmann::json()}};
  return true;
}

}  // namespace

int blessAcceptedImages(const BlessOptions& o) {
  std::string error;
  if (!o.backend.empty()) return reportError("bless: --device and --backend exclude each other");
  if (o.reason.empty())
    return reportError("bless: --device needs --reason: say why this device's image is right where it differs from the "
                       "primary golden");
  nlohmann::json results;
  if (!readJsonFile((fs::path(o.from) / "results.json").string(), &results, &error)) return reportError(error);
  const std::string goldenDir = o.goldenDir.empty() ? defaultGoldenDir() : o.goldenDir;
  nlohmann::json manifest;
  if (!readManifest(goldenDir, &manifest, &error)) return reportError(error);
  if (!isAcceptedName(o.device)) return reportError("bless: --device '" + o.device + "' is not a device name");

  std::set<std::string> devices;
  std::vector<nlohmann::json> cases;
  for (const auto& c : results.value("cases", nlohmann::json::array())) {
    if (!inFilter(o.filters.techniques, c.value("technique", "")) || !inFilter(o.filters.scenes, c.value("scene", "")) ||
        !inFilter(o.filters.platforms, c.value("platform", "")) || c.value("technique", "") == kScriptTechnique)
      continue;
    const std::string device = c.value("device", c.value("backend", ""));
    devices.insert(device);
    if (device == o.device) cases.push_back(c);
  }
  if (cases.empty()) {
    std::string known;
    for (const std::string& d : devices) known += (known.empty() ? "" : ", ") + d;
    return reportError(o.from + ": device '" + o.device + "' is not a device of the run's cases" +
                       (known.empty() ? std::string(" (none match the filters)") : " (its devices: " + known + ")"));
  }

  struct Planned {
    std::string key, source, target;
    nlohmann::json entry;
  };
  std::vector<Planned> plan;
  int refused = 0;
  auto refuse = [&](const std::string& key, const std::string& why) {
    std::fprintf(stderr, "parity: bless: %s on %s refused: %s\n", key.c_str(), o.device.c_str(), why.c_str());
    ++refused;
  };
  for (const nlohmann::json& c : cases) {
    const std::string key = goldenKey(c["technique"], c["scene"], c["platform"]);
    if (!c.contains("image") || !c.value("deterministic", false)) {
      refuse(key, "the run holds no deterministic image of it");
      continue;
    }
    const std::string primary = goldenPath(goldenDir, c["technique"], c["scene"], c["platform"]);
    if (!fs::exists(primary)) {
      refuse(key, "no primary golden golden/" + key + ".png to measure it against (bless the reference device first)");
      continue;
    }
    const std::string source = (fs::path(o.from) / c["image"].get<std::string>()).string();
    nlohmann::json evidence;
    std::string why;
    if (!measureAgainstPrimary(primary, source, &evidence, &why)) {
      refuse(key, why);
      continue;
    }
    evidence["against"] = key + ".png";
    OIIO::ImageBuf img;
    if (!readImage(source, &img, &error)) return reportError(error);
    const std::string target = acceptedImagePath(goldenDir, key, o.device);
    nlohmann::json entry = {{"file", fs::relative(target, goldenDir).string()},
                            {"devices", {o.device}},
                            {"width", img.spec().width},
                            {"height", img.spec().height},
                            {"pixel_sha1", OIIO::ImageBufAlgo::computePixelHashSHA1(img)},
                            {"blessed", nowIso()},
                            {"reason", o.reason},
                            {"blessed_from",
                             {{"run", results.value("run_id", "")},
                              {"case", c.value("id", "")},
                              {"result", c.value("result", "")},
                              {"device", o.device},
                              {"renderer", c.value("renderer", "")},
                              {"driver", c.value("driver", "")},
                              {"api", c.value("api", "")},
                              {"project_commit", results.value("project_commit", "")},
                              {"rendered", results.value("started", "")}}},
                            {"evidence", evidence}};
    plan.push_back({key, source, target, entry});
  }
  // All or nothing, as for primary goldens.
  if (refused) return reportError(std::to_string(refused) + " accepted image(s) refused (see above); nothing written");
  if (!o.dryRun) removeStaleTemporaries(goldenDir, true);
  for (const Planned& p : plan) {
    const nlohmann::json& flip = p.entry["evidence"]["flip"];
    const nlohmann::json& diagnosis = p.entry["evidence"]["diagnosis"];
    std::printf("%s %s for %s: FLIP mean %.4g, p99 %.4g against golden/%s.png%s; reason: %s\n",
                o.dryRun ? "would accept" : "accepted", p.target.c_str(), o.device.c_str(), flip["mean"].get<double>(),
                flip["p99"].get<double>(), p.key.c_str(),
                diagnosis.is_object() ? ("; likely cause: " + diagnosis.value("cause", std::string())).c_str() : "",
                o.reason.c_str());
    if (o.dryRun) continue;
    // Image first, then the manifest: both replaced whole, never half-written.
    if (!copyFileAtomic(p.source, p.target, &error)) return reportError(error);
    manifest["accepted"][p.key][o.device] = p.entry;
  }
  if (!o.dryRun && !writeFileAtomic((fs::path(goldenDir) / "manifest.json").string(), manifest.dump(2) + "\n", &error))
    return reportError(error);
  return 0;
}

}  // namespace parity::harness
