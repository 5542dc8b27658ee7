// `cpack -G DEB` as a packager runs it: two Debian packages with their dependencies declared, and
// the runtime one, unpacked anywhere, is a working parity (its data found beside the executable).
// Installing it with apt on a fresh Debian 12 is shown by scripts/package-check.sh.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "harness/run/process.h"
#include "test_support.h"

using namespace parity;
namespace fs = std::filesystem;

namespace {

TEST(Package, DebianPackagesDeclareTheirDependenciesAndTheCommandRunsUnpacked) {
  if (!test::makeDevice("vk", false)) return;
  const fs::path root = fs::temp_directory_path() / ("parity-package-" + std::to_string(::getpid()));
  fs::remove_all(root);
  harness::ProcessResult r = harness::runProcess(
      {(fs::path(PARITY_CMAKE_COMMAND).parent_path() / "cpack").string(), "-G", "DEB", "--config", (fs::path(PARITY_BUILD_DIR) / "CPackConfig.cmake").string(), "-B",
       (root / "debs").string()},
      280);
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  fs::path runtime, development;
  for (const auto& e : fs::directory_iterator(root / "debs")) {
    const std::string name = e.path().filename().string();
    if (name.rfind("parity_", 0) == 0 && e.path().extension() == ".deb") runtime = e.path();
    if (name.rfind("parity-dev_", 0) == 0 && e.path().extension() == ".deb") development = e.path();
  }
  ASSERT_FALSE(runtime.empty()) << r.out;
  ASSERT_FALSE(development.empty()) << r.out;
  auto field = [](const fs::path& deb, const char* name) {
    return harness::runProcess({harness::findInPath("dpkg-deb"), "-f", deb.string(), name}, 60).out;
  };
  const std::string depends = field(runtime, "Depends");
  // The drivers it renders with, and the shared libraries dpkg-shlibdeps found.
  for (const char* p : {"mesa-vulkan-drivers", "libgl1-mesa-dri", "libvulkan1", "libopenimageio", "libegl1"})
    EXPECT_NE(depends.find(p), std::string::npos) << p << " in " << depends;
  const std::string devDepends = field(development, "Depends");
  for (const char* p : {"parity (= ", "glslang-dev", "libglm-dev", "libopenimageio-dev", "nlohmann-json3-dev"})
    EXPECT_NE(devDepends.find(p), std::string::npos) << p << " in " << devDepends;

  r = harness::runProcess({harness::findInPath("dpkg-deb"), "-x", runtime.string(), (root / "unpacked").string()}, 120);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(fs::exists(root / "unpacked/usr/share/parity/shaders/platforms/platform.glsl"));
  EXPECT_FALSE(fs::exists(root / "unpacked/usr/include")) << "headers belong to parity-dev";
  r = harness::runProcess({harness::findInPath("dpkg-deb"), "-c", development.string()}, 60);
  EXPECT_NE(r.out.find("./usr/lib/cmake/parity/parity-config.cmake"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("./usr/include/parity/techniques/technique.h"), std::string::npos);

  ::unsetenv("PARITY_SHADER_DIR");
  ::unsetenv("PARITY_DATA_DIR");
  const std::string parity = (root / "unpacked/usr/bin/parity").string();
  const std::string out = (root / "run").string();
  r = harness::runProcess({parity, "run", "--technique", "forward", "--backend", "vk", "--platform", "reference", "--out",
                           out, "--no-progress", "--scripts",
                           (root / "unpacked/usr/share/parity/tests/scripts/clear.amber").string()},
                          280);
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("Pass"), std::string::npos) << r.out;
  fs::remove_all(root);
}

}  // namespace
