// A script's run (Runner) and the entry points of harness/scripts/runner.h: the checks before a
// run, the device requirements, the cases of a folder and their verdicts.
#include "harness/scripts/runner/steps.h"

#include "harness/scripts/opengl_glsl.h"

#include <algorithm>
#include <filesystem>
#include <regex>

namespace parity::harness::script {

const char* verdictName(Verdict v) {
  switch (v) {
    case Verdict::Pass: return "PASS";
    case Verdict::Fail: return "FAIL";
    default: return "SKIP";
  }
}

Verdict verdictFromName(const std::string& name) {
  return name == "PASS" ? Verdict::Pass : name == "SKIP" ? Verdict::Skip : Verdict::Fail;
}

std::vector<std::string> allowedPlatforms(const Script& script) {
  std::vector<std::string> named;
  for (const Requirement& r : script.requirements)
    if (r.what == "platform" && std::find(named.begin(), named.end(), r.value) == named.end()) named.push_back(r.value);
  if (!named.empty()) return named;
  std::vector<std::string> all;
  for (auto id : {platforms::PlatformId::Reference, platforms::PlatformId::Dx10, platforms::PlatformId::Ps3,
                  platforms::PlatformId::X360})
    all.emplace_back(platforms::platformName(id));
  return all;
}

std::string skipReasonBeforeRun(const Script& script, const std::string& backend, const RunOptions& options) {
  for (const Requirement& r : script.requirements)
    if (r.what == "backend" && r.value != backend)
      return "REQUIRE backend " + r.value + " (line " + std::to_string(r.loc.line) + ")";
  std::vector<std::string> allowed = allowedPlatforms(script);
  if (std::find(allowed.begin(), allowed.end(), options.platform) == allowed.end()) {
    std::string list;
    for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
    return "REQUIRE platform " + list + "; not " + options.platform;
  }
  if (!script.unsupported.empty()) {
    std::string s = "unsupported: ";
    for (size_t i = 0; i < script.unsupported.size() && i < 3; ++i)
      s += (i ? ", " : "") + script.unsupported[i].feature + " (line " + std::to_string(script.unsupported[i].loc.line) + ")";
    if (script.unsupported.size() > 3) s += " and " + std::to_string(script.unsupported.size() - 3) + " more";
    return s;
  }
  return {};
}


namespace runner {

RunResult Runner::run() {
  RunResult result;
  try {
    setupPlatform();
    for (const Shader& sh : script_.shaders) compiled_[sh.name] = compile(sh);  // errors surface even if unused
    // What a port needs of the device matters where the port runs: a driver that compiles the
    // OpenGL GLSL itself answers for it with its own extensions (deviceRequirementMissing).
    for (const auto& [name, module] : compiled_)
      if (!runsOnlyOpenGlGlsl(name)) requireShaderSupport(module);
    linkOpenGlVaryings();
    createResources();
    linkOpenGlBlocks();
    applyUniformInitializers();
    for (const Command& c : script_.commands) execute(c, result);
    const auto failedCheck = std::find_if(result.expects.begin(), result.expects.end(), [](const ExpectResult& e) { return !e.pass && !e.warning; });
    const auto warned = std::find_if(result.expects.begin(), result.expects.end(), [](const ExpectResult& e) { return e.warning; });
    if (failedCheck != result.expects.end()) {
      result.verdict = Verdict::Fail;
      result.reason = failedCheck->message;
    } else if (warned != result.expects.end()) {
      result.reason = "warn: " + warned->message;  // RunResult::verdict: piglit's warn, a Pass
    }
  } catch (const Unsupported& u) {
    result.verdict = Verdict::Skip;
    result.reason = "unsupported: " + u.what;
  } catch (const Failure& f) {
    result.verdict = Verdict::Fail;
    result.reason = f.what;
    for (const auto& e : result.expects)
      if (!e.pass && !e.warning) {  // report the first failure first
        result.reason = e.message + "; then " + f.what;
        break;
      }
  }
  return result;
}

void Runner::execute(const Command& c, RunResult& result) {
  const Pipeline* p = c.pipeline.empty() ? nullptr : script_.findPipeline(c.pipeline);
  switch (c.kind) {
    case Command::Kind::ClearColor:
      for (int i = 0; i < 4; ++i) clear_[p->name].color[i] = static_cast<float>(c.color[i] / 255.0);
      break;
    case Command::Kind::ClearDepth: clear_[p->name].depth = static_cast<float>(c.color[0]); break;
    case Command::Kind::ClearStencil: clear_[p->name].stencil = static_cast<uint8_t>(c.color[0]); break;
    case Command::Kind::Clear: clearPass(*p); break;
    case Command::Kind::DrawRect:
    case Command::Kind::DrawGrid:
    case Command::Kind::DrawArray: draw(c, *p); break;
    case Command::Kind::Compute: compute(c, *p); break;
    case Command::Kind::ExpectProbe: {
      ExpectResult e = probe(c);
      e.warning = c.warnOnly && !e.pass;
      result.expects.push_back(e);
      break;
    }
    case Command::Kind::Hint:
      result.notes.push_back(lineOf(c.loc) + ": hint " + c.other + " not passed on (OpenGL lets an implementation ignore hints; Vulkan has none)");
      break;
    case Command::Kind::ExpectValues: result.expects.push_back(values(c)); break;
    case Command::Kind::ExpectBuffer: result.expects.push_back(buffers(c)); break;
    case Command::Kind::Copy: copy(c); break;
    case Command::Kind::Resolve:
      if (!targets_->resolve(c.buffer, c.resolveSamples))
        throw Failure{lineOf(c.loc) + ": RESOLVE " + c.buffer + " failed on " + opts_.platform + ": " + targets_->error()};
      break;
    case Command::Kind::ExpectMemory:
      if (c.platform.empty() || c.platform == opts_.platform) result.expects.push_back(memory(c));
      break;
    case Command::Kind::ExpectImage: result.expects.push_back(image(c)); break;
    case Command::Kind::SetUniform: setUniform(c); break;
    case Command::Kind::ProgramParameter:
    case Command::Kind::LoadProjection:
    case Command::Kind::CurrentAttribute: setArbProgramState(c); break;
    case Command::Kind::ExpectUniform: result.expects.push_back(activeUniform(c)); break;
    case Command::Kind::ExpectProgramQuery: result.expects.push_back(programQuery(c)); break;
    case Command::Kind::ExpectLink:
      if (c.linkError) {
        result.expects.push_back(linkError(c, *p));
        break;
      }
      link(*p);
      result.expects.push_back({c.loc.line, true, lineOf(c.loc) + ": link success"});
      break;
    case Command::Kind::WriteBuffer: {
      rhi::BufferHandle b = gpuBuffer(c.buffer, c.loc);
      if (c.px + c.bytes.size() > res_.at(c.buffer).def->bytes.size()) throw Failure{lineOf(c.loc) + ": write past the end of '" + c.buffer + "'"};
      dev_.writeBuffer(b, c.px, c.bytes.data(), c.bytes.size());
      break;
    }
  }
}

}  // namespace runner

std::string ScriptCase::id() const { return script + "/" + backend + "/" + platform; }

bool isExpectFail(const std::string& path) {
  const std::string suffix = ".expect_fail.amber";
  return path.size() >= suffix.size() && path.compare(path.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::vector<std::string> collectScripts(const std::vector<std::string>& paths, std::string* error) {
  namespace fs = std::filesystem;
  std::vector<std::string> out;
  for (const std::string& p : paths) {
    std::error_code ec;
    if (fs::is_directory(p, ec)) {
      std::vector<std::string> found;
      for (auto it = fs::recursive_directory_iterator(p, ec); !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
        if (it->is_regular_file() && (it->path().extension() == ".amber" || it->path().extension() == ".shader_test"))
          found.push_back(it->path().string());
      std::sort(found.begin(), found.end());
      out.insert(out.end(), found.begin(), found.end());
    } else if (fs::is_regular_file(p, ec)) {
      out.push_back(p);
    } else {
      *error = p + ": no such file or folder";
      return {};
    }
  }
  return out;
}

std::vector<ScriptCase> listScriptCases(const std::vector<std::string>& paths, const std::vector<std::string>& backends,
                                        const std::vector<std::string>& platforms, std::string* error) {
  std::vector<ScriptCase> out;
  std::vector<std::string> files = collectScripts(paths, error);
  if (!error->empty()) return {};
  for (const std::string& f : files) {
    ParseResult parsed = parseScriptFile(f);
    std::vector<std::string> allowed = parsed.ok ? allowedPlatforms(parsed.script) : std::vector<std::string>{"reference"};
    for (const std::string& b : backends)
      for (const std::string& p : allowed)
        if (platforms.empty() || std::find(platforms.begin(), platforms.end(), p) != platforms.end())
          out.push_back({f, b, p, isExpectFail(f)});
  }
  return out;
}

RunResult applyExpectFail(RunResult r, bool expectFail) {
  if (!expectFail) return r;
  if (r.verdict == Verdict::Fail) {
    r.verdict = Verdict::Pass;
    r.reason = "failed as expected: " + r.reason;
  } else if (r.verdict == Verdict::Pass) {
    r.verdict = Verdict::Fail;
    r.reason = "expected to fail (*.expect_fail.amber) but passed";
  }
  return r;
}

RunResult runScriptCase(const ScriptCase& c) {
  RunResult r;
  ParseResult parsed = parseScriptFile(c.script);
  RunOptions ro;
  ro.platform = c.platform;
  if (!parsed.ok) return applyExpectFail({Verdict::Fail, parsed.error, {}}, c.expectFail);
  if (std::string why = skipReasonBeforeRun(parsed.script, c.backend, ro); !why.empty()) return {Verdict::Skip, why, {}};
  rhi::DeviceDesc desc;
  desc.backend = c.backend;
  desc.glCompatibilityProfile = compatibilityProfile(parsed.script);
  std::vector<std::string> validation;
  desc.onValidationError = [&validation](const std::string& id, const std::string& msg) { validation.push_back(id + ": " + msg); };
  std::string whyNot;
  std::unique_ptr<rhi::Device> dev = rhi::createDevice(desc, &whyNot);
  if (!dev) return {Verdict::Skip, "backend " + c.backend + " unavailable: " + whyNot, {}};
  r = runScript(parsed.script, *dev, ro);
  if (!validation.empty() && r.verdict == Verdict::Pass) {
    r.verdict = Verdict::Fail;
    r.reason = "RHI validation: " + validation.front();
  } else if (!validation.empty() && r.verdict == Verdict::Fail) {
    r.reason += " (RHI validation: " + validation.front() + ")";
  }
  return applyExpectFail(r, c.expectFail);
}

bool compatibilityProfile(const Script& script) {
  // ARB assembly programs exist in compatibility contexts only, and so do GLSL before 1.40 and
  // a shader of the compatibility profile.
  static const std::regex kCompatibilityShader(R"(#[ \t]*version[ \t]+\d+[ \t]+compatibility\b)");
  return script.hasArbPrograms() || script.compatibilityContext || std::any_of(script.shaders.begin(), script.shaders.end(), [](const Shader& s) {
           return s.openGl && (s.glslVersion < 140 || std::regex_search(s.source, kCompatibilityShader));
         });
}

std::string deviceRequirementMissing(const Script& script, const rhi::DeviceInfo& info) {
  // Emulated by the runner: uint8 indices are widened on the CPU.
  static const std::set<std::string> kEmulated = {"indexTypeUint8", "VK_EXT_index_type_uint8"};
  const bool openGlDriver = std::find(info.features.begin(), info.features.end(), "openGlGlsl") != info.features.end();
  for (const Requirement& r : script.requirements) {
    if (r.what != "opengl_extension") continue;
    // A driver that compiles OpenGL GLSL answers for its own context, as it does for piglit.
    // Elsewhere the port runs: extensions core in GL 4.5 or GLSL built-ins glslang knows (mix()
    // of integers, GLSL 4.00's integer functions of GL_MESA_shader_integer_functions, the
    // extensions glslang knows by other names, portsExtension) have one.
    const std::string& e = r.value;
    const bool ported = e.rfind("GL_ARB_", 0) == 0 || e.rfind("GL_KHR_", 0) == 0 || e == "GL_EXT_shader_integer_mix" ||
                        e == "GL_EXT_texture_array" || e == "GL_MESA_shader_integer_functions" || portsExtension(e);
    if (openGlDriver && std::find(info.openGlExtensions.begin(), info.openGlExtensions.end(), e) == info.openGlExtensions.end())
      return "[require] " + e + " (line " + std::to_string(r.loc.line) + ") not offered by " + info.backend + " on " + info.renderer;
    if (!openGlDriver && !ported)
      return "[require] " + e + " (line " + std::to_string(r.loc.line) + "): no port of its shaders for " + info.backend;
  }
  for (const Requirement& r : script.requirements) {
    const bool feature = r.what == "device_feature", property = r.what == "device_property";
    if (!feature && !property && r.what != "device_extension") continue;
    // Amber qualifies features and properties by their structure ("Float16Int8Features.shaderFloat16");
    // the member names are unique across the structures.
    std::string name = feature || property ? r.value.substr(r.value.rfind('.') + 1) : r.value;
    const std::vector<std::string>& offered = feature ? info.features : property ? info.properties : info.extensions;
    if (kEmulated.count(name) || std::find(offered.begin(), offered.end(), name) != offered.end()) continue;
    return std::string(feature ? "DEVICE_FEATURE " : property ? "DEVICE_PROPERTY " : "DEVICE_EXTENSION ") + r.value +
           " (line " + std::to_string(r.loc.line) + ") not " + (property ? "reported" : "offered") + " by " + info.backend +
           " on " + info.renderer;
  }
  return {};
}

RunResult runScript(const Script& script, rhi::Device& device, const RunOptions& options) {
  std::string why = skipReasonBeforeRun(script, device.info().backend, options);
  if (!why.empty()) return {Verdict::Skip, why, {}};
  const rhi::Capabilities& caps = device.info().caps;
  for (const Requirement& r : script.requirements) {
    if (r.what != "capability") continue;
    bool ok = r.value == "compute" ? caps.compute
              : r.value == "texture_views" ? caps.textureViews
              : r.value == "timestamps" ? caps.timestamps
              : r.value == "independent_blend" ? caps.independentBlend
              : r.value == "msaa4" ? caps.maxSamples >= 4
                                   : false;
    if (!ok) return {Verdict::Skip, "REQUIRE capability " + r.value + " not offered by this backend", {}};
  }
  if (std::string why = deviceRequirementMissing(script, device.info()); !why.empty()) return {Verdict::Skip, why, {}};
  runner::Runner runner(script, device, options);
  return runner.run();
}

}  // namespace parity::harness::script
