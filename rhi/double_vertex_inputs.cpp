// 64-bit vertex inputs read as 32-bit words (double_vertex_inputs.h). The module is rewritten in
// three steps: read what the rewrite needs, plan the new declarations and the entry point's
// first instructions, then copy the module with them in place.
#include "rhi/double_vertex_inputs.h"

#include <spirv_cross/spirv.h>

#include <map>
#include <set>

#include "rhi/shader_reflection.h"  // forEachInstruction

namespace parity::rhi {

std::vector<WordAttribute> wordAttributes(const DoubleAttribute& a) {
  if (a.components <= 2) return {{a.location, 2 * a.components, 0}};
  return {{a.location, 4, 0}, {a.location + 1, 2 * (a.components - 2), 16}};
}

namespace {

constexpr uint32_t instruction(uint32_t op, size_t words) { return static_cast<uint32_t>(words << 16) | op; }

struct AccessChain {
  size_t at;
  uint32_t resultType, result, base;
};

struct Module {
  std::map<uint32_t, std::vector<uint32_t>> types;  // result id -> the instruction's words
  std::map<std::vector<uint32_t>, uint32_t> typeIds;  // opcode and operands -> result id
  std::map<uint32_t, uint32_t> constants;           // OpConstant (32-bit) -> value
  std::map<uint32_t, uint32_t> locations;
  std::set<uint32_t> placedByComponent, builtIns;
  std::map<uint32_t, size_t> inputs;  // Input variable -> where its OpVariable is
  std::vector<AccessChain> chains;
  size_t entryPointAt = 0, firstDeclarationAt = 0, firstFunctionAt = 0;
  uint32_t entryFunction = 0;
};

bool isPreamble(uint32_t op) {
  switch (op) {
    case SpvOpCapability: case SpvOpExtension: case SpvOpExtInstImport: case SpvOpMemoryModel:
    case SpvOpEntryPoint: case SpvOpExecutionMode: case SpvOpExecutionModeId: case SpvOpString:
    case SpvOpSourceExtension: case SpvOpSource: case SpvOpSourceContinued: case SpvOpName:
    case SpvOpMemberName: case SpvOpModuleProcessed: case SpvOpDecorate: case SpvOpMemberDecorate:
    case SpvOpDecorationGroup: case SpvOpGroupDecorate: case SpvOpGroupMemberDecorate:
    case SpvOpDecorateId: case SpvOpDecorateString: case SpvOpMemberDecorateString: case SpvOpNop:
      return true;
    default: return false;
  }
}

Module read(const std::vector<uint32_t>& spirv) {
  Module m;
  forEachInstruction(spirv, [&](uint32_t op, size_t at, uint32_t n) {
    const uint32_t* w = spirv.data() + at;
    if (!isPreamble(op) && m.firstDeclarationAt == 0) m.firstDeclarationAt = at;
    if (op >= SpvOpTypeVoid && op < SpvOpTypeForwardPointer && n >= 2) {
      m.types[w[1]] = std::vector<uint32_t>(w, w + n);
      std::vector<uint32_t> key{op};
      key.insert(key.end(), w + 2, w + n);
      m.typeIds.emplace(key, w[1]);
    }
    switch (op) {
      case SpvOpEntryPoint:
        if (n >= 3 && w[1] == SpvExecutionModelVertex && m.entryPointAt == 0) {
          m.entryPointAt = at;
          m.entryFunction = w[2];
        }
        break;
      case SpvOpConstant:
        if (n == 4) m.constants[w[2]] = w[3];
        break;
      case SpvOpDecorate:
        if (n >= 4 && w[2] == SpvDecorationLocation) m.locations[w[1]] = w[3];
        if (n >= 3 && w[2] == SpvDecorationComponent) m.placedByComponent.insert(w[1]);
        if (n >= 3 && w[2] == SpvDecorationBuiltIn) m.builtIns.insert(w[1]);
        break;
      case SpvOpVariable:
        if (n >= 4 && w[3] == SpvStorageClassInput && m.firstFunctionAt == 0) m.inputs[w[2]] = at;
        break;
      case SpvOpAccessChain: case SpvOpInBoundsAccessChain:
        if (n >= 4) m.chains.push_back({at, w[1], w[2], w[3]});
        break;
      case SpvOpFunction:
        if (m.firstFunctionAt == 0) m.firstFunctionAt = at;
        break;
      default: break;
    }
  });
  return m;
}

// One double or dvecN of an input: its location, type, component count and access chain.
struct Column {
  uint32_t location, type, rows;
  std::vector<uint32_t> chain;
};

// Appends the columns of `type` at `location` to `out`; false when `type` is not made of 64-bit
// floats alone. `*used` is the locations it takes, as Vulkan counts them.
bool columnsOf(const Module& m, uint32_t type, uint32_t location, const std::vector<uint32_t>& chain,
               std::vector<Column>* out, uint32_t* used) {
  auto t = m.types.find(type);
  if (t == m.types.end()) return false;
  const std::vector<uint32_t>& w = t->second;
  auto isDouble = [&](uint32_t id) {
    auto s = m.types.find(id);
    return s != m.types.end() && (s->second[0] & 0xFFFF) == SpvOpTypeFloat && s->second[2] == 64;
  };
  switch (w[0] & 0xFFFF) {
    case SpvOpTypeFloat:
      if (!isDouble(type)) return false;
      out->push_back({location, type, 1, chain});
      *used = 1;
      return true;
    case SpvOpTypeVector:
      if (!isDouble(w[2])) return false;
      out->push_back({location, type, w[3], chain});
      *used = w[3] > 2 ? 2 : 1;
      return true;
    case SpvOpTypeMatrix: case SpvOpTypeArray: {
      uint32_t count = w[3];
      if ((w[0] & 0xFFFF) == SpvOpTypeArray) {
        auto length = m.constants.find(w[3]);
        if (length == m.constants.end()) return false;
        count = length->second;
      }
      *used = 0;
      for (uint32_t i = 0; i < count; ++i) {
        std::vector<uint32_t> element = chain;
        element.push_back(i);
        uint32_t size = 0;
        if (!columnsOf(m, w[2], location + *used, element, out, &size)) return false;
        *used += size;
      }
      return true;
    }
    default: return false;
  }
}

// New global declarations, each made once and reusing the module's own types.
class Declarations {
 public:
  Declarations(Module& m, uint32_t* bound) : m_(m), bound_(bound) {}

  uint32_t type(std::vector<uint32_t> key) {
    if (auto hit = m_.typeIds.find(key); hit != m_.typeIds.end()) return hit->second;
    const uint32_t id = (*bound_)++;
    m_.typeIds[key] = id;
    std::vector<uint32_t> words{instruction(key[0], key.size() + 1), id};
    words.insert(words.end(), key.begin() + 1, key.end());
    m_.types[id] = words;
    append(words);
    return id;
  }
  uint32_t uintType() { return type({SpvOpTypeInt, 32, 0}); }
  uint32_t vector(uint32_t component, uint32_t count) {
    return count == 1 ? component : type({SpvOpTypeVector, component, count});
  }
  uint32_t pointer(SpvStorageClass storage, uint32_t pointee) { return type({SpvOpTypePointer, uint32_t(storage), pointee}); }

  uint32_t uintConstant(uint32_t value) {
    uint32_t& id = uints_[value];
    if (id == 0) append({instruction(SpvOpConstant, 4), uintType(), id = (*bound_)++, value});
    return id;
  }
  uint32_t doubleConstant(uint32_t doubleType, double value) {
    uint32_t& id = doubles_[value];
    const uint32_t high = value == 1.0 ? 0x3FF00000u : 0u;  // 0.0 and 1.0 are all it needs
    if (id == 0) append({instruction(SpvOpConstant, 5), doubleType, id = (*bound_)++, 0u, high});
    return id;
  }
  uint32_t variable(uint32_t pointerType, SpvStorageClass storage) {
    const uint32_t id = (*bound_)++;
    append({instruction(SpvOpVariable, 4), pointerType, id, uint32_t(storage)});
    return id;
  }
  const std::vector<uint32_t>& words() const { return words_; }

 private:
  void append(const std::vector<uint32_t>& w) { words_.insert(words_.end(), w.begin(), w.end()); }
  Module& m_;
  uint32_t* bound_;
  std::map<uint32_t, uint32_t> uints_;
  std::map<double, uint32_t> doubles_;
  std::vector<uint32_t> words_;
};

}  // namespace

std::string readDoubleInputsAsWords(std::vector<uint32_t>& spirv, const std::vector<DoubleAttribute>& attributes) {
  if (attributes.empty() || spirv.size() < 5) return {};
  Module m = read(spirv);
  if (m.entryPointAt == 0 || m.firstFunctionAt == 0) return {};
  std::map<uint32_t, uint32_t> fed;  // location -> components of the 64-bit attribute there
  for (const DoubleAttribute& a : attributes) fed[a.location] = a.components;

  struct Lowered {
    uint32_t variable, pointee;
    std::vector<Column> columns;
  };
  std::vector<Lowered> lowered;
  for (const auto& [variable, at] : m.inputs) {
    auto location = m.locations.find(variable);
    if (location == m.locations.end() || m.builtIns.count(variable)) continue;
    const uint32_t pointerType = spirv[at + 1];
    auto pointer = m.types.find(pointerType);
    if (pointer == m.types.end() || pointer->second.size() < 4) continue;
    Lowered l{variable, pointer->second[3], {}};
    uint32_t used = 0;
    if (!columnsOf(m, l.pointee, location->second, {}, &l.columns, &used)) continue;
    size_t covered = 0;
    for (const Column& c : l.columns) covered += fed.count(c.location);
    if (covered == 0) continue;
    const std::string where = "the 64-bit vertex input at location " + std::to_string(location->second);
    if (covered != l.columns.size()) return where + " is only partly fed by 64-bit attributes";
    if (m.placedByComponent.count(variable)) return where + " has a Component decoration";
    lowered.push_back(std::move(l));
  }
  if (lowered.empty()) return {};

  uint32_t bound = spirv[3];
  Declarations declare(m, &bound);
  std::set<uint32_t> privatePointers;  // the lowered variables and the access chains into them
  std::map<size_t, uint32_t> chainTypes;  // access chain -> its new (Private) result type
  for (const Lowered& l : lowered) privatePointers.insert(l.variable);
  for (const AccessChain& c : m.chains) {
    if (!privatePointers.count(c.base)) continue;
    privatePointers.insert(c.result);
    chainTypes[c.at] = declare.pointer(SpvStorageClassPrivate, m.types.at(c.resultType)[3]);
  }

  // The word inputs, their locations, and the code that fills each private copy from them.
  std::vector<uint32_t> wordInputs, decorations, fill;
  auto emit = [&fill](std::initializer_list<uint32_t> words) {
    fill.push_back(instruction(*words.begin(), words.size()));
    fill.insert(fill.end(), words.begin() + 1, words.end());
  };
  std::map<uint32_t, uint32_t> privateTypes;  // lowered variable -> its Private pointer type
  for (const Lowered& l : lowered) {
    privateTypes[l.variable] = declare.pointer(SpvStorageClassPrivate, l.pointee);
    for (const Column& c : l.columns) {
      const uint32_t n = fed.at(c.location);
      const uint32_t doubleType = c.rows == 1 ? c.type : m.types.at(c.type)[2];
      std::vector<uint32_t> halves;  // a double or dvec2 for components 0-1, then for 2-3
      for (const WordAttribute& part : wordAttributes({c.location, n})) {
        const uint32_t words = declare.vector(declare.uintType(), part.words);
        const uint32_t input = declare.variable(declare.pointer(SpvStorageClassInput, words), SpvStorageClassInput);
        wordInputs.push_back(input);
        decorations.insert(decorations.end(), {instruction(SpvOpDecorate, 4), input, SpvDecorationLocation, part.location});
        const uint32_t loaded = bound++, value = bound++;
        emit({SpvOpLoad, words, loaded, input});
        emit({SpvOpBitcast, declare.vector(doubleType, part.words / 2), value, loaded});
        halves.push_back(value);
      }
      std::vector<uint32_t> components;
      for (uint32_t k = 0; k < c.rows; ++k) {
        if (k >= n) {
          components.push_back(declare.doubleConstant(doubleType, k == 3 ? 1.0 : 0.0));
        } else if ((k < 2 ? n : n - 2) == 1) {  // that half is a single double
          components.push_back(halves[k / 2]);
        } else {
          components.push_back(bound++);
          emit({SpvOpCompositeExtract, doubleType, components.back(), halves[k / 2], k % 2});
        }
      }
      uint32_t value = components[0];
      if (c.rows > 1) {
        value = bound++;
        fill.push_back(instruction(SpvOpCompositeConstruct, 3 + components.size()));
        fill.insert(fill.end(), {c.type, value});
        fill.insert(fill.end(), components.begin(), components.end());
      }
      uint32_t target = l.variable;
      if (!c.chain.empty()) {
        target = bound++;
        fill.push_back(instruction(SpvOpAccessChain, 4 + c.chain.size()));
        fill.insert(fill.end(), {declare.pointer(SpvStorageClassPrivate, c.type), target, l.variable});
        for (uint32_t index : c.chain) fill.push_back(declare.uintConstant(index));
      }
      emit({SpvOpStore, target, value});
    }
  }

  // The copy: the lowered variables' locations dropped and their declarations moved after the
  // new types, the entry point's interface updated, the fill at the start of its function.
  const bool interfaceListsPrivates = spirv[1] >= 0x00010400;  // SPIR-V 1.4: every global is listed
  std::vector<uint32_t> out(spirv.begin(), spirv.begin() + 5);
  bool inEntryFunction = false, fillPending = false;
  forEachInstruction(spirv, [&](uint32_t op, size_t at, uint32_t n) {
    const uint32_t* w = spirv.data() + at;
    if (at == m.firstDeclarationAt) out.insert(out.end(), decorations.begin(), decorations.end());
    if (at == m.firstFunctionAt) {
      out.insert(out.end(), declare.words().begin(), declare.words().end());
      for (const Lowered& l : lowered)
        out.insert(out.end(), {instruction(SpvOpVariable, 4), privateTypes[l.variable], l.variable, SpvStorageClassPrivate});
    }
    if (fillPending && op != SpvOpVariable && op != SpvOpLine && op != SpvOpNoLine) {
      out.insert(out.end(), fill.begin(), fill.end());
      fillPending = false;
    }
    if (op == SpvOpFunction) inEntryFunction = n >= 3 && w[2] == m.entryFunction;
    if (op == SpvOpLabel && inEntryFunction) {
      fillPending = true;
      inEntryFunction = false;
    }
    if (op == SpvOpVariable && privateTypes.count(w[2])) return;
    if (op == SpvOpDecorate && n >= 3 && privateTypes.count(w[1]) &&
        (w[2] == SpvDecorationLocation || w[2] == SpvDecorationComponent))
      return;
    const size_t start = out.size();
    out.insert(out.end(), w, w + n);
    if (auto chain = chainTypes.find(at); chain != chainTypes.end()) out[start + 1] = chain->second;
    if (at == m.entryPointAt) {
      size_t name = 3;  // the name: a nul-terminated string in whole words
      while (name < n && (w[name] >> 24) != 0) ++name;
      out.resize(start + name + 1);
      for (size_t i = name + 1; i < n; ++i)
        if (interfaceListsPrivates || !privateTypes.count(w[i])) out.push_back(w[i]);
      out.insert(out.end(), wordInputs.begin(), wordInputs.end());
      out[start] = instruction(op, out.size() - start);
    }
  });
  out[3] = bound;
  spirv = std::move(out);
  return {};
}

}  // namespace parity::rhi
