#include "rhi/shader_compiler.h"

#include <glslang/Public/ResourceLimits.h>
#include <glslang/build_info.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>
#include <glslang/MachineIndependent/iomapper.h>
#include <spirv-tools/libspirv.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <regex>
#include <sstream>

#include "rhi/shader_cache.h"
#include "rhi/vertex_input_locations.h"

namespace fs = std::filesystem;

namespace parity::rhi {

namespace {

// glslang's process-wide state: initialised once, never finalised (other threads may compile).
void initGlslangOnce() {
  static std::once_flag once;
  std::call_once(once, [] { glslang::InitializeProcess(); });
}

bool readFile(const std::string& path, std::string* text) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::stringstream ss;
  ss << in.rdbuf();
  *text = ss.str();
  return true;
}

// Resolves #include "x" against the including file's folder, then the option's folders, then
// shaders/include. Included file names are kept as given on disk so that errors read
// "shaders/include/parity_math.glsl:12: ...".
class Includer : public glslang::TShader::Includer {
 public:
  explicit Includer(std::vector<std::string> dirs) : dirs_(std::move(dirs)) {}

  IncludeResult* includeLocal(const char* headerName, const char* includerName, size_t depth) override {
    std::vector<std::string> candidates;
    fs::path includer(includerName ? includerName : "");
    if (includer.has_parent_path()) candidates.push_back((includer.parent_path() / headerName).string());
    for (const std::string& d : dirs_) candidates.push_back((fs::path(d) / headerName).string());
    return open(candidates);
  }
  IncludeResult* includeSystem(const char* headerName, const char*, size_t) override {
    std::vector<std::string> candidates;
    for (const std::string& d : dirs_) candidates.push_back((fs::path(d) / headerName).string());
    return open(candidates);
  }
  void releaseInclude(IncludeResult* result) override {
    if (!result) return;
    delete static_cast<std::string*>(result->userData);
    delete result;
  }

 private:
  IncludeResult* open(const std::vector<std::string>& candidates) {
    for (const std::string& path : candidates) {
      std::error_code ec;
      if (!fs::is_regular_file(path, ec)) continue;
      auto* text = new std::string;
      if (!readFile(path, text)) {
        delete text;
        continue;
      }
      return new IncludeResult(fs::path(path).lexically_normal().string(), text->data(), text->size(), text);
    }
    return nullptr;  // glslang reports "cannot find include file"
  }
  std::vector<std::string> dirs_;
};

// #include of OpenGL's named strings (ShaderCompileOptions::namedStrings): a later string of a
// path replaces an earlier one, as glNamedStringARB does.
class NamedStringIncluder : public glslang::TShader::Includer {
 public:
  explicit NamedStringIncluder(const ShaderCompileOptions& o) : searchPaths_(o.namedStringSearchPaths) {
    for (const auto& [path, text] : o.namedStrings) strings_[normal(path)] = text;
  }
  IncludeResult* includeLocal(const char* headerName, const char* includerName, size_t) override {
    const std::string including = includerName ? includerName : "";
    if (!including.empty() && including[0] == '/')
      if (IncludeResult* r = find(fs::path(including).parent_path() / headerName)) return r;
    return includeSystem(headerName, includerName, 0);
  }
  IncludeResult* includeSystem(const char* headerName, const char*, size_t) override {
    if (headerName[0] == '/') return find(headerName);
    for (const std::string& dir : searchPaths_)
      if (IncludeResult* r = find(fs::path(dir) / headerName)) return r;
    return nullptr;
  }
  void releaseInclude(IncludeResult* result) override { delete result; }

 private:
  static std::string normal(const fs::path& p) { return p.lexically_normal().generic_string(); }
  IncludeResult* find(const fs::path& path) {
    auto it = strings_.find(normal(path));
    if (it == strings_.end()) return nullptr;
    return new IncludeResult(it->first, it->second.data(), it->second.size(), nullptr);
  }
  std::map<std::string, std::string> strings_;
  std::vector<std::string> searchPaths_;
};

// A shader with named strings includes those; any other includes files of `dirs`.
std::unique_ptr<glslang::TShader::Includer> makeIncluder(const ShaderCompileOptions& o, const std::vector<std::string>& dirs) {
  if (o.namedStrings.empty()) return std::make_unique<Includer>(dirs);
  return std::make_unique<NamedStringIncluder>(o);
}

// glslang prints "ERROR: file:line: message"; reformat to the compiler convention
// "file:line: error: message" so editors and CI annotate the right line.
std::string formatLog(const std::string& log) {
  static const std::regex kLine(R"(^(ERROR|WARNING): ([^:]+):(\d+): (.*)$)");
  std::stringstream in(log), out;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::smatch m;
    if (std::regex_match(line, m, kLine)) {
      out << m[2] << ':' << m[3] << ": " << (m[1] == "ERROR" ? "error" : "warning") << ": " << m[4] << '\n';
    } else if (line.find("compilation terminated") == std::string::npos &&
               line.find("compilation errors") == std::string::npos) {
      out << line << '\n';
    }
  }
  return out.str();
}

EShLanguage toGlslang(ShaderStage stage) {
  switch (stage) {
    case ShaderStage::Vertex: return EShLangVertex;
    case ShaderStage::Fragment: return EShLangFragment;
    case ShaderStage::Compute: return EShLangCompute;
    case ShaderStage::Geometry: return EShLangGeometry;
    case ShaderStage::TessControl: return EShLangTessControl;
    case ShaderStage::TessEvaluation: return EShLangTessEvaluation;
  }
  return EShLangVertex;
}

std::mutex gCacheMutex;
std::map<std::string, CompiledShader>& cache() {
  static std::map<std::string, CompiledShader> c;
  return c;
}

std::string preambleOf(const ShaderCompileOptions& options) {
  std::string preamble = "#extension GL_GOOGLE_include_directive : require\n";
  for (const auto& [key, value] : options.defines) preamble += "#define " + key + " " + value + "\n";
  return preamble;
}

// Every compilation unit, of a module or of a program, is compiled alike. `preamble` must outlive
// the unit's parse.
void configureUnit(glslang::TShader& unit, ShaderStage stage, const ShaderCompileOptions& options, const std::string& preamble) {
  unit.setPreamble(preamble.c_str());
  unit.setEntryPoint("main");
  // Vulkan 1.2 / SPIR-V 1.5: every Vulkan 1.3 ICD accepts it, SPIRV-Cross reads it, and it
  // avoids SPIR-V 1.6's LocalSizeId (which needs maintenance4 on Vulkan).
  unit.setEnvInput(glslang::EShSourceGlsl, toGlslang(stage), glslang::EShClientVulkan, 100);
  unit.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_2);
  unit.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_5);
  if (options.openGlSource) {
    unit.setEnvInputVulkanRulesRelaxed();
    unit.setGlobalUniformSet(options.defaultUniformSet);
    unit.setGlobalUniformBinding(options.defaultUniformBinding);
    unit.setAutoMapBindings(true);
    unit.setAutoMapLocations(true);
  }
}

const EShMessages kMessages = static_cast<EShMessages>(EShMsgSpvRules | EShMsgVulkanRules);

}  // namespace

namespace {
std::string& packageDataDirectory() {
  static std::string dir;
  return dir;
}
}  // namespace

bool setPackageDataDirectory(const std::string& dir) {
  packageDataDirectory() = dir;
  return true;
}

std::string dataDirectory() {
  if (const char* env = std::getenv("PARITY_DATA_DIR"); env && *env) return env;
  static const std::string installed = [] {
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec) return std::string();
    const fs::path data = (exe.parent_path() / PARITY_INSTALL_DATA_FROM_BIN).lexically_normal();
    return fs::is_directory(data / "shaders", ec) ? data.string() : std::string();
  }();
  if (!installed.empty()) return installed;
  std::error_code ec;
  const std::string& package = packageDataDirectory();
  if (!package.empty() && fs::is_directory(fs::path(package) / "shaders", ec)) return package;
  return PARITY_SOURCE_DIR;
}

std::string shaderDirectory() {
  if (const char* env = std::getenv("PARITY_SHADER_DIR")) return env;
  return (fs::path(dataDirectory()) / "shaders").string();
}

bool stageFromPath(const std::string& path, ShaderStage* stage) {
  std::string p = path;
  if (p.size() > 5 && p.substr(p.size() - 5) == ".glsl") p.resize(p.size() - 5);
  std::string ext = fs::path(p).extension().string();
  if (ext == ".vert") *stage = ShaderStage::Vertex;
  else if (ext == ".frag") *stage = ShaderStage::Fragment;
  else if (ext == ".comp") *stage = ShaderStage::Compute;
  else if (ext == ".geom") *stage = ShaderStage::Geometry;
  else if (ext == ".tesc") *stage = ShaderStage::TessControl;
  else if (ext == ".tese") *stage = ShaderStage::TessEvaluation;
  else return false;
  return true;
}

CompiledShader compileGlslFile(const std::string& path, ShaderStage stage, const ShaderCompileOptions& options) {
  std::string source;
  if (!readFile(path, &source)) {
    CompiledShader out;
    out.error = path + ": error: cannot read shader file";
    return out;
  }
  return compileGlslSource(source, path, stage, options);
}

CompiledShader compileGlslSource(const std::string& source, const std::string& name, ShaderStage stage,
                                 const ShaderCompileOptions& options) {
  const std::string preamble = preambleOf(options);

  std::string cacheKey = std::to_string(static_cast<int>(stage)) + '\0' + name + '\0' + preamble + '\0' + source;
  for (const std::string& d : options.includeDirs) cacheKey += '\0' + d;
  if (options.openGlSource)
    cacheKey += "\0gl" + std::to_string(options.defaultUniformSet) + "/" + std::to_string(options.defaultUniformBinding);
  for (const std::string& unit : options.linkedSources) cacheKey += std::string("\0unit\0") + unit;
  for (const auto& [path, text] : options.namedStrings) cacheKey += std::string("\0named\0") + path + '\0' + text;
  for (const std::string& path : options.namedStringSearchPaths) cacheKey += std::string("\0search\0") + path;
  {
    std::lock_guard<std::mutex> lock(gCacheMutex);
    auto it = cache().find(cacheKey);
    if (it != cache().end()) return it->second;
  }

  initGlslangOnce();
  CompiledShader out;
  // The source and each linked unit, compiled alike.
  auto configure = [&](glslang::TShader& unit) { configureUnit(unit, stage, options, preamble); };
  glslang::TShader shader(toGlslang(stage));
  const char* strings[] = {source.c_str()};
  const int lengths[] = {static_cast<int>(source.size())};
  const char* names[] = {name.c_str()};
  shader.setStringsWithLengthsAndNames(strings, lengths, names, 1);
  configure(shader);

  std::vector<std::string> dirs = options.includeDirs;
  dirs.push_back((fs::path(shaderDirectory()) / "include").string());
  const std::unique_ptr<glslang::TShader::Includer> includer = makeIncluder(options, dirs);
  const EShMessages messages = kMessages;

  // Across processes (rhi/shader_cache.h): the key is the in-process one, every included file's
  // text (the preprocessed source) and what the result depends on besides (compiler version,
  // environment, the validation below). Preprocessing costs a fraction of a compile.
  std::string diskKey;
  // Not with linked units: the preprocessed text below is the first unit's alone.
  if (!shaderCacheDirectory().empty() && options.linkedSources.empty()) {
    glslang::TShader pre(toGlslang(stage));
    pre.setStringsWithLengthsAndNames(strings, lengths, names, 1);
    pre.setPreamble(preamble.c_str());
    pre.setEnvInput(glslang::EShSourceGlsl, toGlslang(stage), glslang::EShClientVulkan, 100);
    pre.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_2);
    pre.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_5);
    std::string preprocessed;
    const std::unique_ptr<glslang::TShader::Includer> preIncluder = makeIncluder(options, dirs);
    if (pre.preprocess(GetDefaultResources(), 450, ENoProfile, false, false, messages, &preprocessed, *preIncluder)) {
      diskKey = "glslang " + std::to_string(GLSLANG_VERSION_MAJOR) + "." + std::to_string(GLSLANG_VERSION_MINOR) + "." +
                std::to_string(GLSLANG_VERSION_PATCH) + " vulkan1.2 spv1.5 validated-vulkan1.2 code " PARITY_SHADER_CACHE_STAMP + '\0' + cacheKey +
                '\0' + preprocessed;
      if (std::optional<std::vector<uint32_t>> words = loadCachedWords(diskKey)) {
        out.spirv = std::move(*words);
        std::lock_guard<std::mutex> lock(gCacheMutex);
        cache()[cacheKey] = out;
        return out;
      }
    }
  }
  if (!shader.parse(GetDefaultResources(), 450, ENoProfile, false, false, messages, *includer)) {
    out.error = formatLog(shader.getInfoLog());
    if (out.error.empty()) out.error = name + ": error: compilation failed\n";
    return out;  // failures are not cached: the file may be fixed and retried
  }
  glslang::TProgram program;
  program.addShader(&shader);
  std::vector<std::unique_ptr<glslang::TShader>> units;
  for (const std::string& text : options.linkedSources) {
    units.push_back(std::make_unique<glslang::TShader>(toGlslang(stage)));
    const char* unitStrings[] = {text.c_str()};
    const int unitLengths[] = {static_cast<int>(text.size())};
    units.back()->setStringsWithLengthsAndNames(unitStrings, unitLengths, names, 1);
    configure(*units.back());
    if (!units.back()->parse(GetDefaultResources(), 450, ENoProfile, false, false, messages, *includer)) {
      out.error = formatLog(units.back()->getInfoLog());
      if (out.error.empty()) out.error = name + ": error: compilation failed\n";
      return out;
    }
    program.addShader(units.back().get());
  }
  if (!program.link(messages)) {
    out.error = formatLog(program.getInfoLog());
    if (out.error.empty()) out.error = name + ": error: link failed\n";
    return out;
  }
  // glslang's mapper for OpenGL's rules: explicit locations are reserved before the automatic ones
  // are given (the default mapper numbers from 0 and collides with them).
  glslang::TGlslIoMapper openGlMapper;
  glslang::TDefaultGlslIoResolver openGlResolver(*program.getIntermediate(toGlslang(stage)));
  if (options.openGlSource && !program.mapIO(&openGlResolver, &openGlMapper)) {  // assigns the automatic bindings and locations
    out.error = formatLog(program.getInfoLog());
    if (out.error.empty()) out.error = name + ": error: cannot assign bindings and locations\n";
    return out;
  }
  glslang::SpvOptions spvOptions;
  spvOptions.validate = false;  // validateSpirv() below, with readable messages
  spv::SpvBuildLogger logger;
  glslang::GlslangToSpv(*program.getIntermediate(toGlslang(stage)), out.spirv, &logger, &spvOptions);
  if (options.openGlSource && stage == ShaderStage::Vertex) vulkanVertexInputLocations(out.spirv);
  std::string validation;
  if (!validateSpirv(out.spirv, &validation)) {
    out.error = name + ": error: generated SPIR-V is invalid: " + validation + "\n";
    out.spirv.clear();
    return out;
  }
  if (!diskKey.empty()) storeCachedWords(diskKey, out.spirv);
  std::lock_guard<std::mutex> lock(gCacheMutex);
  cache()[cacheKey] = out;
  return out;
}

ProgramLink linkGlslProgram(const std::vector<ProgramStageSource>& stages, const std::string& name) {
  initGlslangOnce();
  ProgramLink out;
  std::vector<std::string> preambles;
  preambles.reserve(stages.size());  // the units keep pointers to their preambles
  std::vector<std::unique_ptr<glslang::TShader::Includer>> includers;
  std::vector<std::unique_ptr<glslang::TShader>> units;
  glslang::TProgram program;  // destroyed before the units it links
  const char* names[] = {name.c_str()};
  for (const ProgramStageSource& stage : stages) {
    preambles.push_back(preambleOf(stage.options));
    std::vector<std::string> dirs = stage.options.includeDirs;
    dirs.push_back((fs::path(shaderDirectory()) / "include").string());
    includers.push_back(makeIncluder(stage.options, dirs));
    std::vector<const std::string*> texts{&stage.source};
    for (const std::string& unit : stage.options.linkedSources) texts.push_back(&unit);
    for (const std::string* text : texts) {
      units.push_back(std::make_unique<glslang::TShader>(toGlslang(stage.stage)));
      const char* strings[] = {text->c_str()};
      const int lengths[] = {static_cast<int>(text->size())};
      units.back()->setStringsWithLengthsAndNames(strings, lengths, names, 1);
      configureUnit(*units.back(), stage.stage, stage.options, preambles.back());
      if (!units.back()->parse(GetDefaultResources(), 450, ENoProfile, false, false, kMessages, *includers.back())) {
        out.compileError = formatLog(units.back()->getInfoLog());
        if (out.compileError.empty()) out.compileError = name + ": error: compilation failed\n";
        return out;
      }
      program.addShader(units.back().get());
    }
  }
  if (program.link(kMessages)) return out;
  // Every rule glslang's linker checks, within a stage (its units merged) or across stages (the
  // uniforms and blocks of all stages, each stage's outputs against the next one's inputs), is
  // reported through TIntermediate::error as "ERROR: Linking <stage> stage: ..." or "ERROR:
  // Linking <a> and <b> stages: ...". What the linker refuses without that prefix ("Cannot mix
  // ES profile with non-ES profile shaders") is kept apart, with the units' compile errors, and so
  // is what glslang 12 reports of programs OpenGL links: between the tessellation stages it takes
  // a `patch` array for a per-vertex one (TIntermediate::isIoResizeArray), whose sizes never match.
  static const char* const kNotRules[] = {"Linking tessellation control and tessellation evaluation stages: Array sizes must be compatible"};
  const std::string log = formatLog(program.getInfoLog());
  bool rule = false;
  std::istringstream lines(log);
  for (std::string line; std::getline(lines, line);)
    rule |= line.rfind("ERROR: Linking ", 0) == 0 &&
            std::none_of(std::begin(kNotRules), std::end(kNotRules), [&](const char* n) { return line.find(n) != std::string::npos; });
  (rule ? out.linkError : out.compileError) = log.empty() ? name + ": error: link failed\n" : log;
  return out;
}

bool validateSpirv(const std::vector<uint32_t>& spirv, std::string* error) {
  spvtools::SpirvTools tools(SPV_ENV_VULKAN_1_2);
  std::string messages;
  tools.SetMessageConsumer([&](spv_message_level_t, const char*, const spv_position_t& pos, const char* msg) {
    if (!messages.empty()) messages += "; ";
    messages += msg;
  });
  if (spirv.empty()) {
    if (error) *error = "empty module";
    return false;
  }
  bool ok = tools.Validate(spirv);
  if (!ok && error) *error = messages;
  return ok;
}

CompiledShader assembleSpirv(const std::string& text, const std::string& name, int firstLine, int spirvMinor) {
  // Universal 1.0 by default: the version hand-written modules (Amber's among them) are written
  // for; the header then says 1.0, which Vulkan 1.3 and SPIRV-Cross both accept.
  static const spv_target_env kEnvs[] = {SPV_ENV_UNIVERSAL_1_0, SPV_ENV_UNIVERSAL_1_1, SPV_ENV_UNIVERSAL_1_2, SPV_ENV_UNIVERSAL_1_3,
                                         SPV_ENV_UNIVERSAL_1_4, SPV_ENV_UNIVERSAL_1_5, SPV_ENV_UNIVERSAL_1_6};
  spvtools::SpirvTools tools(kEnvs[spirvMinor >= 0 && spirvMinor <= 6 ? spirvMinor : 0]);
  CompiledShader out;
  tools.SetMessageConsumer([&](spv_message_level_t, const char*, const spv_position_t& pos, const char* msg) {
    if (!out.error.empty()) out.error += "\n";
    out.error += name + ":" + std::to_string(firstLine + static_cast<int>(pos.line)) + ": " + msg;
  });
  if (!tools.Assemble(text, &out.spirv, SPV_TEXT_TO_BINARY_OPTION_PRESERVE_NUMERIC_IDS) && out.error.empty())
    out.error = name + ": not SPIR-V assembly";
  if (!out.error.empty()) out.spirv.clear();
  return out;
}

}  // namespace parity::rhi
