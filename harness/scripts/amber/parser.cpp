// AmberScript statements of the script itself (REQUIRE, SET, DEVICE_FEATURE, DEVICE_EXTENSION, REPEAT, COPY, ...) and the dispatch of every statement to its family.
#include "harness/scripts/amber/statements.h"

#include <map>

#include "platforms/common/platform.h"
#include "platforms/common/platform_params.h"

namespace parity::harness::script::amber {

Script Parser::parseAll() {
  while (true) {
    Token t = next();
    if (!t.valid()) break;
    statement(t);
  }
  return std::move(script_);
}

void Parser::statement(const Token& t) {
  const std::string& k = t.text;
  if (k == "#!amber") return skipLine();
  if (k == "SHADER") return shader(t);
  if (k == "BUFFER" || k == "IMAGE") return buffer(t, k == "IMAGE");
  if (k == "SAMPLER") return sampler(t);
  if (k == "PIPELINE") return pipeline(t);
  if (k == "DERIVE_PIPELINE") return derivePipeline(t);
  if (k == "CLEAR_COLOR" || k == "CLEAR_DEPTH" || k == "CLEAR_STENCIL" || k == "CLEAR") return clear(t);
  if (k == "RUN") return run(t);
  if (k == "EXPECT") return expect(t);
  if (k == "REQUIRE") return require(t);
  if (k == "DEVICE_FEATURE") return deviceFeature(t);
  if (k == "DEVICE_EXTENSION" || k == "INSTANCE_EXTENSION") {
    Token n = nextSameLine("extension name");
    // Checked against the device when the script runs (runScript); instance extensions other
    // than the one Vulkan 1.1 made core are not queried.
    if (k == "DEVICE_EXTENSION") script_.requirements.push_back({"device_extension", n.text, {t.line, t.col}});
    else if (n.text != "VK_KHR_get_physical_device_properties2") unsupported(t, k + " " + n.text);
    return expectEndOfLine();
  }
  if (k == "DEVICE_PROPERTY") {
    Token n = nextSameLine("property name");
    // Checked against the device's boolean properties when the script runs (runScript).
    script_.requirements.push_back({"device_property", n.text, {t.line, t.col}});
    return expectEndOfLine();
  }
  if (k == "SET") return set(t);
  if (k == "RESOLVE") return resolve(t);
  if (k == "REPEAT") {  // the body's commands, unrolled
    uint32_t n = uintSameLine("repeat count");
    expectEndOfLine();
    size_t first = script_.commands.size();
    while (true) {
      Token w = next();
      if (!w.valid()) error(t, "missing END for REPEAT");
      if (w.text == "END") break;
      if (w.text != "RUN" && w.text != "CLEAR" && w.text != "CLEAR_COLOR" && w.text != "CLEAR_DEPTH" &&
          w.text != "CLEAR_STENCIL" && w.text != "EXPECT" && w.text != "COPY")
        error(w, "'" + w.text + "' cannot be repeated (commands only)");
      statement(w);
    }
    std::vector<Command> body(script_.commands.begin() + static_cast<long>(first), script_.commands.end());
    if (n == 0) script_.commands.resize(first);
    for (uint32_t i = 1; i < n; ++i) script_.commands.insert(script_.commands.end(), body.begin(), body.end());
    return;
  }
  if (k == "STRUCT") return structDecl(t);
  if (k == "VIRTUAL_FILE") return virtualFile(t);
  if (k == "COPY") {
    Command c;
    c.kind = Command::Kind::Copy;
    c.loc = {t.line, t.col};
    Token a = nextSameLine("source buffer");
    if (!script_.findBuffer(a.text)) error(a, "unknown buffer '" + a.text + "'");
    expectWord("TO");
    Token d = nextSameLine("destination buffer");
    if (!script_.findBuffer(d.text)) error(d, "unknown buffer '" + d.text + "'");
    c.buffer = a.text;
    c.other = d.text;
    expectEndOfLine();
    script_.commands.push_back(c);
    return;
  }
  if (k == "DEBUG") {
    unsupported(t, k);
    return skipBlock(t);
  }
  error(t, "unknown command '" + k + "'");
}

void Parser::require(const Token& t) {
  Token what = nextSameLine("backend, platform or capability");
  if (what.text != "backend" && what.text != "platform" && what.text != "capability")
    error(what, "REQUIRE takes backend, platform or capability, got '" + what.text + "'");
  Token v = nextSameLine(what.text + " name");
  if (what.text == "backend" && v.text != "gl" && v.text != "vk") error(v, "unknown backend '" + v.text + "' (gl or vk)");
  if (what.text == "platform" && !platforms::platformFromName(v.text))
    error(v, "unknown platform '" + v.text + "' (reference, dx10, ps3, x360)");
  script_.requirements.push_back({what.text, v.text, {t.line, t.col}});
  expectEndOfLine();
}

void Parser::set(const Token& t) {
  Token what = nextSameLine("PLATFORM_PARAM or ENGINE_DATA");
  if (what.text == "PLATFORM_PARAM") {
    Token n = nextSameLine("parameter name");
    Token v = nextSameLine("parameter value");
    // Short names for the parameters scripts set most; the catalogue names work as well.
    static const std::map<std::string, std::string> kAliases = {
        {"HALFPIXELOFFSET", "x360.halfpixeloffset"},     {"RESOLVE_PATH", "x360.dsf_resolve_path"},
        {"SIGNED_K16_RESOLVE", "x360.signed_k16_resolve"}, {"K16_UNPACK_CLAMP", "x360.k16_unpack_clamp"},
        {"TEXDEPTH2D_PRECISE", "ps3.texdepth2d_precise"}};
    std::string name = kAliases.count(n.text) ? kAliases.at(n.text) : n.text;
    std::string value = v.text;
    if (name == "x360.halfpixeloffset") value = value == "1" || lower(value) == "true" ? "true" : value == "0" || lower(value) == "false" ? "false" : value;
    if (!platforms::findParameter(name)) error(n, "unknown platform parameter '" + n.text + "' (`parity explain` lists them)");
    platforms::PlatformParams scratch;
    std::string why;
    if (!platforms::setParameter(scratch, name, value, &why)) error(v, why);
    script_.platformParams[name] = value;
    return expectEndOfLine();
  }
  if (what.text == "ENGINE_DATA") return skipLine();  // fence timeouts: nothing to do here
  error(what, "SET takes PLATFORM_PARAM or ENGINE_DATA, got '" + what.text + "'");
}

// Checked against the device's features when the script runs (runScript).
void Parser::deviceFeature(const Token& t) {
  Token n = nextSameLine("feature name");
  script_.requirements.push_back({"device_feature", n.text, {t.line, t.col}});
  expectEndOfLine();
}

}  // namespace parity::harness::script::amber

namespace parity::harness::script {

ParseResult parseScript(const std::string& text, const std::string& name) {
  ParseResult r;
  try {
    amber::Parser p(text, name);
    r.script = p.parseAll();
    r.ok = true;
  } catch (const amber::ParseError& e) {
    r.error = name + ":" + std::to_string(e.loc.line) + ":" + std::to_string(e.loc.column) + ": error: " + e.message;
  }
  return r;
}

}  // namespace parity::harness::script
