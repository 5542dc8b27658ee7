// piglit's SPIR-V programs ([require] SPIRV YES|ONLY, GL_ARB_gl_spirv): their [X shader
// specializations] sections and [test] commands. The modules need not carry names, so piglit
// finds a block by its binding: `block binding|offset|array index|matrix stride|row major N` say
// where the next `uniform TYPE NAME values` goes (NAME is a comment then) and which block a
// `verify program_interface_query` asks about (shader_runner.c, force_no_names).
#include "harness/scripts/shader_test/steps.h"

#include <cstring>
#include <set>

namespace parity::harness::script::shader_test {

namespace {

int64_t integerOperand(const std::string& text, int line, const std::string& what, int64_t least) {
  Value v;
  if (!parseNumber(text, &v) || !v.isInteger || v.i < least)
    throw ShaderTestError{line, what + " takes an integer" + (least >= 0 ? " >= " + std::to_string(least) : "") + ", got '" + text + "'"};
  return v.i;
}

}  // namespace

// piglit: each line `TYPE SPEC_ID VALUE` gives the SpecId's constant its value when the module
// is specialized (glSpecializeShader); 32-bit types only (what the runner writes into the module).
void SectionSteps::specializations(const Section& s, const std::string& shaderName) {
  for (const auto& [line, text] : s.lines) {
    const std::vector<std::string> w = words(uncommented(text));
    if (w.empty()) continue;
    if (w.size() != 3) error(line, "expected TYPE SPEC_ID VALUE, got '" + trim(text) + "'");
    const uint32_t id = static_cast<uint32_t>(integerOperand(w[1], line, "a specialization's SpecId", 0));
    Value v;
    if (!parseNumber(w[2], &v)) error(line, "expected a number, got '" + w[2] + "'");
    uint32_t bits = 0;
    if (w[0] == "float") {
      applyHexFloatBits(w[2], Scalar::Float32, &v);  // 0x... is the float's bits
      const float f = static_cast<float>(v.d);
      std::memcpy(&bits, &f, sizeof bits);
    } else if (w[0] == "uint" || w[0] == "int" || w[0] == "bool") {
      if (!v.isInteger) error(line, w[0] + " specialization needs an integer, got '" + w[2] + "'");
      bits = static_cast<uint32_t>(v.i);
    } else {
      unsupported(line, "[" + s.name + "] of type " + w[0] + " (32-bit constants only)");
      continue;
    }
    specializations_[shaderName][id] = bits;
  }
}

void ProbeCommands::blockPosition(int line, const std::vector<std::string>& w) {
  const std::string what = w.size() >= 3 && (w[1] == "array" || w[1] == "matrix" || w[1] == "row") ? w[1] + " " + w[2] : w.size() >= 2 ? w[1] : "";
  const size_t words = what.find(' ') == std::string::npos ? 3 : 4;
  if (w.size() != words) error(line, "expected block binding|offset|array index|matrix stride|row major N");
  const std::string& operand = w.back();
  if (what == "binding") block_.binding = integerOperand(operand, line, "block binding", 0);
  else if (what == "offset") block_.offset = integerOperand(operand, line, "block offset", 0);
  else if (what == "array index") block_.arrayIndex = integerOperand(operand, line, "block array index", 0);
  else if (what == "matrix stride") block_.matrixStride = integerOperand(operand, line, "block matrix stride", 0);
  else if (what == "row major") block_.rowMajor = integerOperand(operand, line, "block row major", 0) != 0;
  else error(line, "unknown block command 'block " + what + "' (binding, offset, array index, matrix stride, row major)");
}

// The values go to the uniform block at OpenGL binding `block binding` (element `block array
// index` of an array of blocks), from byte `block offset`; a matrix's columns (rows with `block
// row major 1`) `block matrix stride` apart. Only what the values cover is written, as piglit
// writes it.
void ProbeCommands::setBlockUniform(int line, const std::vector<std::string>& w) {
  if (!w[2].empty() && std::isdigit(static_cast<unsigned char>(w[2][0])))
    return unsupported(line, "uniform " + w[1] + " at location " + w[2] + " (a loose uniform of a SPIR-V program: no default uniform block on Vulkan)");
  if (block_.binding < 0) error(line, "uniform " + w[2] + " of a SPIR-V program needs a `block binding` first");
  if (block_.offset < 0) error(line, "uniform " + w[2] + " of a SPIR-V program needs a `block offset` first");
  ElementType type = valueType(line, w[1], false);
  std::vector<Value> values = typedNumbers(line, w, 3, type);
  if (values.size() != type.layout.fields.size())
    error(line, "uniform " + w[1] + " takes " + std::to_string(type.layout.fields.size()) + " values, got " + std::to_string(values.size()));
  std::vector<uint8_t> bytes;
  if (type.columns > 1) {
    if (block_.matrixStride <= 0) return unsupported(line, "uniform " + w[1] + " without a `block matrix stride`");
    const uint32_t scalar = scalarSize(type.layout.fields[0].scalar), stride = static_cast<uint32_t>(block_.matrixStride);
    for (uint32_t c = 0; c < type.columns; ++c)
      for (uint32_t r = 0; r < type.rows; ++r)
        storeValue(bytes, block_.rowMajor ? r * stride + c * scalar : c * stride + r * scalar, type.layout.fields[c * type.rows + r].scalar,
                   values[c * type.rows + r]);
  } else {
    bytes = pack(type, values);
  }
  const uint64_t offset = static_cast<uint64_t>(block_.offset);
  std::string where = "0:" + std::to_string(block_.binding);
  if (block_.arrayIndex > 0) where += ":" + std::to_string(block_.arrayIndex);
  Command c;
  c.kind = Command::Kind::WriteBuffer;
  c.loc = {line, 1};
  c.buffer = bufferFor(line, "ubo", where, offset + bytes.size());
  c.px = static_cast<uint32_t>(offset);
  c.bytes = std::move(bytes);
  script_.commands.push_back(c);
}

// verify program_interface_query GL_UNIFORM_BLOCK|GL_SHADER_STORAGE_BLOCK NAME PNAME VALUE (the
// block at `block binding`, NAME a comment) and verify program_query PNAME VALUE: the answers the
// modules themselves give (the runner reads them); other queries are named unsupported.
void ProbeCommands::verifyProgramQuery(int line, const std::vector<std::string>& w) {
  static const std::set<std::string> kBlockProperties = {"GL_NUM_ACTIVE_VARIABLES", "GL_BUFFER_DATA_SIZE", "GL_BUFFER_BINDING"};
  static const std::set<std::string> kProgramProperties = {"GL_ACTIVE_UNIFORMS", "GL_ACTIVE_UNIFORM_BLOCKS"};
  Command c;
  c.kind = Command::Kind::ExpectProgramQuery;
  c.loc = {line, 1};
  if (w[1] == "program_interface_query") {
    if (w.size() != 6) return unsupported(line, "verify program_interface_query " + (w.size() > 2 ? w[2] : std::string()) + " (only by block binding)");
    if (w[2] != "GL_UNIFORM_BLOCK" && w[2] != "GL_SHADER_STORAGE_BLOCK") return unsupported(line, "verify program_interface_query " + w[2]);
    if (!kBlockProperties.count(w[4])) return unsupported(line, "verify program_interface_query " + w[2] + " " + w[4]);
    if (block_.binding < 0) error(line, "verify program_interface_query of a SPIR-V program needs a `block binding` first");
    c.programInterface = w[2];
    c.uniform = w[3];
    c.other = w[4];
    c.blockBinding = block_.binding;
  } else {
    if (w.size() != 4) error(line, "expected verify program_query PNAME VALUE");
    if (!kProgramProperties.count(w[2])) return unsupported(line, "verify program_query " + w[2]);
    c.other = w[2];
  }
  c.values = {Value{}};
  c.values[0].isInteger = true;
  c.values[0].i = integerOperand(w.back(), line, "verify " + w[1] + " " + c.other, 0);
  c.values[0].d = static_cast<double>(c.values[0].i);
  script_.commands.push_back(c);
}

}  // namespace parity::harness::script::shader_test
