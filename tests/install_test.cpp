// `cmake --install` as a user runs it: the prefix holds bin/parity and share/parity (shaders,
// goldens, the script library), and an installed parity uses that data, wherever the prefix is
// moved, from any working folder: a shader planted in the installed copy changes the installed
// parity's render and not the build tree's.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "harness/run/process.h"
#include "test_support.h"

using namespace parity;
namespace fs = std::filesystem;

namespace {

TEST(Install, AnInstalledParityRunsFromItsPrefixWhereverItIs) {
  if (!test::makeDevice("vk", false)) return;
  const fs::path root = fs::temp_directory_path() / ("parity-install-" + std::to_string(::getpid()));
  fs::remove_all(root);
  harness::ProcessResult r =
      harness::runProcess({PARITY_CMAKE_COMMAND, "--install", PARITY_BUILD_DIR, "--prefix", (root / "first").string()}, 300);
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  for (const char* f : {"bin/parity", "share/parity/shaders/platforms/platform.glsl", "share/parity/golden/manifest.json",
                        "share/parity/tests/scripts"})
    EXPECT_TRUE(fs::exists(root / "first" / f)) << f;
  // Moved: the data is found beside the executable, not where it was installed.
  fs::rename(root / "first", root / "moved");
  const fs::path prefix = root / "moved";
  const std::string parity = (prefix / "bin" / "parity").string();
  // Run from a folder of its own with no variable pointing anywhere.
  ::unsetenv("PARITY_SHADER_DIR");
  ::unsetenv("PARITY_DATA_DIR");
  const fs::path cwd = fs::current_path();
  fs::create_directories(root / "work");
  fs::current_path(root / "work");
  auto run = [&](std::vector<std::string> args, double timeout = 300) {
    args.insert(args.begin(), parity);
    return harness::runProcess(args, timeout);
  };
  r = run({"list"});
  EXPECT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("deferred"), std::string::npos) << r.out;
  r = run({"run", "--technique", "forward", "--backend", "vk", "--platform", "reference", "--out", "run", "--no-progress",
           "--scripts", (prefix / "share/parity/tests/scripts/clear.amber").string()});
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("Pass"), std::string::npos) << r.out;
  // compared with the installed goldens
  EXPECT_NE(test::readFile("run/results.json").find((prefix / "share/parity/golden").string()), std::string::npos);
  r = run({"test", (prefix / "share/parity/tests/scripts/clear.amber").string(), "--backend", "vk"});
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
  // A shader planted in the installed copy: the installed parity's render changes, the build's
  // does not.
  const fs::path compose = prefix / "share/parity/shaders/deferred/compose.frag";
  std::string text = test::readFile(compose);
  const size_t end = text.rfind('}');
  ASSERT_NE(end, std::string::npos);
  text.insert(end, "  outColor.rgb = vec3(1.0, 0.0, 1.0);\n");
  std::ofstream(compose, std::ios::binary | std::ios::trunc) << text;
  r = run({"render", "--backend", "vk", "--technique", "deferred", "-o", "installed.png"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  r = harness::runProcess({PARITY_BINARY, "render", "--backend", "vk", "--technique", "deferred", "-o", "built.png"}, 120);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(test::readFile("installed.png"), test::readFile("built.png")) << "the installed parity read the source tree's shaders";
  fs::current_path(cwd);
  fs::remove_all(root);
}

}  // namespace
