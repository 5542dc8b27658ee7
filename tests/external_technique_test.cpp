// parity used as a library by another project, as a studio would: examples/external-technique
// is configured against an installed prefix with find_package(parity) alone, builds its own
// technique into its own parity command, and passes `run` with goldens of its own. Its goldens'
// evidence (golden/evidence.json, recorded in golden/manifest.json) is this test: the reference
// image is deferred shading's G-buffer diffuse target.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/run/process.h"
#include "techniques/technique.h"
#include "test_support.h"

using namespace parity;
namespace fs = std::filesystem;

namespace {

TEST(ExternalTechnique, RegistrationRefusesNamesThatCannotNameGoldens) {
  auto make = [](std::string name) {
    return techniques::TechniqueEntry{name, "test", [] { return techniques::createTechnique("forward"); }};
  };
  EXPECT_THROW(techniques::registerTechnique(make("forward")), techniques::TechniqueError) << "already registered";
  EXPECT_THROW(techniques::registerTechnique(make("")), techniques::TechniqueError);
  EXPECT_THROW(techniques::registerTechnique(make("a/b")), techniques::TechniqueError);
  EXPECT_THROW(techniques::registerTechnique(techniques::TechniqueEntry{"no-create", "test", nullptr}),
               techniques::TechniqueError);
  const size_t before = techniques::techniqueRegistry().size();
  techniques::registerTechnique(make("forward-again"));
  ASSERT_EQ(techniques::techniqueRegistry().size(), before + 1);
  EXPECT_NE(techniques::createTechnique("forward-again"), nullptr);
}

TEST(ExternalTechnique, BuildsAgainstTheInstalledPackageAndPassesItsOwnGoldens) {
  if (!test::makeDevice("vk", false) || !test::makeDevice("gl", false)) return;
  const fs::path root = fs::temp_directory_path() / ("parity-external-" + std::to_string(::getpid()));
  fs::remove_all(root);
  const fs::path prefix = root / "prefix", build = root / "build";
  const fs::path example = fs::path(PARITY_SOURCE_DIR) / "examples" / "external-technique";
  auto cmake = [&](std::vector<std::string> args) {
    args.insert(args.begin(), PARITY_CMAKE_COMMAND);
    return harness::runProcess(args, 280);
  };
  harness::ProcessResult r = cmake({"--install", PARITY_BUILD_DIR, "--prefix", prefix.string()});
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  for (const char* f : {"lib/cmake/parity/parity-config.cmake", "lib/libparity_harness.a", "include/parity/rhi/rhi.h",
                        "include/parity/techniques/technique.h", "include/parity/harness/cli/cli.h"})
    EXPECT_TRUE(fs::exists(prefix / f)) << f;
  r = cmake({"-S", example.string(), "-B", build.string(), "-DCMAKE_PREFIX_PATH=" + prefix.string(),
             "-DCMAKE_BUILD_TYPE=RelWithDebInfo"});
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  r = cmake({"--build", build.string(), "-j2"});
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  // Compiled against the prefix's headers, not parity's source tree (the example's own folder is
  // in that tree here, so only the include folders and parity's definitions are looked at).
  const std::string flags = test::readFile(build / "CMakeFiles" / "albedo-parity.dir" / "flags.make");
  const size_t at = flags.find("CXX_INCLUDES");
  ASSERT_NE(at, std::string::npos) << flags;
  const std::string includes = flags.substr(at, flags.find('\n', at) - at);
  EXPECT_NE(includes.find((prefix / "include" / "parity").string()), std::string::npos) << includes;
  EXPECT_EQ(includes.find(PARITY_SOURCE_DIR), std::string::npos) << includes;
  EXPECT_EQ(flags.find("PARITY_SOURCE_DIR"), std::string::npos) << flags;

  // Another engine's technique that clears its light lists by compute and has no port path: on
  // ps3 its dispatch is E_CAP_COMPUTE, naming its pipeline, and `render` fails naming the
  // capability and writes nothing; on the reference it renders.
  const fs::path capsBuild = root / "build-caps";
  r = cmake({"-S", (fs::path(PARITY_SOURCE_DIR) / "examples" / "console-capabilities").string(), "-B", capsBuild.string(),
             "-DCMAKE_PREFIX_PATH=" + prefix.string(), "-DCMAKE_BUILD_TYPE=RelWithDebInfo"});
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  r = cmake({"--build", capsBuild.string(), "-j2"});
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  const std::string lists = (capsBuild / "lists-parity").string();
  const fs::path listsImage = root / "lists.png";
  r = harness::runProcess({lists, "render", "-t", "compute-lists", "-p", "ps3", "-b", "vk", "-o", listsImage.string()}, 120);
  EXPECT_NE(r.exitCode, 0) << r.err;
  EXPECT_NE(r.err.find("E_CAP_COMPUTE"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("clear light lists"), std::string::npos) << "the error names the pipeline: " << r.err;
  EXPECT_NE(r.err.find("compute-lists cannot run on ps3"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("capability"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(listsImage)) << "an image of what ps3 cannot run was written";
  r = harness::runProcess({lists, "render", "-t", "compute-lists", "-p", "reference", "-b", "vk", "-o", listsImage.string()},
                          120);
  EXPECT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(r.err.find("E_CAP_"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(listsImage));

  const std::string tool = (build / "albedo-parity").string();
  ::unsetenv("PARITY_SHADER_DIR");
  ::unsetenv("PARITY_DATA_DIR");
  const fs::path cwd = fs::current_path();
  fs::create_directories(root / "work");
  fs::current_path(root / "work");
  auto run = [&](std::vector<std::string> args) {
    args.insert(args.begin(), tool);
    return harness::runProcess(args, 280);
  };
  r = run({"list"});
  EXPECT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("unlit-albedo"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("deferred"), std::string::npos) << "the project's own techniques stay: " << r.out;

  const std::string goldens = (example / "golden").string();
  r = run({"run", "--technique", "unlit-albedo", "--golden", goldens, "--out", "run", "--no-progress",
           "--require-backends", "gl,vk"});
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
  ASSERT_TRUE(fs::exists("run/results.json")) << r.out << r.err;
  nlohmann::json results = nlohmann::json::parse(test::readFile("run/results.json"));
  std::map<std::string, int> byResult;
  for (const auto& c : results["cases"]) ++byResult[c["result"].get<std::string>()];
  // Four platforms x two backends, every one passing: the platform rules find nothing in it.
  EXPECT_EQ(byResult["Pass"], 8) << r.out;

  // The evidence the manifest records for the reference golden: deferred shading's geometry
  // pass stores the same diffuse colour (within the 8-bit target's rounding).
  r = run({"render", "--technique", "unlit-albedo", "--backend", "vk", "-o", "albedo.png"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  r = harness::runProcess({PARITY_BINARY, "render", "--technique", "deferred", "--backend", "vk", "--passes", "passes",
                           "-o", "deferred.png"}, 120);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  r = harness::runProcess({PARITY_BINARY, "diff", "passes/gbuffer.diffuse.exr", "albedo.png", "--fail", "0.004",
                           "--warn", "0.004"}, 60);
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
  // The manifest names this test as the reference golden's evidence (golden/evidence.json), and
  // the consoles' goldens the reference golden within their bounds.
  const nlohmann::json manifest = nlohmann::json::parse(test::readFile(example / "golden" / "manifest.json"));
  const nlohmann::json& evidence = manifest["goldens"]["unlit-albedo/default/reference"]["evidence"];
  ASSERT_TRUE(evidence.is_array() && evidence.size() == 1) << evidence.dump();
  EXPECT_EQ(evidence[0]["tests"][0],
            "tests/external_technique_test.cpp: ExternalTechnique.BuildsAgainstTheInstalledPackageAndPassesItsOwnGoldens");
  EXPECT_NE(evidence[0].value("why", "").find("gbuffer.diffuse"), std::string::npos);
  for (const char* console : {"ps3", "dx10", "x360"})
    EXPECT_EQ(manifest["goldens"][std::string("unlit-albedo/default/") + console]["evidence"][0]["reference"],
              "unlit-albedo/default/reference")
        << console;

  // The program uses the installed package's shaders (parity's vertex shader, planted here) and
  // its run fails on the difference.
  const fs::path vert = prefix / "share/parity/shaders/forward/forward.vert";
  std::string text = test::readFile(vert);
  const size_t end = text.rfind('}');
  ASSERT_NE(end, std::string::npos);
  text.insert(end, "  gl_Position.x += 0.05 * gl_Position.w;\n");
  std::ofstream(vert, std::ios::binary | std::ios::trunc) << text;
  r = run({"run", "--technique", "unlit-albedo", "--platform", "reference", "--golden", goldens, "--out", "planted",
           "--no-progress"});
  EXPECT_NE(r.exitCode, 0) << r.out;
  EXPECT_NE(r.out.find("differs from golden"), std::string::npos) << r.out;
  fs::current_path(cwd);
  fs::remove_all(root);
}

}  // namespace
