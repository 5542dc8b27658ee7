#include "harness/scripts/spirv_interface.h"

#include <algorithm>
#include <cstdlib>
#include <map>
#include <tuple>

#include "rhi/shader_reflection.h"

namespace parity::harness::script {

namespace {

// SPIR-V opcodes and decorations read here (SPIR-V 1.5 specification, 3.32 and 3.20).
enum : uint32_t {
  kOpName = 5, kOpExtension = 10, kOpCapability = 17, kOpMemberName = 6, kOpTypeBool = 20, kOpTypeInt = 21, kOpTypeFloat = 22, kOpTypeVector = 23,
  kOpTypeMatrix = 24, kOpTypeImage = 25, kOpTypeSampler = 26, kOpTypeSampledImage = 27, kOpTypeArray = 28, kOpTypeRuntimeArray = 29, kOpTypeStruct = 30, kOpTypePointer = 32, kOpConstant = 43,
  kOpVariable = 59, kOpDecorate = 71, kOpMemberDecorate = 72,
};
enum : uint32_t {
  kDecBlock = 2, kDecBufferBlock = 3, kDecRowMajor = 4, kDecArrayStride = 6, kDecMatrixStride = 7, kDecBuiltIn = 11, kDecPatch = 15, kDecLocation = 30,
  kDecComponent = 31, kDecBinding = 33, kDecSet = 34, kDecOffset = 35
};
enum : uint32_t { kStorageUniformConstant = 0, kStorageInput = 1, kStorageUniform = 2, kStorageOutput = 3, kStorageBuffer = 12 };


struct Module {
  std::map<uint32_t, std::string> names;
  std::map<std::pair<uint32_t, uint32_t>, std::string> memberNames;
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> decorations;  // (id, decoration) -> first operand
  std::map<std::pair<uint32_t, uint32_t>, size_t> decorationWords;  // (id, decoration) -> index of that operand
  std::map<std::tuple<uint32_t, uint32_t, uint32_t>, uint32_t> memberDecorations;  // (struct, member, decoration)
  std::map<uint32_t, std::vector<uint32_t>> types;  // id -> the instruction's words from the opcode on
  std::map<uint32_t, uint32_t> constants;           // 32-bit integer constants (array lengths)
  std::map<uint32_t, std::pair<uint32_t, uint32_t>> variables;  // id -> (pointer type, storage class)

  explicit Module(const std::vector<uint32_t>& w) {
    for (size_t i = 5; i < w.size();) {
      uint32_t op = w[i] & 0xFFFF, n = w[i] >> 16;
      if (n == 0 || i + n > w.size()) break;
      if (op == kOpName && n >= 3) names[w[i + 1]] = rhi::spirvLiteralString(w, i + 2, i + n);
      else if (op == kOpMemberName && n >= 4) memberNames[{w[i + 1], w[i + 2]}] = rhi::spirvLiteralString(w, i + 3, i + n);
      else if (op == kOpDecorate && n >= 4) decorations[{w[i + 1], w[i + 2]}] = w[i + 3], decorationWords[{w[i + 1], w[i + 2]}] = i + 3;
      else if (op == kOpDecorate && n == 3) decorations[{w[i + 1], w[i + 2]}] = 0;  // Block, BufferBlock, ...
      else if (op == kOpMemberDecorate && n >= 5) memberDecorations[{w[i + 1], w[i + 2], w[i + 3]}] = w[i + 4];
      else if (op == kOpMemberDecorate && n == 4) memberDecorations[{w[i + 1], w[i + 2], w[i + 3]}] = 0;  // RowMajor, ...
      else if ((op >= kOpTypeBool && op <= kOpTypeStruct) || op == kOpTypePointer) types[w[i + 1]] = std::vector<uint32_t>(w.begin() + long(i), w.begin() + long(i + n));
      else if (op == kOpConstant && n >= 4) constants[w[i + 2]] = w[i + 3];
      else if (op == kOpVariable && n >= 4) variables[w[i + 2]] = {w[i + 1], w[i + 3]};
      i += n;
    }
  }
  uint32_t op(uint32_t type) const {
    auto it = types.find(type);
    return it == types.end() ? 0 : it->second[0] & 0xFFFF;
  }
  const std::vector<uint32_t>& type(uint32_t id) const {
    static const std::vector<uint32_t> kNone{0, 0, 0, 0};
    auto it = types.find(id);
    return it == types.end() ? kNone : it->second;
  }
  uint32_t decoration(uint32_t id, uint32_t dec, uint32_t fallback = 0) const {
    auto it = decorations.find({id, dec});
    return it == decorations.end() ? fallback : it->second;
  }
  bool hasDecoration(uint32_t id, uint32_t dec) const { return decorations.count({id, dec}) > 0; }
  uint32_t memberDecoration(uint32_t s, uint32_t m, uint32_t dec) const {
    auto it = memberDecorations.find({s, m, dec});
    return it == memberDecorations.end() ? 0 : it->second;
  }

  // Bytes a value of `type` occupies in a block (a matrix: columns x its member's MatrixStride).
  uint32_t size(uint32_t id, uint32_t matrixStride) const {
    const std::vector<uint32_t>& t = type(id);
    switch (op(id)) {
      case kOpTypeInt:
      case kOpTypeFloat: return t[2] / 8;
      case kOpTypeBool: return 4;
      case kOpTypeVector: return t[3] * size(t[2], 0);
      case kOpTypeMatrix: return t[3] * std::max(matrixStride, size(t[2], 0));
      case kOpTypeArray: {
        auto length = constants.find(t[3]);
        return (length == constants.end() ? 1 : length->second) * decoration(id, kDecArrayStride, size(t[2], matrixStride));
      }
      case kOpTypeStruct: {
        uint32_t end = 0;
        for (uint32_t m = 0; m + 2 < t.size(); ++m)
          end = std::max(end, memberDecoration(id, m, kDecOffset) + size(t[m + 2], memberDecoration(id, m, kDecMatrixStride)));
        return end;
      }
      default: return 0;
    }
  }

  // The Uniform variable whose pointee struct is named `typeName`.
  std::optional<std::pair<uint32_t, uint32_t>> block(const std::string& typeName) const {  // (variable, struct)
    for (const auto& [id, v] : variables) {
      if (v.second != kStorageUniform || op(v.first) != kOpTypePointer) continue;
      uint32_t pointee = type(v.first)[3];
      if (op(pointee) == kOpTypeArray) pointee = type(pointee)[2];  // an array of blocks: each element's layout
      auto n = names.find(pointee);
      if (op(pointee) == kOpTypeStruct && n != names.end() && n->second == typeName) return std::make_pair(id, pointee);
    }
    return std::nullopt;
  }
};

}  // namespace

std::optional<uint32_t> inputLocation(const std::vector<uint32_t>& spirv, const std::string& name) {
  Module m(spirv);
  for (const auto& [id, v] : m.variables) {
    auto n = m.names.find(id);
    if (v.second == kStorageInput && n != m.names.end() && n->second == name && m.hasDecoration(id, kDecLocation))
      return m.decoration(id, kDecLocation);
  }
  return std::nullopt;
}

bool usesSubgroupOperations(const std::vector<uint32_t>& spirv) {
  for (size_t i = 5; i < spirv.size();) {
    uint32_t op = spirv[i] & 0xFFFF, n = spirv[i] >> 16;
    if (n == 0 || i + n > spirv.size()) break;
    // OpCapability GroupNonUniform (61) .. GroupNonUniformQuad (68)
    if (op == kOpCapability && n == 2 && spirv[i + 1] >= 61 && spirv[i + 1] <= 68) return true;
    i += n;
  }
  return false;
}

std::vector<std::string> spirvExtensions(const std::vector<uint32_t>& spirv) {
  std::vector<std::string> out;
  for (size_t i = 5; i < spirv.size();) {
    uint32_t op = spirv[i] & 0xFFFF, n = spirv[i] >> 16;
    if (n == 0 || i + n > spirv.size()) break;
    if (op == kOpExtension && n >= 2) out.push_back(rhi::spirvLiteralString(spirv, i + 1, i + n));
    i += n;
  }
  return out;
}

std::vector<DescriptorArray> descriptorArrays(const std::vector<uint32_t>& spirv) {
  Module m(spirv);
  std::vector<DescriptorArray> out;
  for (const auto& [id, v] : m.variables) {
    if (!m.hasDecoration(id, kDecBinding) || m.op(v.first) != kOpTypePointer) continue;
    uint32_t pointee = m.type(v.first)[3];
    if (m.op(pointee) != kOpTypeArray && m.op(pointee) != kOpTypeRuntimeArray) continue;
    DescriptorArray a;
    auto n = m.names.find(id);
    a.name = n == m.names.end() || n->second.empty() ? "%" + std::to_string(id) : n->second;
    const uint32_t element = m.type(pointee)[2];
    if (m.op(pointee) == kOpTypeArray) {
      auto length = m.constants.find(m.type(pointee)[3]);
      a.elements = length == m.constants.end() ? 0 : length->second;
    }
    a.nested = m.op(element) == kOpTypeArray || m.op(element) == kOpTypeRuntimeArray;
    a.samplers = m.op(element) == kOpTypeSampler;
    out.push_back(a);
  }
  return out;
}

namespace {
// A block variable's type name, size and the words of its set and binding decorations.
void describeBlock(const Module& m, uint32_t id, uint32_t pointee, UniformBlockVariable* b) {
  auto n = m.names.find(pointee);
  b->typeName = n == m.names.end() ? "" : n->second;
  b->size = m.size(pointee, 0);
  auto set = m.decorationWords.find({id, kDecSet});
  auto binding = m.decorationWords.find({id, kDecBinding});
  b->setWord = set == m.decorationWords.end() ? 0 : set->second;
  b->bindingWord = binding == m.decorationWords.end() ? 0 : binding->second;
}
}  // namespace

std::vector<UniformBlockVariable> uniformBlocks(const std::vector<uint32_t>& spirv) {
  Module m(spirv);
  std::vector<UniformBlockVariable> out;
  for (const auto& [id, v] : m.variables) {
    if (v.second != kStorageUniform || m.op(v.first) != kOpTypePointer) continue;
    uint32_t pointee = m.type(v.first)[3];
    UniformBlockVariable b;
    if (m.op(pointee) == kOpTypeArray && m.constants.count(m.type(pointee)[3])) {  // an array of blocks
      b.elements = m.constants.at(m.type(pointee)[3]);
      pointee = m.type(pointee)[2];
    }
    if (m.op(pointee) != kOpTypeStruct || !m.hasDecoration(pointee, kDecBlock) || m.hasDecoration(pointee, kDecBufferBlock)) continue;
    describeBlock(m, id, pointee, &b);
    out.push_back(b);
  }
  return out;
}

std::vector<UniformBlockVariable> storageBlocks(const std::vector<uint32_t>& spirv) {
  Module m(spirv);
  std::vector<UniformBlockVariable> out;
  for (const auto& [id, v] : m.variables) {
    if (v.second != kStorageBuffer || m.op(v.first) != kOpTypePointer) continue;
    uint32_t pointee = m.type(v.first)[3];
    if (m.op(pointee) != kOpTypeStruct) continue;
    UniformBlockVariable b;
    describeBlock(m, id, pointee, &b);
    out.push_back(b);
  }
  return out;
}

bool outputsBuiltIn(const std::vector<uint32_t>& spirv, uint32_t builtIn) {
  Module m(spirv);
  for (const auto& [id, v] : m.variables) {
    if (v.second != kStorageOutput) continue;
    if (m.hasDecoration(id, kDecBuiltIn) && m.decoration(id, kDecBuiltIn) == builtIn) return true;
    uint32_t pointee = m.type(v.first)[3];
    while (m.op(pointee) == kOpTypeArray) pointee = m.type(pointee)[2];
    const std::vector<uint32_t>& t = m.type(pointee);
    for (uint32_t member = 0; m.op(pointee) == kOpTypeStruct && member + 2 < t.size(); ++member)
      if (m.memberDecorations.count({pointee, member, kDecBuiltIn}) && m.memberDecoration(pointee, member, kDecBuiltIn) == builtIn) return true;
  }
  return false;
}

std::vector<InterfaceVariable> interfaceVariables(const std::vector<uint32_t>& spirv) {
  Module m(spirv);
  std::vector<InterfaceVariable> out;
  for (const auto& [id, v] : m.variables) {
    auto location = m.decorationWords.find({id, kDecLocation});
    if ((v.second != kStorageInput && v.second != kStorageOutput) || location == m.decorationWords.end() || m.hasDecoration(id, kDecBuiltIn))
      continue;
    uint32_t pointee = m.type(v.first)[3];
    while (m.op(pointee) == kOpTypeArray || m.op(pointee) == kOpTypeRuntimeArray) pointee = m.type(pointee)[2];
    const bool block = m.op(pointee) == kOpTypeStruct && m.hasDecoration(pointee, kDecBlock);
    auto name = m.names.find(block ? pointee : id);
    if (name == m.names.end() || name->second.empty()) continue;
    InterfaceVariable iv;
    iv.name = name->second;
    iv.output = v.second == kStorageOutput;
    iv.patch = m.hasDecoration(id, kDecPatch);
    iv.location = m.decoration(id, kDecLocation);
    iv.locationWord = location->second;
    auto component = m.decorationWords.find({id, kDecComponent});
    iv.component = m.decoration(id, kDecComponent);
    iv.componentWord = component == m.decorationWords.end() ? 0 : component->second;
    out.push_back(iv);
  }
  return out;
}

namespace {

// Locations a value of `type` takes as a stage input or output (SPIR-V 1.5, 2.16.2 "Location
// Assignment"): a 64-bit vector of three or four components two, a matrix one per column,
// arrays and structs the sum of their elements.
uint32_t locationsOf(const Module& m, uint32_t type) {
  const std::vector<uint32_t>& t = m.type(type);
  switch (m.op(type)) {
    case kOpTypeArray: {
      auto length = m.constants.find(t[3]);
      return (length == m.constants.end() ? 1 : length->second) * locationsOf(m, t[2]);
    }
    case kOpTypeMatrix: return t[3] * locationsOf(m, t[2]);
    case kOpTypeStruct: {
      uint32_t sum = 0;
      for (size_t member = 2; member < t.size(); ++member) sum += locationsOf(m, t[member]);
      return sum;
    }
    case kOpTypeVector: return m.type(t[2])[2] == 64 && t[3] > 2 ? 2 : 1;
    default: return 1;
  }
}

}  // namespace

OutputExtent outputExtent(const std::vector<uint32_t>& spirv, bool perVertexOutputs) {
  Module m(spirv);
  OutputExtent out;
  for (const auto& [id, v] : m.variables) {
    if (v.second != kStorageOutput || !m.hasDecoration(id, kDecLocation) || m.hasDecoration(id, kDecBuiltIn)) continue;
    uint32_t type = m.type(v.first)[3];
    if (perVertexOutputs && !m.hasDecoration(id, kDecPatch) && m.op(type) == kOpTypeArray) type = m.type(type)[2];
    const uint32_t end = m.decoration(id, kDecLocation) + locationsOf(m, type);
    if (end <= out.end) continue;
    out.end = end;
    auto name = m.names.find(id);
    out.name = name == m.names.end() ? std::string() : name->second;
  }
  return out;
}

std::vector<std::string> perVertexMembers(const std::vector<uint32_t>& spirv, bool output) {
  Module m(spirv);
  for (const auto& [id, v] : m.variables) {
    if (v.second != (output ? kStorageOutput : kStorageInput)) continue;
    uint32_t pointee = m.type(v.first)[3];
    while (m.op(pointee) == kOpTypeArray) pointee = m.type(pointee)[2];
    if (m.op(pointee) != kOpTypeStruct || !m.memberDecorations.count({pointee, 0, kDecBuiltIn})) continue;
    std::vector<std::string> members;
    const std::vector<uint32_t>& t = m.type(pointee);
    for (uint32_t member = 0; member + 2 < t.size(); ++member) {
      auto length = [&] {
        const std::vector<uint32_t>& array = m.type(t[member + 2]);
        auto n = m.constants.find(array[3]);
        return std::to_string(n == m.constants.end() ? 1 : n->second);
      };
      switch (m.memberDecoration(pointee, member, kDecBuiltIn)) {
        case 0: members.push_back("vec4 gl_Position;"); break;
        case 1: members.push_back("float gl_PointSize;"); break;
        case 3: members.push_back("float gl_ClipDistance[" + length() + "];"); break;
        case 4: members.push_back("float gl_CullDistance[" + length() + "];"); break;
        default: break;
      }
    }
    return members;
  }
  return {};
}

std::vector<SamplerVariable> samplerVariables(const std::vector<uint32_t>& spirv) {
  Module m(spirv);
  std::vector<SamplerVariable> out;
  for (const auto& [id, v] : m.variables) {
    if (v.second != kStorageUniformConstant || m.op(v.first) != kOpTypePointer) continue;
    uint32_t pointee = m.type(v.first)[3];
    SamplerVariable s;
    if (m.op(pointee) == kOpTypeArray && m.constants.count(m.type(pointee)[3])) {  // an array of samplers
      s.elements = m.constants.at(m.type(pointee)[3]);
      pointee = m.type(pointee)[2];
    }
    // OpTypeImage's Sampled operand is 2 for a storage image.
    s.storageImage = m.op(pointee) == kOpTypeImage && m.type(pointee).size() > 7 && m.type(pointee)[7] == 2;
    if (m.op(pointee) != kOpTypeSampledImage && !s.storageImage) continue;
    const uint32_t image = m.op(pointee) == kOpTypeSampledImage ? m.type(pointee)[2] : pointee;
    if (m.op(image) == kOpTypeImage && m.type(image).size() > 6) {
      const std::vector<uint32_t>& t = m.type(image);
      s.dim = t[3];
      s.depth = t[4] == 1;
      s.arrayed = t[5] == 1;
      s.multisampled = t[6] == 1;
      if (m.op(t[2]) == kOpTypeInt) s.texel = m.type(t[2]).size() > 3 && m.type(t[2])[3] ? SamplerVariable::Texel::Int : SamplerVariable::Texel::UInt;
    }
    auto n = m.names.find(id);
    s.name = n == m.names.end() ? "" : n->second;
    auto set = m.decorationWords.find({id, kDecSet});
    auto binding = m.decorationWords.find({id, kDecBinding});
    s.setWord = set == m.decorationWords.end() ? 0 : set->second;
    s.bindingWord = binding == m.decorationWords.end() ? 0 : binding->second;
    out.push_back(s);
  }
  return out;
}

bool renameStruct(std::vector<uint32_t>& spirv, const std::string& from, const std::string& to) {
  Module m(spirv);
  for (size_t i = 5; i < spirv.size();) {
    uint32_t op = spirv[i] & 0xFFFF, n = spirv[i] >> 16;
    if (n == 0 || i + n > spirv.size()) break;
    if (op == kOpName && n >= 3 && m.op(spirv[i + 1]) == kOpTypeStruct && rhi::spirvLiteralString(spirv, i + 2, i + n) == from) {
      std::vector<uint32_t> words((to.size() + 4) / 4, 0);  // nul-terminated, padded to words
      for (size_t c = 0; c < to.size(); ++c) words[c / 4] |= uint32_t(static_cast<unsigned char>(to[c])) << (8 * (c % 4));
      std::vector<uint32_t> instruction = {uint32_t(words.size() + 2) << 16 | kOpName, spirv[i + 1]};
      instruction.insert(instruction.end(), words.begin(), words.end());
      spirv.erase(spirv.begin() + long(i), spirv.begin() + long(i + n));
      spirv.insert(spirv.begin() + long(i), instruction.begin(), instruction.end());
      return true;
    }
    i += n;
  }
  return false;
}

std::optional<UniformBlockInfo> findUniformBlock(const std::vector<uint32_t>& spirv, const std::string& typeName) {
  Module m(spirv);
  auto b = m.block(typeName);
  if (!b) return std::nullopt;
  UniformBlockInfo info;
  info.set = m.decoration(b->first, kDecSet);
  info.binding = m.decoration(b->first, kDecBinding);
  info.size = m.size(b->second, 0);
  return info;
}

std::optional<UniformSlot> findUniform(const std::vector<uint32_t>& spirv, const std::string& typeName, const std::string& path) {
  Module m(spirv);
  auto b = m.block(typeName);
  if (!b) return std::nullopt;
  UniformSlot slot;
  uint32_t type = b->second, matrixStride = 0;
  bool rowMajor = false;
  bool indexed = false;
  // Path steps: ".name" or "[index]"; the first name has no dot.
  for (size_t i = 0; i < path.size();) {
    if (path[i] == '[') {
      size_t close = path.find(']', i);
      if (close == std::string::npos || m.op(type) != kOpTypeArray) return std::nullopt;
      uint32_t index = static_cast<uint32_t>(std::strtoul(path.substr(i + 1, close - i - 1).c_str(), nullptr, 10));
      const std::vector<uint32_t>& t = m.type(type);
      auto length = m.constants.find(t[3]);
      uint32_t count = length == m.constants.end() ? 1 : length->second;
      if (index >= count) return std::nullopt;
      slot.offset += index * m.decoration(type, kDecArrayStride);
      slot.elements = count - index;
      slot.arrayStride = m.decoration(type, kDecArrayStride);
      indexed = true;
      type = t[2];
      i = close + 1;
      continue;
    }
    if (path[i] == '.') ++i;
    size_t end = path.find_first_of(".[", i);
    std::string name = path.substr(i, end == std::string::npos ? std::string::npos : end - i);
    i = end == std::string::npos ? path.size() : end;
    if (m.op(type) != kOpTypeStruct) return std::nullopt;
    const std::vector<uint32_t>& t = m.type(type);
    bool found = false;
    for (uint32_t member = 0; member + 2 < t.size() && !found; ++member) {
      auto n = m.memberNames.find({type, member});
      if (n == m.memberNames.end() || n->second != name) continue;
      slot.offset += m.memberDecoration(type, member, kDecOffset);
      matrixStride = m.memberDecoration(type, member, kDecMatrixStride);
      rowMajor = m.memberDecorations.count({type, member, kDecRowMajor}) > 0;
      type = t[member + 2];
      found = true;
    }
    if (!found) return std::nullopt;
    indexed = false;
    slot.arrayStride = 0, slot.elements = 1;  // an array indexed before the member is not this one
  }
  // A whole array named without an index: its elements from the first.
  if (!indexed && m.op(type) == kOpTypeArray) {
    const std::vector<uint32_t>& t = m.type(type);
    auto length = m.constants.find(t[3]);
    slot.elements = length == m.constants.end() ? 1 : length->second;
    slot.arrayStride = m.decoration(type, kDecArrayStride);
    type = t[2];
  } else if (!indexed) {
    slot.elements = 1;
  }
  if (m.op(type) == kOpTypeMatrix) {
    slot.columns = m.type(type)[3];
    slot.matrixStride = matrixStride;
    slot.rowMajor = rowMajor;
    type = m.type(type)[2];
  }
  if (m.op(type) == kOpTypeVector) {
    slot.rows = m.type(type)[3];
    type = m.type(type)[2];
  }
  const std::vector<uint32_t>& t = m.type(type);
  switch (m.op(type)) {
    case kOpTypeFloat: slot.scalar = t[2] == 64 ? Scalar::Float64 : t[2] == 16 ? Scalar::Float16 : Scalar::Float32; break;
    case kOpTypeInt:
      slot.scalar = t[2] == 64 ? (t[3] ? Scalar::Int64 : Scalar::Uint64) : t[2] == 16 ? (t[3] ? Scalar::Int16 : Scalar::Uint16)
                  : t[2] == 8 ? (t[3] ? Scalar::Int8 : Scalar::Uint8) : (t[3] ? Scalar::Int32 : Scalar::Uint32);
      break;
    case kOpTypeBool: slot.scalar = Scalar::Uint32; break;
    default: return std::nullopt;  // a struct named without a member
  }
  return slot;
}

}  // namespace parity::harness::script
