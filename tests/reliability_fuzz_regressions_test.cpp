// Inputs the fuzzers in fuzz/ found (and hand-written hostile ones), replayed through the same
// entry points: tests/fuzz_regressions/<target>/<file>. Each must load or fail with a one-line
// message; an exception escaping or a crash fails the suite. Runs without clang or libFuzzer.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "harness/run/golden.h"
#include "harness/io/image_io.h"
#include "harness/scripts/script.h"
#include "scene/scene.h"

namespace fs = std::filesystem;
using namespace parity;

namespace {

fs::path regressionsDir() { return fs::path(PARITY_SOURCE_DIR) / "tests" / "fuzz_regressions"; }

// Inputs whose fix lies outside the files this suite owns: skipped with the fix needed.
const std::map<std::string, std::string>& knownDefects() {
  static const std::map<std::string, std::string> known = {};
  return known;
}

struct Input {
  std::string target, file;
  fs::path path;
};

std::vector<Input> inputs() {
  std::vector<Input> list;
  std::error_code ec;
  if (!fs::is_directory(regressionsDir(), ec)) return list;
  for (const auto& t : fs::directory_iterator(regressionsDir()))
    if (t.is_directory())
      for (const auto& f : fs::directory_iterator(t.path()))
        if (f.is_regular_file())
          list.push_back({t.path().filename().string(), f.path().filename().string(), f.path()});
  std::sort(list.begin(), list.end(), [](const Input& a, const Input& b) { return a.path < b.path; });
  return list;
}

std::string readBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Copies the input into a private folder under the name the parser expects.
fs::path stage(const Input& in, const std::string& name, fs::path* dir) {
  *dir = fs::temp_directory_path() / ("parity-fuzz-regression-" + std::to_string(::getpid()));
  fs::remove_all(*dir);
  fs::create_directories(*dir);
  fs::copy_file(in.path, *dir / name);
  return *dir / name;
}

// Runs the input through its target's entry point; returns (ok, message).
std::pair<bool, std::string> replay(const Input& in) {
  std::string error;
  bool ok = false;
  fs::path dir;
  if (in.target == "scene_gltf" || in.target == "scene_obj") {
    fs::path file = stage(in, in.target == "scene_gltf" ? "input.gltf" : "input.obj", &dir);
    scene::SceneParams params;
    params.lightCount = 4;
    scene::Scene s;
    ok = scene::loadSceneFile(file.string(), params, &s, &error);
  } else if (in.target == "expectations") {
    fs::path file = stage(in, "input.json", &dir);
    std::vector<harness::Expectation> list;
    ok = harness::loadExpectations(file.string(), &list, &error);
  } else if (in.target == "tolerances") {
    fs::path file = stage(in, "input.json", &dir);
    harness::Tolerance t;
    ok = harness::loadTolerance(file.string(), harness::CaseKey{"forward", "default", "reference", "gl"}, &t, &error);
  } else if (in.target == "script") {
    harness::script::ParseResult r = harness::script::parseScript(readBytes(in.path), in.file);
    ok = r.ok;
    error = r.error;
  } else if (in.target == "image") {
    // As the fuzzer: the first byte picks the extension.
    std::string bytes = readBytes(in.path);
    static const char* const kExtensions[] = {".png", ".exr", ".hdr", ".tga"};
    std::string ext = bytes.empty() ? ".png" : kExtensions[static_cast<uint8_t>(bytes[0]) % 4];
    dir = fs::temp_directory_path() / ("parity-fuzz-regression-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ofstream(dir / ("input" + ext), std::ios::binary) << (bytes.empty() ? bytes : bytes.substr(1));
    OIIO::ImageBuf image;
    ok = harness::readImage((dir / ("input" + ext)).string(), &image, &error);
  } else {
    ADD_FAILURE() << "unknown fuzz target folder " << in.target;
  }
  if (!dir.empty()) fs::remove_all(dir);
  return {ok, error};
}

class FuzzRegression : public ::testing::TestWithParam<Input> {};

TEST_P(FuzzRegression, LoadsOrFailsWithOneLine) {
  const Input& in = GetParam();
  std::string key = in.target + "/" + in.file;
  auto known = knownDefects().find(key);
  std::pair<bool, std::string> r;
  try {
    r = replay(in);
  } catch (const std::exception& e) {
    if (known != knownDefects().end()) GTEST_SKIP() << known->second << " (observed: " << e.what() << ")";
    FAIL() << key << ": exception escaped: " << e.what();
  }
  if (!r.first) {
    EXPECT_FALSE(r.second.empty()) << key << " failed without a message";
    EXPECT_EQ(r.second.find('\n'), std::string::npos) << key << ": " << r.second;
  }
}

TEST(FuzzRegressions, EveryTargetHasInputs) {
  std::map<std::string, int> perTarget;
  for (const Input& in : inputs()) ++perTarget[in.target];
  for (const char* t : {"scene_gltf", "scene_obj", "expectations", "tolerances", "script", "image"})
    EXPECT_GT(perTarget[t], 0) << "tests/fuzz_regressions/" << t << " is empty";
}

std::string inputName(const ::testing::TestParamInfo<Input>& info) {
  std::string n = info.param.target + "_" + info.param.file;
  for (char& c : n)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return n;
}

INSTANTIATE_TEST_SUITE_P(Inputs, FuzzRegression, ::testing::ValuesIn(inputs()), inputName);

}  // namespace

namespace {

// The input CI's smaller machine was killed on: bounded before allocation, with the line named.
TEST(FuzzRegressions, HugeScriptBufferIsAParseErrorNotAnAllocation) {
  auto file = regressionsDir() / "script" / "huge-buffer-size.amber";
  harness::script::ParseResult r = harness::script::parseScript(readBytes(file), "huge-buffer-size.amber");
  ASSERT_FALSE(r.ok);
  EXPECT_NE(r.error.find("huge-buffer-size.amber:2:"), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("more than the 268435456 a script may allocate"), std::string::npos) << r.error;
}

TEST(FuzzRegressions, OversizedImageSideIsAParseError) {
  harness::script::ParseResult r = harness::script::parseScript(
      "#!amber\nIMAGE i FORMAT R8G8B8A8_UNORM WIDTH 70000 HEIGHT 70000\n", "big.amber");
  ASSERT_FALSE(r.ok);
  EXPECT_NE(r.error.find("big.amber:2:"), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("larger than the 16384"), std::string::npos) << r.error;
}

}  // namespace
