// ARB assembly programs (piglit's [vertex program] and [fragment program]): a device with an
// assembly program path (GL) loads the text (rhi::ShaderDesc::arbProgram) beside a port that only
// places it in the RHI's binding model; any other device runs the program's translation to GLSL
// (arb_program_glsl.h), which reads OpenGL's state from a uniform block per stage. The runner
// binds the textures of the units a program reads and keeps the state that piglit's `parameter`,
// `ortho`, `frustum`, `color` and `texcoord` set for the draws, for the device or the blocks.
#include "harness/scripts/runner/steps.h"

#include <cstring>
#include <regex>

#include "harness/io/text.h"
#include "harness/scripts/arb_program_glsl.h"
#include "rhi/shader_compiler.h"

namespace parity::harness::script::runner {

namespace {

// The texture units a program reads (`TEX r, c, texture[N], 2D;`, `texture` alone being unit 0)
// and the sampler type of the port for each: the target the instruction names.
std::map<uint32_t, std::string> texturesRead(const Shader& s) {
  static const std::map<std::string, std::string> kSamplerTypes = {
      {"1D", "sampler1D"}, {"2D", "sampler2D"}, {"3D", "sampler3D"}, {"CUBE", "samplerCube"},
      {"SHADOW1D", "sampler1DShadow"}, {"SHADOW2D", "sampler2DShadow"}};
  static const std::regex kComment(R"(#[^\n]*)");
  static const std::regex kTextureUse(R"(\btexture\s*(?:\[\s*(\d+)\s*\])?\s*,\s*(\w+))");
  const std::string code = std::regex_replace(s.source, kComment, "");
  std::map<uint32_t, std::string> units;
  for (auto m = std::sregex_iterator(code.begin(), code.end(), kTextureUse); m != std::sregex_iterator(); ++m) {
    const uint32_t unit = (*m)[1].matched ? static_cast<uint32_t>(std::stoul((*m)[1].str())) : 0;
    const std::string target = (*m)[2].str();
    auto type = kSamplerTypes.find(target);
    if (type == kSamplerTypes.end())
      throw Unsupported{"texture target " + target + " in an ARB assembly program (the RHI's textures have no such form)"};
    if (unit >= rhi::kMaxBindings) throw Unsupported{"texture unit " + std::to_string(unit) + " in an ARB assembly program"};
    auto [at, added] = units.emplace(unit, type->second);
    if (!added && at->second != type->second)
      throw Unsupported{"texture unit " + std::to_string(unit) + " read as two targets by an ARB assembly program"};
  }
  return units;
}

// The translations' state blocks: past every texture unit's binding, one per stage.
uint32_t stateBinding(Stage stage) { return rhi::kMaxBindings + (stage == Stage::Fragment ? 1 : 0); }
std::string stateResource(Stage stage) {
  return std::string("ARB program state of the ") + (stage == Stage::Vertex ? "vertex" : "fragment") + " program";
}

}  // namespace

bool ShaderSteps::driverLoadsArbPrograms() const {
  const std::vector<std::string>& features = dev_.info().features;
  return std::find(features.begin(), features.end(), "arbAssemblyPrograms") != features.end();
}

std::vector<uint32_t> ShaderSteps::arbProgramTranslation(const Shader& s) {
  ArbProgramGlsl t = translateArbProgram(s.source, 0, stateBinding(s.stage));
  if (!t.unsupported.empty())
    throw Unsupported{"ARB assembly program '" + s.name + "': " + t.unsupported + " (not in its translation to GLSL, which " +
                      dev_.info().backend + " runs)"};
  rhi::CompiledShader c = rhi::compileGlslSource(t.glsl, script_.file, rhiStage(s.stage), {});
  if (!c.ok()) throw Failure{"the GLSL translation of ARB assembly program '" + s.name + "' does not compile: " + oneLine(c.error)};
  arbTexturesOf_[s.name] = t.textures;
  arbStateBlocks_[s.stage] = t.state;
  Resource& r = res_[stateResource(s.stage)];
  if (r.buffer) dev_.destroy(r.buffer);
  rhi::BufferDesc bd;
  bd.size = t.state.bytes();
  bd.label = stateResource(s.stage);
  r.buffer = dev_.createBuffer(bd);
  if (!r.buffer) throw Failure{"cannot create the buffer of " + bd.label};
  writeArbStateBlocks();
  return c.spirv;
}

// The state a translation reads, as the device path has it: OpenGL's initial current colour
// (1, 1, 1, 1), secondary colour and texture coordinates (0, 0, 0, 1), an identity model-view.
void ShaderSteps::writeArbStateBlocks() {
  static constexpr float kIdentity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  static constexpr float kNone[4] = {0, 0, 0, 1}, kWhite[4] = {1, 1, 1, 1};
  for (const auto& [stage, block] : arbStateBlocks_) {
    std::vector<uint8_t> bytes(block.bytes(), 0);
    auto put = [&](size_t offset, const float* v, size_t n) { std::memcpy(bytes.data() + offset, v, n * sizeof(float)); };
    put(ArbStateBlock::kModelView, kIdentity, 16);
    put(ArbStateBlock::kProjection, projection_.data(), 16);
    put(ArbStateBlock::kColor, kWhite, 4);
    put(ArbStateBlock::kSecondaryColor, kNone, 4);
    for (size_t unit = 0; unit < 8; ++unit) put(ArbStateBlock::kTexCoords + 16 * unit, kNone, 4);
    for (const auto& [key, value] : currentAttributes_) {
      const auto& [attribute, index] = key;
      if (attribute == rhi::Device::CurrentAttribute::Color && index == 0) put(ArbStateBlock::kColor, value.data(), 4);
      if (attribute == rhi::Device::CurrentAttribute::TexCoord && index < 8) put(ArbStateBlock::kTexCoords + 16 * index, value.data(), 4);
    }
    for (const auto& [key, value] : programParameters_) {
      const auto& [parameterStage, local, index] = key;
      if (parameterStage != stage || index >= (local ? block.localCount : block.envCount)) continue;
      put((local ? block.localOffset() : ArbStateBlock::kEnv) + 16 * size_t(index), value.data(), 4);
    }
    dev_.writeBuffer(res_.at(stateResource(stage)).buffer, 0, bytes.data(), bytes.size());
  }
}

std::vector<uint32_t> ShaderSteps::arbProgramPort(const Shader& s) {
  if (!driverLoadsArbPrograms()) return arbProgramTranslation(s);
  const std::map<uint32_t, std::string> units = texturesRead(s);
  arbTexturesOf_[s.name] = units;
  // The port declares what places the program: its vertex input at location 0 (vertex.position,
  // which piglit's `draw rect` feeds) and its units as samplers, each read so that it stays.
  std::string src = "#version 450\n", reads = "0.0";
  for (const auto& [unit, type] : units) {
    const std::string name = "parity_texture_" + std::to_string(unit);
    src += "layout(binding = " + std::to_string(unit) + ") uniform " + type + " " + name + ";\n";
    reads += " + float(textureSize(" + name + ", 0)" + (type.find("1D") != std::string::npos ? ")" : ".x)");
  }
  if (s.stage == Stage::Vertex)
    src += "layout(location = 0) in vec4 parity_Vertex;\nvoid main() { gl_Position = parity_Vertex + vec4(" + reads + "); }\n";
  else
    src += "layout(location = 0) out vec4 parity_FragColor;\nvoid main() { parity_FragColor = vec4(" + reads + "); }\n";
  rhi::CompiledShader c = rhi::compileGlslSource(src, script_.file, rhiStage(s.stage), {});
  if (!c.ok()) throw Failure{"the port of ARB assembly program '" + s.name + "' does not compile: " + oneLine(c.error)};
  return c.spirv;
}

void ShaderSteps::arbProgramBinds(const Shader& s, std::vector<Bind>& binds) const {
  if (!driverLoadsArbPrograms() && res_.count(stateResource(s.stage))) {
    Bind state;
    state.kind = BindKind::Uniform;
    state.set = 0, state.binding = stateBinding(s.stage);
    state.buffer = stateResource(s.stage);
    binds.push_back(state);
  }
  auto units = arbTexturesOf_.find(s.name);
  if (units == arbTexturesOf_.end()) return;
  for (const auto& [unit, type] : units->second) {
    Bind b;
    b.kind = BindKind::CombinedImageSampler;
    b.set = 0, b.binding = unit;
    for (const Buffer& image : script_.buffers)
      if (image.textureUnit == static_cast<int>(unit)) b.buffer = image.name;
    for (const Sampler& sampler : script_.samplers)
      if (sampler.textureUnit == static_cast<int>(unit)) b.sampler = sampler.name;
    if (b.buffer.empty())
      throw Failure{"ARB assembly program '" + s.name + "' reads texture unit " + std::to_string(unit) + ", which no texture command filled"};
    binds.push_back(b);
  }
}

void ShaderSteps::setArbProgramState(const Command& c) {
  if (c.kind == Command::Kind::LoadProjection) {
    for (size_t i = 0; i < projection_.size() && i < c.values.size(); ++i) projection_[i] = static_cast<float>(c.values[i].d);
    writeArbStateBlocks();
    return;
  }
  if (c.kind == Command::Kind::CurrentAttribute) {
    const auto attribute = c.other == "color" ? rhi::Device::CurrentAttribute::Color : rhi::Device::CurrentAttribute::TexCoord;
    std::array<float, 4>& value = currentAttributes_[{attribute, c.px}];
    for (size_t i = 0; i < 4 && i < c.values.size(); ++i) value[i] = static_cast<float>(c.values[i].d);
    writeArbStateBlocks();
    return;
  }
  const Stage stage = c.other.size() > 3 && c.other.compare(c.other.size() - 3, 3, "_vp") == 0 ? Stage::Vertex : Stage::Fragment;
  std::array<float, 4>& value = programParameters_[{stage, c.other.rfind("local", 0) == 0, c.px}];
  for (size_t i = 0; i < 4 && i < c.values.size(); ++i) value[i] = static_cast<float>(c.values[i].d);
  writeArbStateBlocks();
}

void ShaderSteps::applyArbProgramState(const Pipeline& p) {
  if (std::none_of(p.shaders.begin(), p.shaders.end(), [&](const std::string& n) { return script_.findShader(n)->format == "ARB"; }))
    return;
  static constexpr std::array<float, 16> kIdentity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  dev_.setTransformMatrices(kIdentity, projection_);  // piglit loads no model-view matrix
  for (const auto& [key, value] : programParameters_) {
    const auto& [stage, local, index] = key;
    dev_.setProgramParameter(rhiStage(stage), local, index, value);
  }
  for (const auto& [key, value] : currentAttributes_) dev_.setCurrentAttribute(key.first, key.second, value);
}

}  // namespace parity::harness::script::runner
