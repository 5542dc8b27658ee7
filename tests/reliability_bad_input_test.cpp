// Bad input to the `parity` command, one test per case: malformed scenes, expectations and
// tolerances, unknown names, shader and script errors, broken goldens, unwritable outputs, absurd
// sizes, missing drivers. The rule each case checks: a non-zero exit, one line on stderr naming
// the file (or value) and the reason, nothing left behind, never a crash. Cases about a single
// render case inside `parity run` (a broken golden, a missing driver) check the case's result
// instead: Fail or Skip with the reason, the run itself intact.
//
// A case whose defect lies in a file this suite does not own carries `knownDefect`: the fix
// needed. While the defect is present the case is skipped with that text; once fixed it passes.
#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "harness/run/process.h"

namespace fs = std::filesystem;
using namespace parity;

namespace {

enum class Expect {
  Error,     // exit != 0, one line on stderr naming `mentions`, no output
  CaseFail,  // `parity run`: exit != 0, the case is Fail with a reason naming `mentions`
  CaseSkip,  // `parity run`: the case is Skip with a reason naming `mentions`, no crash
  TestFail,  // `parity test`: exit != 0, the script's line names `mentions`, no crash
  DiskFull,  // writes fail midway: exit != 0, a one-line error, no truncated report, no temporary file
};

struct Invocation {
  std::vector<std::string> args;
  std::map<std::string, std::string> env;  // set for the child only
  std::vector<std::string> mentions;       // all must appear in the message
  std::vector<fs::path> mustNotExist;      // partial output that must not be there
  Expect expect = Expect::Error;
  long fileSizeLimitKb = 0;                // > 0: writes past this size fail (EFBIG), as on a full disk
};

struct BadInput {
  std::string name;
  std::function<Invocation(const fs::path& dir)> setup;
  std::string knownDefect;  // the fix needed in a file outside this suite; empty: none known
};

void writeText(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary) << text;
}

std::string readText(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

fs::path sourceGoldens() { return fs::path(PARITY_SOURCE_DIR) / "golden"; }

// A copy of the project's goldens to break one of them.
fs::path copyGoldens(const fs::path& dir) {
  fs::path g = dir / "golden";
  fs::copy(sourceGoldens(), g, fs::copy_options::recursive);
  return g;
}
const char* kCase = "forward/default/reference/gl";
fs::path goldenOf(const fs::path& g) { return g / "forward" / "default" / "reference.png"; }

// `parity render` of a scene file, which must fail before writing the image.
Invocation renderScene(const fs::path& dir, const fs::path& scene, std::vector<std::string> mentions) {
  fs::path out = dir / "out.png";
  return {{"render", "--backend", "gl", "--scene", scene.string(), "--size", "32x18", "-o", out.string()},
          {},
          std::move(mentions),
          {out}};
}

// `parity run` of one case with a run option pointing at a file; the run must refuse to start.
Invocation runWith(const fs::path& dir, const std::string& option, const fs::path& file,
                   std::vector<std::string> mentions) {
  fs::path out = dir / "run";
  return {{"run", "--case", kCase, "--size", "32x18", "--jobs", "1", "--retries", "0", option, file.string(), "--out",
           out.string(), "--no-progress"},
          {},
          std::move(mentions),
          {out}};
}

// `parity merge` of one hand-written shard (DIR/shard/results.json); the merge must refuse it
// before creating its output folder.
Invocation mergeOf(const fs::path& dir, std::vector<std::string> mentions) {
  fs::path out = dir / "merged";
  return {{"merge", (dir / "shard").string(), "--out", out.string()}, {}, std::move(mentions), {out}};
}

// `parity run` of one case against a golden folder (the case itself must fail or skip).
Invocation runAgainst(const fs::path& dir, const fs::path& golden, const char* caseId, Expect expect,
                      std::vector<std::string> mentions) {
  return {{"run", "--case", caseId, "--jobs", "1", "--retries", "0", "--golden", golden.string(), "--out",
           (dir / "run").string(), "--no-progress"},
          {},
          std::move(mentions),
          {},
          expect};
}

const char* kMinimalGltfHead = R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],)";

// A triangle whose one buffer has the given URI and declared length.
std::string gltfWithBuffer(const std::string& uri, size_t byteLength, size_t count = 3) {
  return std::string(kMinimalGltfHead) + R"( "accessors": [{"bufferView": 0, "componentType": 5126, "count": )" +
         std::to_string(count) + R"(, "type": "VEC3"}], "bufferViews": [{"buffer": 0, "byteLength": )" +
         std::to_string(byteLength) + R"(}], "buffers": [{"uri": ")" + uri + R"(", "byteLength": )" +
         std::to_string(byteLength) + "}]}";
}

// 36 bytes: three float3 positions.
std::string triangleBytes() {
  const float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  return std::string(reinterpret_cast<const char*>(p), sizeof p);
}

std::string scriptHead(const std::string& format, const std::string& fbSize, const std::string& fragmentBody) {
  return "#!amber\nSHADER vertex vs PASSTHROUGH\nSHADER fragment fs GLSL\n#version 450\n"
         "layout(location = 0) out vec4 color_out;\nvoid main() { " +
         fragmentBody + " }\nEND\nBUFFER framebuffer FORMAT " + format +
         "\nPIPELINE graphics pipeline\n  ATTACH vs\n  ATTACH fs\n  FRAMEBUFFER_SIZE " + fbSize +
         "\n  BIND BUFFER framebuffer AS color LOCATION 0\nEND\nCLEAR pipeline\n"
         "EXPECT framebuffer IDX 0 0 SIZE 1 1 EQ_RGBA 0 0 0 0\n";
}

Invocation testScript(const fs::path& dir, const std::string& text, std::vector<std::string> mentions) {
  fs::path file = dir / "bad.amber";
  writeText(file, text);
  return {{"test", file.string(), "--backend", "gl"}, {}, std::move(mentions), {}, Expect::TestFail};
}

// A 4-channel float image of the golden's size with one NaN and one Inf texel.
void writeNanExr(const fs::path& path) {
  OIIO::ImageSpec spec(320, 180, 4, OIIO::TypeDesc::FLOAT);
  OIIO::ImageBuf img(spec);
  OIIO::ImageBufAlgo::fill(img, {0.5f, 0.5f, 0.5f, 1.0f});
  float nan[4] = {NAN, 0, 0, 1}, inf[4] = {INFINITY, 0, 0, 1};
  img.setpixel(3, 4, nan);
  img.setpixel(5, 6, inf);
  ASSERT_TRUE(img.write(path.string()));
}

const std::vector<BadInput>& catalogue() {
  static const std::vector<BadInput> cases = {
      // ---- scene files ----
      {"GltfSyntaxError",
       [](const fs::path& d) {
         writeText(d / "s.gltf", R"({"asset": {"version": "2.0"}, "nodes": [)");
         return renderScene(d, d / "s.gltf", {"s.gltf"});
       }},
      {"GltfWrongType",
       [](const fs::path& d) {
         writeText(d / "s.gltf", std::string(kMinimalGltfHead) + R"( "accessors": "three"})");
         return renderScene(d, d / "s.gltf", {"s.gltf"});
       }},
      {"GltfMissingBuffer",
       [](const fs::path& d) {
         writeText(d / "s.gltf", gltfWithBuffer("absent.bin", 36));
         return renderScene(d, d / "s.gltf", {"s.gltf", "absent.bin"});
       }},
      {"GltfTruncatedBuffer",
       [](const fs::path& d) {
         writeText(d / "s.gltf", gltfWithBuffer("short.bin", 36));
         writeText(d / "short.bin", triangleBytes().substr(0, 20));
         return renderScene(d, d / "s.gltf", {"s.gltf"});
       }},
      {"GltfTruncatedJson",
       [](const fs::path& d) {
         std::string full = gltfWithBuffer("tri.bin", 36);
         writeText(d / "tri.bin", triangleBytes());
         writeText(d / "s.gltf", full.substr(0, full.size() / 2));
         return renderScene(d, d / "s.gltf", {"s.gltf"});
       }},
      {"GltfMissingTexture",
       [](const fs::path& d) {
         writeText(d / "tri.bin", triangleBytes());
         std::string text = gltfWithBuffer("tri.bin", 36);
         text.pop_back();
         text += R"(, "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
                    "textures": [{"source": 0}], "images": [{"uri": "absent.png"}]})";
         // the primitive uses material 0
         text.replace(text.find(R"({"attributes")"), 1, R"({"material": 0, )");
         writeText(d / "s.gltf", text);
         return renderScene(d, d / "s.gltf", {"s.gltf", "absent.png"});
       }},
      {"GltfHugeAccessorCount",
       [](const fs::path& d) {
         writeText(d / "tri.bin", triangleBytes());
         writeText(d / "s.gltf", gltfWithBuffer("tri.bin", 36, 4000000000ull));
         return renderScene(d, d / "s.gltf", {"s.gltf", "4000000000"});
       }},
      {"GltfNegativeCount",
       [](const fs::path& d) {
         writeText(d / "tri.bin", triangleBytes());
         std::string text = gltfWithBuffer("tri.bin", 36);
         text.replace(text.find("\"count\": 3"), 10, "\"count\": -3");
         writeText(d / "s.gltf", text);
         return renderScene(d, d / "s.gltf", {"s.gltf"});
       }},
      {"GlbTruncated",
       [](const fs::path& d) {
         writeText(d / "s.glb", std::string("glTF\x02\0\0\0\xff\0\0\0", 12));
         return renderScene(d, d / "s.glb", {"s.glb"});
       }},
      {"ObjTruncatedFace",
       [](const fs::path& d) {
         writeText(d / "s.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\n");
         return renderScene(d, d / "s.obj", {"s.obj", "missing vertex"});
       }},
      {"ObjNoTriangles",
       [](const fs::path& d) {
         writeText(d / "s.obj", "# nothing\nv 0 0 0\n");
         return renderScene(d, d / "s.obj", {"s.obj", "no triangles"});
       }},
      {"ObjMissingTexture",
       [](const fs::path& d) {
         writeText(d / "s.mtl", "newmtl m\nKd 1 1 1\nmap_Kd absent.png\n");
         writeText(d / "s.obj", "mtllib s.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n");
         return renderScene(d, d / "s.obj", {"s.obj", "absent.png"});
       }},
      {"ObjTextureNotAnImage",
       [](const fs::path& d) {
         writeText(d / "t.png", "this is not a png");
         writeText(d / "s.mtl", "newmtl m\nKd 1 1 1\nmap_Kd t.png\n");
         writeText(d / "s.obj", "mtllib s.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n");
         return renderScene(d, d / "s.obj", {"s.obj", "t.png"});
       }},
      {"SceneFileOfUnknownType",
       [](const fs::path& d) {
         writeText(d / "s.fbx", "Kaydara FBX Binary");
         return renderScene(d, d / "s.fbx", {"s.fbx", ".fbx"});
       }},
      {"SceneFileAbsent", [](const fs::path& d) { return renderScene(d, d / "absent.gltf", {"absent.gltf"}); }},
      {"SceneAskingForTooManyLights",
       [](const fs::path& d) {
         Invocation i = renderScene(d, "default", {"1000000000", "lights"});
         i.args.insert(i.args.end(), {"--lights", "1000000000"});
         return i;
       }},

      // ---- unknown names: the message suggests the nearest ----
      {"UnknownTechnique",
       [](const fs::path& d) {
         return Invocation{{"render", "--backend", "gl", "--technique", "forwrd", "-o", (d / "o.png").string()},
                           {},
                           {"forwrd", "'forward'"},
                           {d / "o.png"}};
       }},
      {"UnknownBackend",
       [](const fs::path& d) {
         return Invocation{
             {"render", "--backend", "vkk", "-o", (d / "o.png").string()}, {}, {"vkk", "vk"}, {d / "o.png"}};
       }},
      {"UnknownPlatform",
       [](const fs::path& d) {
         return Invocation{{"render", "--backend", "gl", "--platform", "ps33", "-o", (d / "o.png").string()},
                           {},
                           {"ps33", "ps3"},
                           {d / "o.png"}};
       }},
      {"UnknownSceneSuggestsTheNearest",
       [](const fs::path& d) {
         return Invocation{{"render", "--backend", "gl", "--scene", "defualt", "-o", (d / "o.png").string()},
                           {},
                           {"defualt", "did you mean 'default'"},
                           {d / "o.png"}};
       }},
      {"RunUnknownTechnique",
       [](const fs::path& d) {
         return Invocation{
             {"run", "--technique", "forwrd", "--out", (d / "run").string()}, {}, {"forwrd", "forward"}, {d / "run"}};
       }},
      {"RunUnknownCaseId",
       [](const fs::path& d) {
         return Invocation{{"run", "--case", "forward/default/reference/metal", "--out", (d / "run").string()},
                           {},
                           {"metal"},
                           {d / "run"}};
       }},

      // ---- sizes ----
      {"SizeZero",
       [](const fs::path& d) {
         return Invocation{
             {"render", "--backend", "gl", "--size", "0x0", "-o", (d / "o.png").string()}, {}, {"0x0"}, {d / "o.png"}};
       }},
      {"SizeNegative",
       [](const fs::path& d) {
         return Invocation{{"render", "--backend", "gl", "--size", "-5x10", "-o", (d / "o.png").string()},
                           {},
                           {"-5x10", "not WIDTHxHEIGHT"},
                           {d / "o.png"}};
       }},
      {"SizeAbsurd",
       [](const fs::path& d) {
         return Invocation{{"render", "--backend", "gl", "--size", "65536x65536", "-o", (d / "o.png").string()},
                           {},
                           {"65536x65536"},
                           {d / "o.png"}};
       }},
      {"RunSizeAbsurd",
       [](const fs::path& d) {
         return Invocation{{"run", "--case", kCase, "--size", "100000x1", "--out", (d / "run").string()},
                           {},
                           {"100000x1"},
                           {d / "run"}};
       }},

      // ---- expectations and tolerances: refused before anything runs ----
      {"ExpectationsSyntaxError",
       [](const fs::path& d) {
         writeText(d / "e.json", R"({"expectations": [)");
         return runWith(d, "--expectations", d / "e.json", {"e.json"});
       }},
      {"ExpectationsWrongType",
       [](const fs::path& d) {
         writeText(d / "e.json", R"({"expectations": [{"case": 5, "result": "Fail", "reason": "r"}]})");
         return runWith(d, "--expectations", d / "e.json", {"e.json"});
       }},
      {"ExpectationsMissingReason",
       [](const fs::path& d) {
         writeText(d / "e.json", R"({"expectations": [{"case": "*", "result": "Fail"}]})");
         return runWith(d, "--expectations", d / "e.json", {"e.json", "reason"});
       }},
      {"ExpectationsUnknownResult",
       [](const fs::path& d) {
         writeText(d / "e.json", R"({"expectations": [{"case": "*", "result": "Maybe", "reason": "r"}]})");
         return runWith(d, "--expectations", d / "e.json", {"e.json", "Maybe"});
       }},
      {"ExpectationsUnknownKey",
       [](const fs::path& d) {
         writeText(d / "e.json", R"({"expectations": [{"case": "*", "result": "Fail", "reason": "r", "reslut": "Crash"}]})");
         return runWith(d, "--expectations", d / "e.json", {"e.json", "reslut"});
       }},
      {"TolerancesTargetWithoutReason",
       [](const fs::path& d) {
         writeText(d / "t.json", R"({"targets": {"*": {"gbuffer.*": {"attachment_fail_percent": 5}}}})");
         return runWith(d, "--tolerances", d / "t.json", {"t.json", "gbuffer.*", "reason"});
       }},
      {"TolerancesSyntaxError",
       [](const fs::path& d) {
         writeText(d / "t.json", R"({"default": )");
         return runWith(d, "--tolerances", d / "t.json", {"t.json"});
       }},
      {"TolerancesWrongType",
       [](const fs::path& d) {
         writeText(d / "t.json", R"({"default": {"golden_fail": "small"}})");
         return runWith(d, "--tolerances", d / "t.json", {"t.json"});
       }},
      {"TolerancesHugeNumber",
       [](const fs::path& d) {
         writeText(d / "t.json", R"({"default": {"golden_fail": 1e400}})");
         return runWith(d, "--tolerances", d / "t.json", {"t.json"});
       }},
      {"TolerancesNegative",
       [](const fs::path& d) {
         writeText(d / "t.json", R"({"default": {"golden_fail": -0.5}})");
         return runWith(d, "--tolerances", d / "t.json", {"t.json", "golden_fail"});
       }},
      {"TolerancesUnknownKey",
       [](const fs::path& d) {
         writeText(d / "t.json", R"({"default": {"golden_fial": 0.1}})");
         return runWith(d, "--tolerances", d / "t.json", {"t.json", "golden_fial"});
       }},

      // ---- merge: results.json files from elsewhere ----
      {"MergeNonNumberTiming",
       [](const fs::path& d) {
         writeText(d / "shard" / "results.json",
                   R"({"cases": [{"id": "forward/default/reference/gl", "result": "Pass"}], "timing": {"wall_s": "fast"}})");
         return mergeOf(d, {"results.json", "wall_s"});
       }},
      {"MergeNonNumberRenderTime",
       [](const fs::path& d) {
         writeText(d / "shard" / "results.json",
                   R"({"cases": [{"id": "forward/default/reference/gl", "result": "Pass", "render_ms": [12.5, "slow"]}]})");
         return mergeOf(d, {"results.json", "render_ms"});
       }},
      {"MergeNonNumberGoldenMetric",
       [](const fs::path& d) {
         writeText(d / "shard" / "results.json",
                   R"({"cases": [{"id": "forward/default/reference/gl", "result": "Fail",
                                  "golden": {"metrics": {"max_error": {"value": 1}}}}]})");
         return mergeOf(d, {"results.json", "max_error"});
       }},
      {"MergeCaseWithoutId",
       [](const fs::path& d) {
         writeText(d / "shard" / "results.json", R"({"cases": [{"result": "Pass"}]})");
         return mergeOf(d, {"results.json", "id"});
       }},

      // ---- the golden manifest: refused whole before anything runs (provenance is not lost) ----
      {"ManifestTruncated",
       [](const fs::path& d) {
         fs::path g = copyGoldens(d);
         const std::string text = readText(g / "manifest.json");
         writeText(g / "manifest.json", text.substr(0, text.size() / 2));
         Invocation i = runAgainst(d, g, kCase, Expect::Error, {"manifest.json"});
         i.mustNotExist = {d / "run"};
         return i;
       }},
      {"ManifestWrongShape",
       [](const fs::path& d) {
         fs::path g = copyGoldens(d);
         writeText(g / "manifest.json", R"({"goldens": ["forward/default/reference"]})");
         Invocation i = runAgainst(d, g, kCase, Expect::Error, {"manifest.json", "goldens"});
         i.mustNotExist = {d / "run"};
         return i;
       }},

      // ---- goldens: the case fails with the golden named, the run completes ----
      {"GoldenMissing",
       [](const fs::path& d) {
         fs::path g = copyGoldens(d);
         fs::remove(goldenOf(g));
         return runAgainst(d, g, kCase, Expect::CaseFail, {"reference.png", "bless"});
       }},
      {"GoldenTruncated",
       [](const fs::path& d) {
         fs::path g = copyGoldens(d);
         std::string bytes = readText(goldenOf(g));
         writeText(goldenOf(g), bytes.substr(0, bytes.size() / 3));
         return runAgainst(d, g, kCase, Expect::CaseFail, {"reference.png"});
       }},
      {"GoldenNotAnImage",
       [](const fs::path& d) {
         fs::path g = copyGoldens(d);
         writeText(goldenOf(g), "<html>not an image</html>");
         return runAgainst(d, g, kCase, Expect::CaseFail, {"reference.png"});
       }},
      {"GoldenWrongSize",
       [](const fs::path& d) {
         fs::path g = copyGoldens(d);
         OIIO::ImageBuf small(OIIO::ImageSpec(100, 50, 4, OIIO::TypeDesc::UINT8));
         EXPECT_TRUE(small.write(goldenOf(g).string()));
         return runAgainst(d, g, kCase, Expect::CaseFail, {"reference.png"});
       }},
      {"GoldenWrongChannelCount",
       [](const fs::path& d) {
         fs::path g = copyGoldens(d);
         OIIO::ImageBuf golden(goldenOf(sourceGoldens()).string());
         OIIO::ImageBuf rgb = OIIO::ImageBufAlgo::channels(golden, 3, {});
         EXPECT_TRUE(rgb.write(goldenOf(g).string()));
         return runAgainst(d, g, kCase, Expect::CaseFail, {"reference.png"});
       }},
      {"DiffTruncatedPngPrintsOneLine",
       [](const fs::path& d) {
         std::string bytes = readText(goldenOf(sourceGoldens()));
         writeText(d / "cut.png", bytes.substr(0, bytes.size() / 3));
         return Invocation{{"diff", goldenOf(sourceGoldens()).string(), (d / "cut.png").string()}, {}, {"cut.png"}};
       }},
      {"DiffNanAndInf",
       [](const fs::path& d) {
         OIIO::ImageBuf golden(goldenOf(sourceGoldens()).string());
         golden.read(0, 0, true, OIIO::TypeDesc::FLOAT);
         EXPECT_TRUE(golden.write((d / "a.exr").string()));
         writeNanExr(d / "b.exr");
         return Invocation{{"diff", (d / "a.exr").string(), (d / "b.exr").string()}, {}, {"b.exr"}};
       }},

      // ---- outputs that cannot be written ----
      {"RenderIntoAFileAsFolder",
       [](const fs::path& d) {
         writeText(d / "plain-file", "x");
         return Invocation{{"render", "--backend", "gl", "--size", "32x18", "-o", (d / "plain-file" / "o.png").string()},
                           {},
                           {"plain-file"}};
       }},
      {"DiskFillsUpWhileWritingTheReport",
       [](const fs::path& d) {
         // 2 KB per file: the case's small image fits, the golden copy and results.json do not.
         Invocation i{{"run", "--case", kCase, "--size", "32x18", "--jobs", "1", "--retries", "0", "--out",
                       (d / "run").string(), "--no-progress"},
                      {},
                      {},
                      {},
                      Expect::DiskFull};
         i.fileSizeLimitKb = 2;
         return i;
       }},
      {"RunOutIsAFile",
       [](const fs::path& d) {
         writeText(d / "plain-file", "x");
         return Invocation{{"run", "--case", kCase, "--size", "32x18", "--out", (d / "plain-file").string()},
                           {},
                           {"plain-file"}};
       }},

      // ---- shader-test scripts ----
      {"ScriptShaderCompileError",
       [](const fs::path& d) {
         return testScript(d, scriptHead("B8G8R8A8_UNORM", "16 16", "int x = ;"), {"bad.amber:6", "error"});
       }},
      {"ScriptSyntaxError",
       [](const fs::path& d) {
         std::string text = scriptHead("B8G8R8A8_UNORM", "16 16", "color_out = vec4(1);");
         text.replace(text.find("PIPELINE"), 8, "PIPELNE");
         return testScript(d, text, {"bad.amber:9:1", "PIPELNE"});
       }},
      {"ScriptHugeFramebuffer",
       [](const fs::path& d) {
         return testScript(d, scriptHead("R32G32B32A32_SFLOAT", "65536 65536", "color_out = vec4(1);"),
                           {"bad.amber", "65536"});
       }},
      {"ScriptHugeBuffer",
       [](const fs::path& d) {
         return testScript(d, "#!amber\nBUFFER b DATA_TYPE float SIZE 4000000000 FILL 0\n", {"bad.amber:2", "SIZE"});
       }},

      // ---- drivers missing: the backend is unavailable with the reason, its cases Skip ----
      {"NoVulkanIcdRunSkips",
       [](const fs::path& d) {
         Invocation i = runAgainst(d, sourceGoldens(), "forward/default/reference/vk", Expect::CaseSkip,
                                   {"unavailable"});
         i.env = {{"VK_DRIVER_FILES", "/nonexistent/icd.json"}, {"VK_ICD_FILENAMES", "/nonexistent/icd.json"}};
         return i;
       }},
      {"NoEglRunSkips",
       [](const fs::path& d) {
         Invocation i = runAgainst(d, sourceGoldens(), kCase, Expect::CaseSkip, {"unavailable"});
         i.env = {{"__EGL_VENDOR_LIBRARY_FILENAMES", "/nonexistent/egl_vendor.json"},
                  {"__EGL_VENDOR_LIBRARY_DIRS", "/nonexistent"}};
         return i;
       }},
      {"NoVulkanIcdRenderFails",
       [](const fs::path& d) {
         Invocation i{{"render", "--backend", "vk", "--size", "32x18", "-o", (d / "o.png").string()},
                      {{"VK_DRIVER_FILES", "/nonexistent/icd.json"}, {"VK_ICD_FILENAMES", "/nonexistent/icd.json"}},
                      {"vk", "unavailable"},
                      {d / "o.png"}};
         return i;
       }},
  };
  return cases;
}

harness::ProcessResult runParity(const Invocation& inv) {
  std::vector<std::string> argv = inv.args;
  argv.insert(argv.begin(), PARITY_BINARY);
  if (inv.fileSizeLimitKb > 0) {
    // RLIMIT_FSIZE with SIGXFSZ ignored (kept across exec): a write past the limit fails with
    // EFBIG, which the program sees as it would see a full disk.
    argv.insert(argv.begin(), {"/bin/bash", "-c",
                               "ulimit -f " + std::to_string(inv.fileSizeLimitKb) + "; trap '' XFSZ; exec \"$@\"",
                               "bash"});
  }
  // The child inherits the environment: set the variables around the call only.
  std::map<std::string, std::optional<std::string>> saved;
  for (const auto& [k, v] : inv.env) {
    const char* old = std::getenv(k.c_str());
    saved[k] = old ? std::optional<std::string>(old) : std::nullopt;
    setenv(k.c_str(), v.c_str(), 1);
  }
  // The run's own backend requirement is the test suite's business, not the child's.
  harness::ProcessResult r = harness::runProcess(argv, 240);
  for (const auto& [k, v] : saved) {
    if (v) setenv(k.c_str(), v->c_str(), 1);
    else unsetenv(k.c_str());
  }
  return r;
}

class BadInputTest : public ::testing::TestWithParam<size_t> {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("parity-bad-input-" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

// Collects the failures of one case, so that a known defect can turn them into a skip.
struct Problems {
  std::vector<std::string> list;
  void check(bool ok, const std::string& what) {
    if (!ok) list.push_back(what);
  }
};

nlohmann::json findCase(const fs::path& runDir, const std::string& id) {
  std::ifstream in(runDir / "results.json");
  if (!in) return {};
  nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded() || !j.contains("cases")) return {};
  for (const auto& c : j["cases"])
    if (c.value("id", "") == id || c.value("case", "") == id) return c;
  return {};
}

TEST_P(BadInputTest, FailsCleanly) {
  const BadInput& c = catalogue()[GetParam()];
  Invocation inv = c.setup(dir_);
  ASSERT_FALSE(HasFailure()) << "set-up of " << c.name;
  harness::ProcessResult r = runParity(inv);
  std::string joined;
  for (const auto& a : inv.args) joined += a + " ";
  std::string context = joined + "\nstdout: " + r.out.substr(0, 2000) + "\nstderr: " + r.err.substr(0, 2000);

  Problems p;
  p.check(r.startError.empty(), "could not start: " + r.startError);
  p.check(!r.crashed, "crashed with signal " + std::to_string(r.signal));
  p.check(!r.timedOut, "timed out");
  auto mentionsAll = [&](const std::string& text, const std::string& where) {
    for (const std::string& m : inv.mentions)
      p.check(text.find(m) != std::string::npos, where + " does not mention '" + m + "'");
  };
  switch (inv.expect) {
    case Expect::Error: {
      p.check(r.exitCode != 0, "exit code 0");
      // `parity diff` follows idiff: the verdict line (FILE ERROR ...) is on stdout, exit 4.
      bool diff = inv.args[0] == "diff";
      const std::string& message = diff ? r.out : r.err;
      mentionsAll(message, diff ? "stdout" : "stderr");
      p.check(std::count(r.err.begin(), r.err.end(), '\n') <= 1, "more than one line on stderr");
      if (!diff) p.check(r.err.rfind("parity: error:", 0) == 0, "stderr does not start with 'parity: error:'");
      break;
    }
    case Expect::CaseFail:
    case Expect::CaseSkip: {
      fs::path runDir = dir_ / "run";
      std::string id = inv.args[2];
      nlohmann::json result = findCase(runDir, id);
      p.check(!result.is_null(), "results.json has no case " + id);
      if (result.is_null()) break;
      std::string got = result.value("result", "");
      std::string reason = result.value("reason", "");
      if (inv.expect == Expect::CaseFail) {
        p.check(r.exitCode != 0, "a failing case left exit code 0");
        p.check(got == "Fail", "result " + got + ", expected Fail");
      } else {
        p.check(got == "Skip", "result " + got + ", expected Skip");
      }
      mentionsAll(reason, "the case's reason '" + reason + "'");
      p.check(fs::exists(runDir / "report" / "index.html"), "no report");
      break;
    }
    case Expect::DiskFull: {
      p.check(r.exitCode != 0, "exit code 0 although writes failed");
      p.check(r.err.rfind("parity: error:", 0) == 0, "stderr does not start with 'parity: error:'");
      p.check(std::count(r.err.begin(), r.err.end(), '\n') <= 1, "more than one line on stderr");
      fs::path results = dir_ / "run" / "results.json";
      if (fs::exists(results)) {
        nlohmann::json j = nlohmann::json::parse(readText(results), nullptr, false);
        p.check(!j.is_discarded(), "results.json is truncated");
      }
      break;
    }
    case Expect::TestFail:
      p.check(r.exitCode != 0, "exit code 0");
      mentionsAll(r.out + r.err, "output");
      p.check(r.out.find("crashed") == std::string::npos, "a script crashed its runner");
      break;
  }
  for (const fs::path& f : inv.mustNotExist) p.check(!fs::exists(f), "left behind: " + f.filename().string());
  for (const auto& e : fs::recursive_directory_iterator(dir_)) {
    std::string n = e.path().filename().string();
    p.check(n.rfind(".parity-tmp", 0) != 0 && n.find(".tmp") == std::string::npos, "temporary file left: " + n);
  }

  if (!c.knownDefect.empty() && !p.list.empty()) {
    std::string all;
    for (const auto& s : p.list) all += "; " + s;
    GTEST_SKIP() << c.knownDefect << " (observed: " << all.substr(2) << ")";
  }
  for (const std::string& s : p.list) ADD_FAILURE() << c.name << ": " << s << "\n" << context;
}

TEST(BadInputCatalogue, HasAtLeastThirtyCases) { EXPECT_GE(catalogue().size(), 30u); }

INSTANTIATE_TEST_SUITE_P(Catalogue, BadInputTest, ::testing::Range<size_t>(0, catalogue().size()),
                         [](const ::testing::TestParamInfo<size_t>& info) { return catalogue()[info.param].name; });

}  // namespace
