// Shaders of a script: compilation to SPIR-V, its edits, and OpenGL GLSL's linking rules.
#include "harness/scripts/runner/steps.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <set>
#include <regex>
#include <sstream>

#include "harness/io/text.h"
#include "harness/scripts/opengl_glsl.h"
#include "harness/scripts/opengl_uniform_types.h"
#include "harness/scripts/spirv_interface.h"
#include "rhi/shader_compiler.h"
#include "rhi/shader_reflection.h"

namespace parity::harness::script::runner {

std::map<SetBinding, uint32_t>& ShaderSteps::bindingMap(const Pipeline& p, const std::vector<std::vector<uint32_t>>& modules) {
  auto it = bindingMaps_.find(p.name);
  if (it != bindingMaps_.end()) return it->second;
  std::set<SetBinding> all;
  for (const auto& m : modules)
    for (auto sb : spirvBindings(m)) all.insert(sb);
  for (const Bind& b : bindsOf(p))
    if (b.kind == BindKind::Storage || b.kind == BindKind::Uniform || b.kind == BindKind::CombinedImageSampler ||
        b.kind == BindKind::StorageImage || b.kind == BindKind::SampledImage || b.kind == BindKind::Sampler ||
        b.kind == BindKind::UniformTexelBuffer || b.kind == BindKind::StorageTexelBuffer)
      all.insert({b.set, b.binding});
  std::map<SetBinding, uint32_t> map;
  bool identity = true;
  for (auto sb : all) identity &= sb.first == 0 && sb.second < rhi::kMaxBindings;
  uint32_t next = 0;
  for (auto sb : all) map[sb] = identity ? sb.second : next++;
  if (next > rhi::kMaxBindings) throw Unsupported{"more than " + std::to_string(rhi::kMaxBindings) + " bindings"};
  return bindingMaps_[p.name] = map;
}

bool ShaderSteps::nextStageBeforeGlsl450() const {
  for (const Shader& next : script_.shaders) {
    if (!next.openGl || (next.stage != Stage::TessControl && next.stage != Stage::TessEvaluation && next.stage != Stage::Geometry))
      continue;
    const std::string source = prepareOpenGlGlsl(next.source, next.stage, next.glslVersion, script_.fixedFunction).source;
    const size_t at = source.find("#version");
    if (at != std::string::npos && std::atoi(source.c_str() + at + 8) < 450) return true;
  }
  return false;
}

// OpenGL links one program: its last stage before rasterisation is its geometry shader, or
// else its tessellation evaluation shader, or else its vertex shader.
bool ShaderSteps::lastBeforeRasterisation(Stage stage) const {
  auto has = [&](Stage st) {
    return std::any_of(script_.shaders.begin(), script_.shaders.end(), [&](const Shader& s) { return s.stage == st; });
  };
  if (stage == Stage::Geometry) return true;
  if (stage == Stage::TessEvaluation) return !has(Stage::Geometry);
  return stage == Stage::Vertex && !has(Stage::Geometry) && !has(Stage::TessEvaluation);
}

rhi::ShaderCompileOptions ShaderSteps::portOptions(const Shader& s) const {
  rhi::ShaderCompileOptions options = compileOptions_;
  options.namedStrings = script_.namedStrings;
  options.namedStringSearchPaths = script_.namedStringSearchPaths;
  if (s.openGl && !s.passthrough) {
    options.openGlSource = true;
    options.defaultUniformSet = kDefaultUniformSet;
    options.defaultUniformBinding = static_cast<uint32_t>(s.stage);
  }
  return options;
}

// One compilation unit as glslang gets it: OpenGL GLSL's declarations added, and the compiler's
// line numbers kept those of the script (a #line after #version).
// `wholeUnit`: for a unit reduced to its declarations, the unit it came from, whose code reads
// what the port must still declare (the compatibility state the runner keeps in uniforms).
std::string ShaderSteps::portSource(const Shader& s, const std::string& source, int sourceLine, const std::string* wholeUnit) const {
  if (s.passthrough) return std::string(nextStageBeforeGlsl450() ? kPassthroughVsWithoutCullDistance : kPassthroughVs);
  if (!s.openGl) return withDeclarations(source, "", sourceLine, "#version 450");
  OpenGlGlsl gl = prepareOpenGlGlsl(source, s.stage, s.glslVersion, script_.fixedFunction, lastBeforeRasterisation(s.stage));
  if (wholeUnit) {
    std::istringstream lines(prepareOpenGlGlsl(*wholeUnit, s.stage, s.glslVersion, script_.fixedFunction, lastBeforeRasterisation(s.stage)).declarations);
    for (std::string line; std::getline(lines, line);)
      if (line.rfind("uniform ", 0) == 0 && gl.declarations.find(line) == std::string::npos) gl.declarations += line + "\n";
  }
  return withDeclarations(gl.source, gl.declarations, sourceLine, "", source.find("#version") == std::string::npos);
}

std::optional<rhi::ProgramLink> ShaderSteps::linkPort(const Pipeline& p) const {
  std::vector<rhi::ProgramStageSource> stages;
  for (const std::string& n : p.shaders) {
    const Shader* s = script_.findShader(n);
    if (!s || s->format != "GLSL") return std::nullopt;
    rhi::ProgramStageSource stage;
    stage.stage = rhiStage(s->stage);
    stage.options = portOptions(*s);
    // Each stage's module has its loose uniforms at a binding of its own; in one program they are
    // OpenGL's one default uniform block, whose bindings glslang's linker compares across stages.
    stage.options.defaultUniformBinding = 0;
    stage.source = portSource(*s, s->source, s->sourceLine);
    for (const Shader::LinkedUnit& unit : s->linkedUnits) stage.options.linkedSources.push_back(portSource(*s, unit.source, unit.sourceLine));
    stages.push_back(std::move(stage));
  }
  return rhi::linkGlslProgram(stages, script_.file);
}

std::vector<uint32_t> ShaderSteps::compile(const Shader& s) {
  if (s.format == "ARB") return arbProgramPort(s);
  if (s.format == "SPIRV-BIN") {
    if (s.source.size() % 4 != 0 || s.source.size() < 20) throw Failure{"shader '" + s.name + "': SPIR-V binary of " + std::to_string(s.source.size()) + " bytes"};
    std::vector<uint32_t> words(s.source.size() / 4);
    std::memcpy(words.data(), s.source.data(), s.source.size());
    return words;
  }
  if (s.format == "SPIRV-ASM") {
    rhi::CompiledShader c = rhi::assembleSpirv(s.source, script_.file, s.sourceLine, s.spirvMinor);
    if (!c.ok()) throw Failure{"shader '" + s.name + "' does not assemble: " + oneLine(c.error)};
    if (!s.openGlSpirv) return c.spirv;
    // OpenGL's SPIR-V (piglit's SPIR-V programs) in the RHI's Vulkan-style terms.
    const std::string loose = looseUniformOf(c.spirv);
    if (!loose.empty())
      throw Unsupported{"shader '" + s.name + "': loose uniform " + loose + " (OpenGL SPIR-V's default uniform block, which Vulkan has no place for)"};
    addMissingDescriptorSets(c.spirv);
    originAtFirstRow(c.spirv);
    dropUniformLocations(c.spirv);
    return c.spirv;
  }
  rhi::ShaderCompileOptions options = portOptions(s);
  auto prepare = [&](const std::string& source, int sourceLine, const std::string* wholeUnit = nullptr) {
    return portSource(s, source, sourceLine, wholeUnit);
  };
  std::string src = prepare(s.source, s.sourceLine);
  for (const Shader::LinkedUnit& unit : s.linkedUnits) options.linkedSources.push_back(prepare(unit.source, unit.sourceLine));
  rhi::ShaderStage st = rhiStage(s.stage);
  rhi::CompiledShader c = rhi::compileGlslSource(src, script_.file, st, options);
  const bool expectsLinkError = std::any_of(script_.commands.begin(), script_.commands.end(), [](const Command& k) { return k.linkError; });
  const std::vector<std::string>& features = dev_.info().features;
  const bool portOnly = std::find(features.begin(), features.end(), "openGlGlsl") == features.end();
  // Where the port is all the device runs, whether a program that should not link breaks a link
  // rule is for glslang's linker to say, over the whole program (PassSteps::portLinkError): a
  // shader glslang does not port (or whose units its linker refuses) has an empty port meanwhile.
  auto linkOnlyPort = [&](const std::string& why) {
    std::vector<uint32_t> empty = emptyPort(s.stage);
    if (!portOnly || !expectsLinkError || empty.empty()) return std::vector<uint32_t>{};
    declarationPorts_[s.name] = why;
    linkOnlyPorts_.insert(s.name);
    return empty;
  };
  if (!c.ok() && s.openGl) {
    // Where a driver compiles OpenGL GLSL (the device's, or RunOptions::openGlCompiler's), it
    // says whether the shader is valid: one it compiles that glslang cannot port is glslang's
    // limit, one it refuses is broken.
    if (std::optional<std::string> driver = driverCompiles(s)) {
      if (!driver->empty()) {
        if (std::optional<std::string> lacking = judgeLacksRequirement()) throw Unsupported{*lacking};
        throw Failure{"shader '" + s.name + "' does not compile: " + *driver};
      }
      const std::string limit = "OpenGL GLSL that the gl driver compiles and glslang cannot port: " + oneLine(c.error);
      if (portOnly) {  // the port is all this device runs
        if (std::vector<uint32_t> empty = linkOnlyPort(limit); !empty.empty()) return empty;
        throw Unsupported{limit};
      }
      // The driver runs the code; a port of the declarations alone places it (runsOpenGlGlsl).
      rhi::ShaderCompileOptions declarations = options;
      declarations.linkedSources.clear();
      for (const Shader::LinkedUnit& unit : s.linkedUnits)
        declarations.linkedSources.push_back(prepare(declarationsOnly(unit.source), unit.sourceLine, &unit.source));
      rhi::CompiledShader port = rhi::compileGlslSource(prepare(declarationsOnly(s.source), s.sourceLine, &s.source), script_.file, st, declarations);
      if (port.ok()) {
        declarationPorts_[s.name] = limit;
        return port.spirv;
      }
      // Whether the program links is the driver's to say, which needs no port (linkError).
      std::vector<uint32_t> empty = emptyPort(s.stage);
      if (!expectsLinkError || empty.empty()) throw Unsupported{limit};
      declarationPorts_[s.name] = limit;
      linkOnlyPorts_.insert(s.name);
      return empty;
    }
  }
  if (!c.ok() && s.openGl && expectsLinkError) {
    const std::string limit = "a program that should not link, and that glslang cannot port: " + oneLine(c.error);
    if (std::vector<uint32_t> empty = linkOnlyPort(limit); !empty.empty()) return empty;
    throw Unsupported{limit};
  }
  if (!c.ok()) {
    // An extension the compiler does not know is a limit of this build's glslang, not a broken shader.
    static const std::regex kUnknownExtension(R"(error: '#extension' : extension not supported: (\w+))");
    std::smatch m;
    if (std::regex_search(c.error, m, kUnknownExtension))
      throw Unsupported{"GLSL extension " + m[1].str() + " (unknown to this glslang)"};
    if (s.openGl)
      if (std::optional<std::string> limitation = glslangLimitation(s.source, s.sourceLine, c.error)) throw Unsupported{*limitation};
    // OpenGL GLSL that SPIR-V for Vulkan cannot hold: samplers in structs or constructors, which
    // glslang rejects or turns into a module the validator refuses.
    static const std::regex kInvalidModule(R"(generated SPIR-V is invalid: \[([\w-]+)\])");
    if (s.openGl && std::regex_search(c.error, m, kInvalidModule))
      throw Unsupported{"OpenGL GLSL without a Vulkan SPIR-V form (glslang's module breaks " + m[1].str() + ")"};
    if (s.openGl && c.error.find("'sampler/image' : cannot construct this type") != std::string::npos)
      throw Unsupported{"OpenGL GLSL without a Vulkan SPIR-V form (a sampler in a constructed struct)"};
    throw Failure{"shader '" + s.name + "' does not compile: " + oneLine(c.error)};
  }
  // glViewport sets every viewport, so an OpenGL shader may pick any of OpenGL's 16 or more; the
  // RHI sets as many as the device has (rhi::Capabilities::viewports).
  if (s.openGl && s.stage != Stage::Fragment && outputsBuiltIn(c.spirv, kBuiltInViewportIndex) && dev_.info().caps.viewports < 16)
    throw Unsupported{"gl_ViewportIndex written by the " + s.name + " shader (OpenGL has 16 viewports or more; " + dev_.info().renderer +
                      " on " + dev_.info().backend + " has " + std::to_string(dev_.info().caps.viewports) + ")"};
  return c.spirv;
}

// OpenGL matches one stage's outputs with the next stage's inputs by name (by location where both
// give one); glslang's automatic locations number each stage's own declarations, which agree
// only where both stages declare the same variables in the same order. Each input matched by
// name takes the location of its producer's output.
void ShaderSteps::linkOpenGlVaryings() {
  static const Stage kOrder[] = {Stage::Vertex, Stage::TessControl, Stage::TessEvaluation, Stage::Geometry, Stage::Fragment};
  const Shader* producer = nullptr;
  for (Stage stage : kOrder) {
    const Shader* consumer = nullptr;
    for (const Shader& s : script_.shaders)
      if (s.stage == stage) consumer = &s;
    if (!consumer) continue;
    if (producer && consumer->openGl && (producer->openGl || producer->passthrough)) {
      const std::set<std::string> locatedOutputs = producer->passthrough ? std::set<std::string>{} : explicitlyLocated(producer->source, true);
      const std::set<std::string> locatedInputs = explicitlyLocated(consumer->source, false);
      std::map<std::pair<std::string, bool>, InterfaceVariable> outputs;  // (name, patch)
      for (const InterfaceVariable& v : interfaceVariables(compiled_.at(producer->name)))
        if (v.output) outputs[{v.name, v.patch}] = v;
      std::vector<uint32_t>& spirv = compiled_.at(consumer->name);
      for (const InterfaceVariable& v : interfaceVariables(spirv)) {
        auto out = outputs.find({v.name, v.patch});
        if (v.output || out == outputs.end() || (locatedInputs.count(v.name) && locatedOutputs.count(v.name))) continue;
        spirv[v.locationWord] = out->second.location;
        if (v.componentWord) spirv[v.componentWord] = out->second.component;
      }
    }
    producer = consumer;
  }
}

void ShaderSteps::linkOpenGlBlocks() {
  for (const Shader& s : script_.shaders) {
    if (!s.openGl) continue;
    std::vector<uint32_t>& spirv = compiled_.at(s.name);
    // glslang's relaxed rules gather the atomic counters of OpenGL binding N into the storage
    // block gl_AtomicCounterBlock_N; it moves to binding N of kAtomicCounterSet (renamed: GLSL
    // reserves gl_ names, and the GL backend runs the module as GLSL).
    for (const UniformBlockVariable& v : storageBlocks(spirv)) {
      if (!v.setWord || !v.bindingWord || v.typeName.rfind(kAtomicCounterBlockPrefix, 0) != 0) continue;
      const uint32_t binding = static_cast<uint32_t>(std::stoul(v.typeName.substr(std::strlen(kAtomicCounterBlockPrefix))));
      renameStruct(spirv, v.typeName, "ParityAtomicCounters_" + std::to_string(binding));
      spirv[v.setWord] = kAtomicCounterSet;
      spirv[v.bindingWord] = binding;
      openGlAtomicsOf_[s.name].push_back(binding);
    }
    // Each stage's loose uniforms are a block of their own: named apart, or OpenGL would link
    // the stages' different blocks as one (the GL backend runs the module as GLSL).
    const std::string defaultBlock = looseUniformBlockOf(s);
    renameStruct(spirv, kDefaultUniformBlock, defaultBlock);
    for (const UniformBlockVariable& v : uniformBlocks(spirv)) {
      if (!v.setWord || !v.bindingWord) continue;
      const uint32_t binding = static_cast<uint32_t>(openGlBlocks_.size());  // unless the block is known
      for (uint32_t e = 0; e < v.elements; ++e) {
        std::string key = v.elements > 1 ? v.typeName + "[" + std::to_string(e) + "]" : v.typeName;
        OpenGlBlock& b = openGlBlocks_[key];
        if (b.resource.empty()) {
          b.resource = "uniform block " + key;
          b.typeName = v.typeName;
          b.loose = v.typeName == defaultBlock;
          b.layoutShader = s.name;
          b.binding = e == 0 ? binding : openGlBlocks_.at(v.typeName + "[0]").binding;
          if (v.elements > 1) b.element = e;
        }
        b.bytes.resize(std::max<size_t>({b.bytes.size(), v.size, 4}), 0);
        spirv[v.setWord] = kDefaultUniformSet;
        spirv[v.bindingWord] = b.binding;
        openGlBlocksOf_[s.name].push_back(key);
      }
    }
    for (const SamplerVariable& v : samplerVariables(spirv)) {
      if (!v.setWord || !v.bindingWord) continue;
      const uint32_t binding = static_cast<uint32_t>(openGlSamplers_.size());  // unless the sampler is known
      for (uint32_t e = 0; e < v.elements; ++e) {
        std::string name = v.elements > 1 ? v.name + "[" + std::to_string(e) + "]" : v.name;
        auto it = openGlSamplers_.emplace(name, OpenGlSampler{binding, e, v.storageImage, v.storageImage ? "" : incompleteTextureStandIn(v)}).first;
        spirv[v.setWord] = kOpenGlSamplerSet;
        spirv[v.bindingWord] = it->second.binding;
        openGlSamplersOf_[s.name].push_back(name);
      }
    }
  }
  for (auto& [key, b] : openGlBlocks_) {
    rhi::BufferDesc bd;
    bd.size = b.bytes.size();
    bd.initialData = b.bytes.data();
    bd.label = b.resource;
    Resource r;
    r.buffer = dev_.createBuffer(bd);
    if (!r.buffer) throw Failure{"cannot create the buffer of " + b.resource};
    res_[b.resource] = r;
  }
}

// glslang drops the initialisers of block members (`uniform vec4 c = vec4(1.0);`): the literal
// ones are written into the blocks here.
void ShaderSteps::applyUniformInitializers() {
  for (const Shader& s : script_.shaders) {
    if (!s.openGl || !openGlBlocksOf_.count(s.name)) continue;
    for (const UniformInitialValue& v : uniformInitializers(s.source)) {
      Command c;
      c.loc = {s.sourceLine, 1};
      c.uniform = v.path;
      c.values = v.values;
      setUniform(c);
    }
  }
}

// The pipeline's binds and the uniform blocks of its OpenGL-GLSL shaders.
std::vector<Bind> ShaderSteps::bindsOf(const Pipeline& p) const {
  std::vector<Bind> all = p.binds;
  std::set<std::string> added;
  auto listed = [](const auto& byShader, const std::string& shader) {
    auto it = byShader.find(shader);
    return it == byShader.end() ? typename std::decay_t<decltype(byShader)>::mapped_type{} : it->second;
  };
  for (const std::string& n : p.shaders) {
    if (const Shader* s = script_.findShader(n); s && s->format == "ARB") arbProgramBinds(*s, all);
    for (const std::string& key : listed(openGlBlocksOf_, n)) {
      if (!added.insert(key).second) continue;
      const OpenGlBlock& block = openGlBlocks_.at(key);
      Bind b;
      b.kind = BindKind::Uniform;
      b.buffer = block.resource;
      b.set = kDefaultUniformSet, b.binding = block.binding;
      b.arrayElement = block.element.value_or(0);
      all.push_back(b);
    }
    for (uint32_t binding : listed(openGlAtomicsOf_, n)) {
      if (!added.insert("atomic counters " + std::to_string(binding)).second) continue;
      Bind b;
      b.kind = BindKind::Storage;
      b.set = kAtomicCounterSet, b.binding = binding;
      for (const Buffer& buffer : script_.buffers)
        if (buffer.atomicCounterBinding == static_cast<int>(binding)) b.buffer = buffer.name;
      if (b.buffer.empty() && checkingLink_) continue;
      if (b.buffer.empty())
        throw Failure{"a shader uses atomic counters at binding " + std::to_string(binding) + ", which no `atomic counters` command made"};
      all.push_back(b);
    }
    for (const std::string& name : listed(openGlSamplersOf_, n)) {
      if (!added.insert("sampler " + name).second) continue;
      auto unit = samplerUnit_.find(name);
      const int64_t u = unit == samplerUnit_.end() ? 0 : unit->second;
      const OpenGlSampler& uniform = openGlSamplers_.at(name);
      Bind b;
      b.kind = uniform.image ? BindKind::StorageImage : BindKind::CombinedImageSampler;
      b.set = kOpenGlSamplerSet, b.binding = uniform.binding;
      b.arrayElement = uniform.element;
      for (const Buffer& image : script_.buffers)
        if (uniform.image ? image.imageUnit == u : image.textureUnit == u) b.buffer = image.name;
      for (const Sampler& sampler : script_.samplers)
        if (sampler.textureUnit == u && !uniform.image) b.sampler = sampler.name;
      if (b.buffer.empty() && checkingLink_) continue;  // linking reads no texture; the defaults stand in
      if (b.buffer.empty() && !uniform.image) b.buffer = uniform.standIn;
      if (b.buffer.empty() && uniform.image)
        throw Failure{"image '" + name + "' reads image unit " + std::to_string(u) + ", to which no `image texture` command bound a texture"};
      if (b.buffer.empty())
        throw Failure{"sampler '" + name + "' reads texture unit " + std::to_string(u) + ", which no texture command filled"};
      all.push_back(b);
    }
    for (const Shader& s : script_.shaders)
      if (s.name == n && s.openGlSpirv) addOpenGlSpirvSamplers(s, all, added);
  }
  return all;
}

void ShaderSteps::addOpenGlSpirvSamplers(const Shader& s, std::vector<Bind>& binds, std::set<std::string>& added) const {
  rhi::ShaderReflection reflection;
  std::string error;
  if (!reflectSpirv(compiled_.at(s.name), rhiStage(s.stage), &reflection, &error)) return;  // the pipeline reports it
  for (const rhi::ShaderResource& r : reflection.resources) {
    if (r.kind != rhi::BindingKind::SampledTexture) continue;
    for (uint32_t e = 0; e < r.arraySize; ++e) {
      const int unit = static_cast<int>(r.binding + e);
      if (!added.insert("texture unit " + std::to_string(unit)).second) continue;
      Bind b;
      b.kind = BindKind::CombinedImageSampler;
      b.set = 0, b.binding = r.binding;
      b.arrayElement = e;
      for (const Buffer& image : script_.buffers)
        if (image.textureUnit == unit) b.buffer = image.name;
      for (const Sampler& sampler : script_.samplers)
        if (sampler.textureUnit == unit) b.sampler = sampler.name;
      if (b.buffer.empty() && checkingLink_) continue;
      if (b.buffer.empty())
        throw Failure{"shader '" + s.name + "': the sampler at binding " + std::to_string(r.binding) +
                      (r.arraySize > 1 ? " (element " + std::to_string(e) + ")" : "") + " reads texture unit " + std::to_string(unit) +
                      ", which no texture command filled"};
      binds.push_back(b);
    }
  }
}

// Where `name` lies in block `b`, if there ("Block.member" names a member of a named block).
std::optional<UniformSlot> ShaderSteps::uniformIn(const OpenGlBlock& b, const std::string& name) const {
  std::string path = name;
  if (!b.loose && path.rfind(b.typeName + ".", 0) == 0) path = path.substr(b.typeName.size() + 1);
  return findUniform(compiled_.at(b.layoutShader), b.typeName, path);
}

// `uniform TYPE NAME values`: written wherever a block holds NAME (a member of a block may be
// named "Block.member"); a name no block holds was optimised away, as OpenGL drivers do.
void ShaderSteps::setUniform(const Command& c) {
  // A sampler uniform holds its texture unit; an array's name alone is its element 0.
  for (const std::string& name : {c.uniform, c.uniform + "[0]"})
    if (openGlSamplers_.count(name)) {
      samplerUnit_[name] = c.values.empty() ? 0 : c.values[0].i;
      return;
    }
  for (auto& [key, b] : openGlBlocks_) {
    if (b.element && *b.element != c.arrayElement) continue;  // piglit's `ubo array index`
    auto slot = uniformIn(b, c.uniform);
    if (!slot) continue;
    const uint32_t perElement = slot->rows * slot->columns;
    if (c.values.size() > size_t(perElement) * slot->elements)
      throw Failure{lineOf(c.loc) + ": " + std::to_string(c.values.size()) + " values for uniform '" + c.uniform + "'"};
    const uint32_t scalarBytes = scalarSize(slot->scalar);
    for (size_t i = 0; i < c.values.size(); ++i) {
      uint32_t element = static_cast<uint32_t>(i / perElement), k = static_cast<uint32_t>(i % perElement);
      uint32_t column = k / slot->rows, row = k % slot->rows;
      // Values are given column by column; a row-major matrix's stride separates its rows.
      const size_t across = slot->rowMajor ? row : column, along = slot->rowMajor ? column : row;
      size_t at = slot->offset + size_t(element) * slot->arrayStride + across * slot->matrixStride + along * scalarBytes;
      if (at + scalarBytes > b.bytes.size()) throw Failure{lineOf(c.loc) + ": uniform '" + c.uniform + "' lies outside its block"};
      storeValue(b.bytes, at, slot->scalar, c.values[i]);
    }
    dev_.writeBuffer(res_.at(b.resource).buffer, 0, b.bytes.data(), b.bytes.size());
  }
}

// piglit's `active uniform NAME PNAME VALUE`: OpenGL reports a uniform's layout in its block as
// the module lays it out. A loose uniform is in no block, where OpenGL reports -1 (and not row
// major); here the loose ones share a block of their own, which OpenGL would not report. Its type
// is the module's (opengl_uniform_types.h), its size the elements of the array it names (1: none).
ExpectResult ShaderSteps::activeUniform(const Command& c) {
  ExpectResult e;
  e.line = c.loc.line;
  const std::string what = "line " + std::to_string(c.loc.line) + ": active uniform " + c.uniform + " " + c.other;
  std::optional<UniformSlot> slot;
  bool loose = false;
  for (const auto& [key, b] : openGlBlocks_) {
    if ((slot = uniformIn(b, c.uniform))) {
      loose = b.loose;
      break;
    }
  }
  std::string type;
  int64_t elements = 1;
  if (slot) {
    type = openGlValueTypeName(slot->scalar, slot->rows, slot->columns).value_or("a type without an OpenGL name");
    elements = slot->elements;
  } else {
    const std::optional<OpaqueUniform> opaque = opaqueUniform(c.uniform);
    if (!opaque) throw Failure{what + ": no active uniform of that name"};
    loose = true;
    type = opaque->type;
    elements = opaque->elements;
  }
  if (c.other == "GL_UNIFORM_TYPE") {
    // What the port cannot tell apart: glslang stores a block's bools as 32-bit unsigned
    // integers, and the port's rectangle textures are 2D ones.
    const bool unsignedInt = type.rfind("GL_UNSIGNED_INT", 0) == 0, expectsBool = c.typeName.rfind("GL_BOOL", 0) == 0;
    if (unsignedInt && expectsBool && type.substr(std::strlen("GL_UNSIGNED_INT")) == c.typeName.substr(std::strlen("GL_BOOL")))
      throw Unsupported{"active uniform " + c.uniform + " GL_UNIFORM_TYPE " + c.typeName + " (line " + std::to_string(c.loc.line) +
                        "): the port holds a bool as a 32-bit unsigned integer, as glslang stores it"};
    if (c.typeName.find("_RECT") != std::string::npos)
      throw Unsupported{"active uniform " + c.uniform + " GL_UNIFORM_TYPE " + c.typeName + " (line " + std::to_string(c.loc.line) +
                        "): the port samples a rectangle texture as a 2D one"};
    e.pass = type == c.typeName;
    e.message = what + (e.pass ? ": ok" : ": expected " + c.typeName + ", got " + type);
    return e;
  }
  int64_t actual = 0;
  if (c.other == "GL_UNIFORM_SIZE") actual = elements;
  else if (!slot) actual = c.other == "GL_UNIFORM_IS_ROW_MAJOR" ? 0 : -1;  // a sampler or image: in no block
  else if (c.other == "GL_UNIFORM_OFFSET") actual = loose ? -1 : int64_t(slot->offset);
  else if (c.other == "GL_UNIFORM_ARRAY_STRIDE") actual = loose ? -1 : int64_t(slot->arrayStride);
  else if (c.other == "GL_UNIFORM_MATRIX_STRIDE") actual = loose ? -1 : slot->columns > 1 ? int64_t(slot->matrixStride) : 0;
  else if (c.other == "GL_UNIFORM_IS_ROW_MAJOR") actual = !loose && slot->columns > 1 && slot->rowMajor;
  e.pass = actual == c.values.at(0).i;
  e.message = what + (e.pass ? ": ok" : ": expected " + std::to_string(c.values[0].i) + ", got " + std::to_string(actual));
  return e;
}

// The sampler or image uniform `name` ("s", or "s[0]" for an array's, as OpenGL names it): its
// type from the module of a shader that declares it, and its elements.
std::optional<ShaderSteps::OpaqueUniform> ShaderSteps::opaqueUniform(const std::string& name) const {
  const std::string base = name.size() > 3 && name.compare(name.size() - 3, 3, "[0]") == 0 ? name.substr(0, name.size() - 3) : name;
  if (!openGlSamplers_.count(name) && !openGlSamplers_.count(base + "[0]")) return std::nullopt;
  OpaqueUniform u;
  u.elements = 0;
  while (openGlSamplers_.count(base + "[" + std::to_string(u.elements) + "]")) ++u.elements;
  u.elements = std::max<int64_t>(u.elements, 1);
  for (const auto& [shader, names] : openGlSamplersOf_) {
    if (std::find(names.begin(), names.end(), name) == names.end() && std::find(names.begin(), names.end(), base + "[0]") == names.end())
      continue;
    if (std::optional<std::string> type = openGlOpaqueTypeName(compiled_.at(shader), base)) {
      u.type = *type;
      return u;
    }
  }
  throw Unsupported{"the OpenGL type of sampler or image '" + name + "' (its SPIR-V image type has no OpenGL name here)"};
}

// A SPIR-V extension that Vulkan 1.3 has not made core needs the device extension that brings
// it: SPV_<VENDOR>_<name> comes with VK_<VENDOR>_<name> or VK_<VENDOR>_shader_<name>.
void ShaderSteps::requireSpirvExtension(const std::string& extension) {
  static const std::set<std::string> kCore = {
      "SPV_KHR_shader_draw_parameters", "SPV_KHR_16bit_storage", "SPV_KHR_8bit_storage", "SPV_KHR_variable_pointers",
      "SPV_KHR_storage_buffer_storage_class", "SPV_KHR_device_group", "SPV_KHR_multiview", "SPV_KHR_float_controls",
      "SPV_KHR_vulkan_memory_model", "SPV_KHR_physical_storage_buffer", "SPV_EXT_physical_storage_buffer",
      "SPV_KHR_terminate_invocation", "SPV_EXT_demote_to_helper_invocation", "SPV_KHR_integer_dot_product",
      "SPV_KHR_non_semantic_info", "SPV_EXT_descriptor_indexing", "SPV_EXT_shader_viewport_index_layer",
      "SPV_KHR_no_integer_wrap_decoration"};
  // Those the RHI rewrites away on every device (rhi/spirv_lowering.h).
  static const std::set<std::string> kLowered = {"SPV_AMD_shader_trinary_minmax"};
  if (kCore.count(extension) || kLowered.count(extension) || extension.rfind("SPV_", 0) != 0) return;
  size_t vendorEnd = extension.find('_', 4);
  if (vendorEnd == std::string::npos) return;
  const std::string vendor = extension.substr(4, vendorEnd - 4), name = extension.substr(vendorEnd + 1);
  const std::vector<std::string>& offered = dev_.info().extensions;
  for (const std::string& candidate : {"VK_" + vendor + "_" + name, "VK_" + vendor + "_shader_" + name})
    if (std::find(offered.begin(), offered.end(), candidate) != offered.end()) return;
  throw Unsupported{"SPIR-V extension " + extension + " (no VK_" + vendor + "_[shader_]" + name + " on " + dev_.info().backend + " " +
                    dev_.info().renderer + ")"};
}

// Outputs past the stage's output locations are not a valid pipeline (VUID-RuntimeSpirv-Location-06272;
// OpenGL refuses to link them); drivers may crash on them, so the case is a SKIP naming the limit.
// glslang numbers a tessellation control shader's patch outputs after its per-vertex ones, as
// Vulkan's shared locations need, where OpenGL would count the two apart.
void ShaderSteps::requireOutputLocations(const Shader& s, const std::vector<uint32_t>& module) {
  const rhi::ShaderStage stage = rhiStage(s.stage);
  const uint32_t limit = dev_.info().caps.maxOutputLocations[size_t(stage)];
  if (limit == 0) return;
  const OutputExtent extent = outputExtent(module, stage == rhi::ShaderStage::TessControl);
  if (extent.end <= limit) return;
  throw Unsupported{"shader '" + s.name + "' writes output '" + extent.name + "' up to location " + std::to_string(extent.end - 1) +
                    "; the device has " + std::to_string(limit) + " output locations for the stage (" + dev_.info().backend + " on " +
                    dev_.info().renderer + ")"};
}

void ShaderSteps::requireShaderSupport(const std::vector<uint32_t>& module) {
  for (const std::string& extension : spirvExtensions(module)) requireSpirvExtension(extension);
  if (usesSubgroupOperations(module) && !dev_.info().caps.subgroups)
    throw Unsupported{"subgroup operations (no GL_KHR_shader_subgroup on " + dev_.info().renderer + ")"};
}

std::vector<rhi::ShaderHandle> ShaderSteps::makeShaders(const Pipeline& p) {
  std::vector<std::vector<uint32_t>> modules;
  std::vector<const Shader*> defs;
  for (const std::string& n : p.shaders) {
    const Shader* s = script_.findShader(n);
    defs.push_back(s);
    modules.push_back(compiled_.at(n));
    auto passes = p.optimizations.find(n);
    if (passes != p.optimizations.end()) optimizeSpirv(modules.back(), passes->second, n);
  }
  for (const Shader* s : defs)
    if (auto d = declarationPorts_.find(s->name);
        d != declarationPorts_.end() && (!runsOpenGlGlsl(p) || (linkOnlyPorts_.count(s->name) && !checkingLink_)))
      throw Unsupported{d->second};
  if (!runsOpenGlGlsl(p))  // the driver counts its own locations
    for (size_t i = 0; i < modules.size(); ++i) requireOutputLocations(*defs[i], modules[i]);
  for (const auto& m : modules)
    for (const DescriptorArray& a : descriptorArrays(m)) {
      if (a.nested || a.elements == 0 || a.elements > rhi::kMaxArrayElements)
        throw Unsupported{"descriptor array '" + a.name + "' " +
                          (a.nested ? std::string("of arrays") : a.elements == 0 ? std::string("without a constant size")
                                                                                 : "of " + std::to_string(a.elements) + " elements") +
                          " (the RHI binds one-dimensional arrays of 1.." + std::to_string(rhi::kMaxArrayElements) + ")"};
      if (a.samplers && !dev_.info().caps.separateSamplerArrays)
        throw Unsupported{"array of separate samplers '" + a.name + "' (no such GLSL on " + dev_.info().backend + ")"};
    }
  auto& map = bindingMap(p, modules);
  std::map<uint32_t, std::set<uint32_t>> boundElements;  // RHI binding -> elements the script binds
  for (const Bind& b : bindsOf(p))
    if (b.kind != BindKind::Color && b.kind != BindKind::DepthStencil && b.kind != BindKind::Resolve &&
        b.kind != BindKind::PushConstant && map.count({b.set, b.binding}))
      boundElements[map.at({b.set, b.binding})].insert(b.arrayElement);
  std::vector<rhi::ShaderHandle> out;
  for (size_t i = 0; i < defs.size(); ++i) {
    remapSpirv(modules[i], map);
    defaultBindings(p, modules[i], rhiStage(defs[i]->stage), boundElements);
    auto spec = p.specializations.find(defs[i]->name);
    if (spec != p.specializations.end()) specializeSpirv(modules[i], spec->second, defs[i]->name);
    rhi::ShaderDesc sd;
    sd.stage = rhiStage(defs[i]->stage);
    sd.spirv = modules[i];
    auto ep = p.entryPoints.find(defs[i]->name);
    if (ep != p.entryPoints.end()) sd.entryPoint = ep->second;
    sd.label = defs[i]->name;
    if (defs[i]->format == "ARB" && driverLoadsArbPrograms()) sd.arbProgram = defs[i]->source;
    if (runsOpenGlGlsl(p)) {
      sd.openGlGlsl = openGlSources(*defs[i], p);
      sd.looseUniformBlock = looseUniformBlockOf(*defs[i]);
    }
    rhi::ShaderHandle h = dev_.createShader(sd);
    if (!h) throw Failure{"cannot create shader '" + defs[i]->name + "'" + deviceLog()};
    shaders_.push_back(h);
    out.push_back(h);
  }
  return out;
}

// A binding a shader declares and the script leaves unbound is left unwritten by Amber: a shader
// that runs does not read it. The RHI needs every binding, so it gets a zeroed resource of its
// kind (pipeline defaults_, bound before the script's binds). An array the script binds only
// some elements of is a SKIP: what the others read is the peer runner's accident.
void ShaderSteps::defaultBindings(const Pipeline& p, const std::vector<uint32_t>& spirv, rhi::ShaderStage stage,
                                  const std::map<uint32_t, std::set<uint32_t>>& boundElements) {
  rhi::ShaderReflection reflection;
  std::string error;
  if (!rhi::reflectSpirv(spirv, stage, &reflection, &error)) return;  // createShader reports it
  uint32_t& pushBytes = pushConstantSizes_[p.name];
  pushBytes = std::max(pushBytes, reflection.pushConstantSize);
  for (const rhi::ShaderResource& r : reflection.resources) {
    auto bound = boundElements.find(r.binding);
    if (bound != boundElements.end()) {
      for (uint32_t e = 0; e < r.arraySize; ++e)
        if (!bound->second.count(e))
          throw Unsupported{"pipeline '" + p.name + "' binds elements of descriptor array '" + r.name + "' of " +
                            std::to_string(r.arraySize) + " but not element " + std::to_string(e)};
      continue;
    }
    for (uint32_t e = 0; e < r.arraySize; ++e) {
      rhi::ResourceBinding d;
      d.binding = r.binding;
      d.arrayElement = e;
      d.kind = r.kind;
      switch (r.kind) {
        case rhi::BindingKind::UniformBuffer:
        case rhi::BindingKind::StorageBuffer:
          d.buffer = zeroBuffer();
          break;
        case rhi::BindingKind::UniformTexelBuffer:
        case rhi::BindingKind::StorageTexelBuffer:
          d.buffer = zeroBuffer();
          d.texelFormat = r.integer ? rhi::Format::R32_UINT : rhi::Format::R32F;
          break;
        case rhi::BindingKind::SeparateSampler:
          break;  // the null sampler: the RHI's default
        default:
          throw Unsupported{"pipeline '" + p.name + "' binds nothing at the texture '" + r.name +
                            "' a shader declares (the runner's zeroed defaults are buffers and samplers)"};
      }
      auto& defaults = defaults_[p.name];
      if (std::none_of(defaults.begin(), defaults.end(), [&](const rhi::ResourceBinding& o) {
            return o.binding == d.binding && o.arrayElement == d.arrayElement;
          }))
        defaults.push_back(d);
    }
  }
}

}  // namespace parity::harness::script::runner
