#include "platforms/shader_use.h"

#include <algorithm>
#include <map>
#include <set>
#include <string>

namespace parity::platforms {

namespace {
constexpr uint32_t kOpTypeBool = 20, kOpTypeInt = 21, kOpTypeFloat = 22, kOpTypeVector = 23, kOpTypeMatrix = 24,
                   kOpTypeArray = 28, kOpTypeStruct = 30, kOpTypePointer = 32, kOpConstant = 43, kOpFunction = 54,
                   kOpVariable = 59, kOpLoad = 61, kOpStore = 62, kOpAccessChain = 65, kOpInBoundsAccessChain = 66,
                   kOpPtrAccessChain = 67, kOpDecorate = 71, kOpImageWrite = 99, kOpAtomicStore = 228;
constexpr uint32_t kDecorationBuiltIn = 11, kDecorationBinding = 33, kStorageInput = 1, kStorageWorkgroup = 4;

// OpImageSampleImplicitLod .. OpImageSampleProjDrefExplicitLod, OpImageGather, OpImageDrefGather.
bool isFilteredSample(uint32_t op) { return (op >= 87 && op <= 94) || op == 96 || op == 97; }
// OpAtomicLoad .. OpAtomicXor, OpAtomicFlagTestAndSet, OpAtomicFlagClear, OpAtomicFAddEXT and
// the float min/max of SPV_EXT_shader_atomic_float_min_max.
bool isAtomic(uint32_t op) { return (op >= 227 && op <= 242) || op == 318 || op == 319 || op == 6035 || op == 5614 || op == 5615; }

// Sizes and interface slots of the module's types, as far as the rules need them.
struct Types {
  std::map<uint32_t, std::vector<uint32_t>> defs;  // type id -> the instruction's words after the opcode
  std::map<uint32_t, uint32_t> constants;          // 32-bit integer constants

  uint32_t bytes(uint32_t id, int depth = 0) const {
    auto it = defs.find(id);
    if (it == defs.end() || depth > 16) return 0;
    const std::vector<uint32_t>& d = it->second;  // d[0] is the opcode
    switch (d[0]) {
      case kOpTypeBool: return 4;
      case kOpTypeInt:
      case kOpTypeFloat: return d.size() > 2 ? d[2] / 8 : 4;
      case kOpTypeVector:
      case kOpTypeMatrix: return d.size() > 3 ? bytes(d[2], depth + 1) * d[3] : 0;
      case kOpTypeArray: return d.size() > 3 ? bytes(d[2], depth + 1) * constant(d[3]) : 0;
      case kOpTypeStruct: {
        uint32_t sum = 0;
        for (size_t m = 2; m < d.size(); ++m) sum += bytes(d[m], depth + 1);
        return sum;
      }
      default: return 0;
    }
  }
  // Interface locations (vec4 slots) a variable of the type takes: a scalar or vector one, a
  // matrix a column each, an array an element each, a block its members.
  uint32_t locations(uint32_t id, int depth = 0) const {
    auto it = defs.find(id);
    if (it == defs.end() || depth > 16) return 1;
    const std::vector<uint32_t>& d = it->second;
    switch (d[0]) {
      case kOpTypeMatrix: return d.size() > 3 ? d[3] : 1;
      case kOpTypeArray: return d.size() > 3 ? locations(d[2], depth + 1) * constant(d[3]) : 1;
      case kOpTypeStruct: {
        uint32_t sum = 0;
        for (size_t m = 2; m < d.size(); ++m) sum += locations(d[m], depth + 1);
        return sum;
      }
      default: return 1;
    }
  }
  uint32_t pointee(uint32_t pointer) const {
    auto it = defs.find(pointer);
    return it != defs.end() && it->second[0] == kOpTypePointer && it->second.size() > 3 ? it->second[3] : 0;
  }
  uint32_t constant(uint32_t id) const {
    auto c = constants.find(id);
    return c == constants.end() ? 0 : c->second;
  }
};

}  // namespace

ShaderUse shaderUse(const std::vector<uint32_t>& spirv, rhi::ShaderStage stage) {
  ShaderUse use;
  use.stage = stage;
  rhi::ShaderReflection r;
  std::string error;
  if (rhi::reflectSpirv(spirv, stage, &r, &error)) {
    use.resources = r.resources;
    use.pairs = r.separatePairs;
    use.localSize = r.localSize;
  }
  // A variable's id among a function's operands is a use of its binding; a literal of the same
  // value counts too, which can only keep a resource, never drop one.
  std::set<uint32_t> builtIns, used, written;
  std::map<uint32_t, uint32_t> inputs;     // input variable -> its pointer type
  std::map<uint32_t, uint32_t> bindingOf;  // variable id -> binding
  std::map<uint32_t, uint32_t> rootOf;     // pointer or loaded image -> the variable it comes from
  Types types;
  bool inFunctions = false;
  auto root = [&](uint32_t id) {
    auto it = rootOf.find(id);
    return it == rootOf.end() ? id : it->second;
  };
  auto writes = [&](uint32_t pointer) {
    if (auto b = bindingOf.find(root(pointer)); b != bindingOf.end()) written.insert(b->second);
  };
  rhi::forEachInstruction(spirv, [&](uint32_t op, size_t at, uint32_t words) {
    auto word = [&](uint32_t i) { return i < words ? spirv[at + i] : 0u; };
    if (isFilteredSample(op)) use.filteredSampling = true;
    if ((op >= kOpTypeBool && op <= kOpTypeMatrix) || op == kOpTypeArray || op == kOpTypeStruct || op == kOpTypePointer)
    {
      std::vector<uint32_t>& d = types.defs[word(1)];
      d.assign(spirv.begin() + long(at), spirv.begin() + long(at + words));
      d[0] = op;  // the first word holds the word count too
    }
    if (op == kOpConstant && words == 4) types.constants[word(2)] = word(3);
    if (op == kOpVariable && words >= 4 && word(3) == kStorageInput) inputs[word(2)] = word(1);
    if (op == kOpVariable && words >= 4 && word(3) == kStorageWorkgroup)
      use.sharedBytes += types.bytes(types.pointee(word(1)));
    if (op == kOpDecorate && words >= 3 && word(2) == kDecorationBuiltIn) builtIns.insert(word(1));
    if (op == kOpDecorate && words >= 4 && word(2) == kDecorationBinding) bindingOf[word(1)] = word(3);
    if ((op == kOpAccessChain || op == kOpInBoundsAccessChain || op == kOpPtrAccessChain || op == kOpLoad) && words >= 4)
      rootOf[word(2)] = root(word(3));
    if (op == kOpStore) writes(word(1));
    if (op == kOpImageWrite) writes(word(1));
    if (isAtomic(op)) {
      use.atomics = true;
      writes(op == kOpAtomicStore || op == 319 ? word(1) : word(3));
    }
    inFunctions = inFunctions || op == kOpFunction;
    if (inFunctions)
      for (uint32_t w = 1; w < words; ++w)
        if (auto b = bindingOf.find(spirv[at + w]); b != bindingOf.end()) used.insert(b->second);
  });
  for (const auto& [variable, pointerType] : inputs) {
    if (builtIns.count(variable)) continue;
    use.userInputs = true;
    use.inputLocations += types.locations(types.pointee(pointerType));
  }
  std::erase_if(use.resources, [&](const rhi::ShaderResource& res) { return !used.count(res.binding); });
  // Only storage buffers and images are written (a binding of another kind cannot be).
  for (const rhi::ShaderResource& res : use.resources)
    if (written.count(res.binding) &&
        (res.kind == rhi::BindingKind::StorageBuffer || res.kind == rhi::BindingKind::StorageTexture ||
         res.kind == rhi::BindingKind::StorageTexelBuffer))
      use.writtenBindings.push_back(res.binding);
  return use;
}

}  // namespace parity::platforms
