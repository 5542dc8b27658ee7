// piglit's `verify program_interface_query` and `verify program_query` for SPIR-V programs
// (GL_ARB_gl_spirv), answered from the modules as OpenGL's SPIR-V linking rules derive them:
// a block's size from its explicit offsets and strides, its active variables from its type, with
// no names involved (Mesa's gl_nir_link_uniform_blocks and the ARB_gl_spirv specification).
#include "harness/scripts/runner/steps.h"

#include <algorithm>
#include <functional>
#include <map>
#include <optional>
#include <set>

#include "rhi/shader_reflection.h"

namespace parity::harness::script::runner {

namespace {

// SPIR-V opcodes, decorations and storage classes read here (SPIR-V 1.0 specification).
enum : uint32_t {
  kOpTypeInt = 21, kOpTypeFloat = 22, kOpTypeVector = 23, kOpTypeMatrix = 24, kOpTypeArray = 28, kOpTypeRuntimeArray = 29,
  kOpTypeStruct = 30, kOpTypePointer = 32, kOpConstant = 43, kOpVariable = 59, kOpDecorate = 71, kOpMemberDecorate = 72,
  kRowMajor = 4, kArrayStride = 6, kMatrixStride = 7, kBuiltIn = 11, kBufferBlock = 3, kLocation = 30, kBinding = 33, kOffset = 35,
  kUniformConstant = 0, kUniform = 2, kAtomicCounter = 10, kStorageBuffer = 12,
};

// The types, decorations and resource variables of one module.
struct ModuleTypes {
  struct Type {
    uint32_t op = 0;
    std::vector<uint32_t> operands;  // the instruction's words after its result id
  };
  std::map<uint32_t, Type> types;
  std::map<uint32_t, uint32_t> constants;                        // 32-bit OpConstant values
  std::map<uint32_t, std::map<uint32_t, uint32_t>> decorations;  // id -> decoration -> first literal
  std::map<std::pair<uint32_t, uint32_t>, std::map<uint32_t, uint32_t>> memberDecorations;
  struct Variable {
    uint32_t id = 0, type = 0, storage = 0;  // type: the pointee
  };
  std::vector<Variable> variables;

  explicit ModuleTypes(const std::vector<uint32_t>& spirv) {
    rhi::forEachInstruction(spirv, [&](uint32_t op, size_t at, size_t words) {
      if (op == kOpDecorate && words >= 3) decorations[spirv[at + 1]][spirv[at + 2]] = words >= 4 ? spirv[at + 3] : 1;
      else if (op == kOpMemberDecorate && words >= 4) memberDecorations[{spirv[at + 1], spirv[at + 2]}][spirv[at + 3]] = words >= 5 ? spirv[at + 4] : 1;
      else if (op == kOpConstant && words == 4) constants[spirv[at + 2]] = spirv[at + 3];
      else if (op == kOpVariable && words >= 4) variables.push_back({spirv[at + 2], spirv[at + 1], spirv[at + 3]});
      else if ((op >= 19 && op <= 39) || op == 5341)  // OpTypeVoid .. OpTypePipe, OpTypeAccelerationStructureKHR
        types[spirv[at + 1]] = {op, std::vector<uint32_t>(spirv.begin() + long(at + 2), spirv.begin() + long(at + words))};
    });
    for (Variable& v : variables) v.type = pointee(v.type);
  }
  uint32_t pointee(uint32_t pointer) const {
    auto t = types.find(pointer);
    return t != types.end() && t->second.op == kOpTypePointer && t->second.operands.size() == 2 ? t->second.operands[1] : 0;
  }
  const Type& type(uint32_t id) const {
    auto t = types.find(id);
    if (t == types.end()) throw Failure{"SPIR-V module: no type %" + std::to_string(id)};
    return t->second;
  }
  std::optional<uint32_t> decoration(uint32_t id, uint32_t d) const {
    auto i = decorations.find(id);
    if (i == decorations.end() || !i->second.count(d)) return std::nullopt;
    return i->second.at(d);
  }
  std::optional<uint32_t> memberDecoration(uint32_t id, uint32_t member, uint32_t d) const {
    auto i = memberDecorations.find({id, member});
    if (i == memberDecorations.end() || !i->second.count(d)) return std::nullopt;
    return i->second.at(d);
  }
  // Elements of an array type; 0 for a runtime array.
  uint32_t length(const Type& array) const {
    if (array.op == kOpTypeRuntimeArray) return 0;
    auto c = constants.find(array.operands.at(1));
    if (c == constants.end()) throw Unsupported{"an array sized by a specialization constant in a program query"};
    return c->second;
  }
  bool structOrArrayOfAggregates(uint32_t id) const {
    const Type& t = type(id);
    if (t.op == kOpTypeStruct) return true;
    if (t.op != kOpTypeArray && t.op != kOpTypeRuntimeArray) return false;
    const uint32_t element = type(t.operands[0]).op;
    return element == kOpTypeStruct || element == kOpTypeArray || element == kOpTypeRuntimeArray;
  }
  // OpenGL's active variables of a type: its leaves, where a leaf is neither a struct nor an
  // array of structs or arrays (each element of those counts apart; a runtime array of them, none).
  uint32_t activeVariables(uint32_t id) const {
    if (!structOrArrayOfAggregates(id)) return 1;
    const Type& t = type(id);
    uint32_t n = 0;
    if (t.op == kOpTypeStruct)
      for (uint32_t member : t.operands) n += activeVariables(member);
    else
      n = length(t) * activeVariables(t.operands[0]);
    return n;
  }
  // The bytes a type takes up to its last byte, from its explicit offsets and strides (Mesa's
  // glsl_type::explicit_size): an array's stride times its length less one plus one element (a
  // runtime array: one stride), a matrix's stride times its columns (rows when row-major) less
  // one plus one column (row). `matrixStride` and `rowMajor` are the enclosing member's.
  uint32_t explicitSize(uint32_t id, uint32_t matrixStride = 0, bool rowMajor = false) const {
    const Type& t = type(id);
    switch (t.op) {
      case kOpTypeInt:
      case kOpTypeFloat: return t.operands.at(0) / 8;
      case kOpTypeVector: return t.operands.at(1) * explicitSize(t.operands[0]);
      case kOpTypeMatrix: {
        const Type& column = type(t.operands.at(0));
        const uint32_t columns = t.operands[1], rows = column.operands.at(1), scalar = explicitSize(column.operands[0]);
        if (!matrixStride) throw Failure{"SPIR-V module: a matrix member without a MatrixStride"};
        return rowMajor ? matrixStride * (rows - 1) + columns * scalar : matrixStride * (columns - 1) + rows * scalar;
      }
      case kOpTypeArray:
      case kOpTypeRuntimeArray: {
        const uint32_t stride = decoration(id, kArrayStride).value_or(0), n = length(t);
        if (n == 0) return stride;
        return stride * (n - 1) + explicitSize(t.operands[0], matrixStride, rowMajor);
      }
      case kOpTypeStruct: {
        uint32_t size = 0;
        for (uint32_t m = 0; m < t.operands.size(); ++m) {
          const uint32_t offset = memberDecoration(id, m, kOffset).value_or(0);
          size = std::max(size, offset + explicitSize(t.operands[m], memberDecoration(id, m, kMatrixStride).value_or(0),
                                                      memberDecoration(id, m, kRowMajor).has_value()));
        }
        return size;
      }
      default: throw Unsupported{"a block member of SPIR-V type opcode " + std::to_string(t.op) + " in a program query"};
    }
  }
};

// One block of the program as OpenGL counts them: each element of an array of blocks is one, at
// its own binding (the array's plus the element's index: ARB_gl_spirv).
struct ProgramBlock {
  bool storage = false;
  uint32_t activeVariables = 0, dataSize = 0;
};

}  // namespace

ExpectResult ShaderSteps::programQuery(const Command& c) {
  const std::string what = "line " + std::to_string(c.loc.line) + ": " +
                           (c.programInterface.empty() ? "program_query " + c.other
                                                       : "program_interface_query " + c.programInterface + " " + c.uniform + " (binding " +
                                                             std::to_string(c.blockBinding) + ") " + c.other);
  std::map<std::pair<bool, uint32_t>, ProgramBlock> blocks;  // by (storage, OpenGL binding)
  // Active uniforms by what links them across stages: a block by its binding, another uniform
  // by its location or binding, one with neither is its stage's own.
  std::map<std::string, uint32_t> uniforms;
  for (const Shader& s : script_.shaders) {
    if (s.format != "SPIRV-ASM" && s.format != "SPIRV-BIN") continue;  // the pass-through vertex shader declares none
    const ModuleTypes m(compiled_.at(s.name));
    for (const ModuleTypes::Variable& v : m.variables) {
      const bool resource = v.storage == kUniform || v.storage == kStorageBuffer || v.storage == kUniformConstant || v.storage == kAtomicCounter;
      if (!resource || m.decoration(v.id, kBuiltIn)) continue;
      // An array (of arrays) of blocks: each element a block of its own.
      uint32_t block = v.type, elements = 1;
      while (m.type(block).op == kOpTypeArray) {
        elements *= m.length(m.type(block));
        block = m.type(block).operands[0];
      }
      if ((v.storage == kUniform || v.storage == kStorageBuffer) && m.type(block).op == kOpTypeStruct) {
        const bool storage = v.storage == kStorageBuffer || m.decoration(block, kBufferBlock).has_value();
        const uint32_t binding = m.decoration(v.id, kBinding).value_or(0);
        const uint32_t dataSize = (m.explicitSize(block) + 15) / 16 * 16;  // rounded up to a vec4, as std140 sizes are
        for (uint32_t e = 0; e < elements; ++e) blocks[{storage, binding + e}] = {storage, m.activeVariables(block), dataSize};
        if (!storage) uniforms["block " + std::to_string(binding)] = m.activeVariables(block);
      } else if (v.storage == kUniformConstant || v.storage == kAtomicCounter) {
        // Samplers and images have bindings of their own kinds (texture and image units), atomic
        // counters a buffer binding and an offset in it.
        const std::optional<uint32_t> location = m.decoration(v.id, kLocation), binding = m.decoration(v.id, kBinding);
        uint32_t innermost = v.type;
        while (m.type(innermost).op == kOpTypeArray || m.type(innermost).op == kOpTypeRuntimeArray) innermost = m.type(innermost).operands[0];
        std::string key = s.name + " %" + std::to_string(v.id);
        if (location) key = "location " + std::to_string(*location);
        else if (binding && v.storage == kAtomicCounter) key = "atomic counter " + std::to_string(*binding) + " " + std::to_string(m.decoration(v.id, kOffset).value_or(0));
        else if (binding) key = "binding " + std::to_string(*binding) + " of type opcode " + std::to_string(m.type(innermost).op);
        uniforms[key] = m.activeVariables(v.type);
      }
    }
  }
  int64_t actual = 0;
  if (c.other == "GL_ACTIVE_UNIFORMS") {
    for (const auto& [key, n] : uniforms) actual += n;
  } else if (c.other == "GL_ACTIVE_UNIFORM_BLOCKS") {
    actual = std::count_if(blocks.begin(), blocks.end(), [](const auto& b) { return !b.second.storage; });
  } else {
    auto b = blocks.find({c.programInterface == "GL_SHADER_STORAGE_BLOCK", static_cast<uint32_t>(c.blockBinding)});
    if (b == blocks.end()) throw Failure{what + ": no active block at that binding"};
    actual = c.other == "GL_NUM_ACTIVE_VARIABLES" ? b->second.activeVariables
             : c.other == "GL_BUFFER_DATA_SIZE"   ? b->second.dataSize
                                                  : c.blockBinding;
  }
  ExpectResult e;
  e.line = c.loc.line;
  e.pass = actual == c.values.at(0).i;
  e.message = what + (e.pass ? ": ok" : ": expected " + std::to_string(c.values[0].i) + ", got " + std::to_string(actual));
  return e;
}

}  // namespace parity::harness::script::runner
