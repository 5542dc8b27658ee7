// Module rewrites for drivers and translators (spirv_lowering.h). The module is read with
// SPIRV-Tools' parser, which knows each instruction's result type and id.
#include "rhi/spirv_lowering.h"

#include <spirv-tools/libspirv.h>
#include <glslang/SPIRV/GLSL.std.450.h>
#include <spirv_cross/spirv.h>

#include <climits>
#include <map>
#include <memory>
#include <utility>

#include "rhi/shader_reflection.h"  // forEachInstruction

namespace parity::rhi {

namespace {

struct IntType {
  uint32_t width = 32;
  bool isSigned = true;
};

// One Ldexp to rewrite: where its instruction starts and the exponent's operand word.
struct LdexpSite {
  size_t at = 0;
  size_t exponentWord = 0;
  uint32_t exponent = 0;
};

struct ModuleFacts {
  const uint32_t* base = nullptr;
  std::map<uint32_t, uint32_t> typeOf;                       // result id -> its type
  std::map<uint32_t, IntType> ints;                           // OpTypeInt
  std::map<uint32_t, std::pair<uint32_t, uint32_t>> vectors;  // OpTypeVector -> (component, count)
  std::vector<LdexpSite> ldexps;
  uint32_t boolType = 0;
  uint32_t glslImport = 0;
  size_t firstFunction = 0;  // word index of the first OpFunction (0: none)
};

spv_result_t collect(void* user, const spv_parsed_instruction_t* inst) {
  auto& facts = *static_cast<ModuleFacts*>(user);
  const size_t at = static_cast<size_t>(inst->words - facts.base);
  if (inst->result_id != 0 && inst->type_id != 0) facts.typeOf[inst->result_id] = inst->type_id;
  switch (inst->opcode) {
    case SpvOpTypeInt:
      facts.ints[inst->result_id] = {inst->words[2], inst->words[3] != 0};
      break;
    case SpvOpTypeBool:
      facts.boolType = inst->result_id;
      break;
    case SpvOpTypeVector:
      facts.vectors[inst->result_id] = {inst->words[2], inst->words[3]};
      break;
    case SpvOpFunction:
      if (facts.firstFunction == 0) facts.firstFunction = at;
      break;
    case SpvOpExtInst:
      if (inst->ext_inst_type == SPV_EXT_INST_TYPE_GLSL_STD_450 && inst->num_operands >= 6 &&
          inst->words[inst->operands[3].offset] == GLSLstd450Ldexp) {
        facts.glslImport = inst->words[inst->operands[2].offset];
        const size_t word = inst->operands[5].offset;
        facts.ldexps.push_back({at, at + word, inst->words[word]});
      }
      break;
    default:
      break;
  }
  return SPV_SUCCESS;
}

// The types and constants the rewrite needs: those the module declares, or new declarations that
// go before its first function, each made once.
class Declarations {
 public:
  Declarations(const ModuleFacts& facts, uint32_t* bound)
      : ints_(facts.ints), vectors_(facts.vectors), bool_(facts.boolType), bound_(bound) {}

  uint32_t int32(uint32_t count) {
    uint32_t scalar = 0;
    for (const auto& [id, t] : ints_)
      if (t.width == 32 && t.isSigned) scalar = id;
    if (scalar == 0) {
      scalar = add({SpvOpTypeInt, 0, 32, 1}, 1);
      ints_[scalar] = {32, true};
    }
    return vector(scalar, count);
  }

  uint32_t boolean(uint32_t count) {
    if (bool_ == 0) bool_ = add({SpvOpTypeBool, 0}, 1);
    return vector(bool_, count);
  }

  // A constant of `type` (a scalar or vector of 32- or 64-bit ints) with every component `value`.
  uint32_t constant(uint32_t type, int64_t value) {
    const auto key = std::make_pair(type, value);
    if (auto hit = constants_.find(key); hit != constants_.end()) return hit->second;
    uint32_t id = 0;
    if (auto v = vectors_.find(type); v != vectors_.end()) {
      std::vector<uint32_t> composite{SpvOpConstantComposite, type, 0};
      composite.insert(composite.end(), v->second.second, constant(v->second.first, value));
      id = add(composite, 2);
    } else {
      const auto bits = static_cast<uint64_t>(value);
      std::vector<uint32_t> scalar{SpvOpConstant, type, 0, static_cast<uint32_t>(bits)};
      if (ints_.at(type).width == 64) scalar.push_back(static_cast<uint32_t>(bits >> 32));
      id = add(scalar, 2);
    }
    return constants_[key] = id;
  }

  const std::vector<uint32_t>& words() const { return words_; }

 private:
  uint32_t vector(uint32_t component, uint32_t count) {
    if (count == 1) return component;
    for (const auto& [id, v] : vectors_)
      if (v.first == component && v.second == count) return id;
    const uint32_t id = add({SpvOpTypeVector, 0, component, count}, 1);
    vectors_[id] = {component, count};
    return id;
  }

  // `instruction` without its word count, with a 0 at `resultWord` for the new id.
  uint32_t add(std::vector<uint32_t> instruction, size_t resultWord) {
    const uint32_t id = (*bound_)++;
    instruction[resultWord] = id;
    instruction[0] |= static_cast<uint32_t>(instruction.size()) << 16;
    words_.insert(words_.end(), instruction.begin(), instruction.end());
    return id;
  }

  std::map<uint32_t, IntType> ints_;
  std::map<uint32_t, std::pair<uint32_t, uint32_t>> vectors_;
  uint32_t bool_ = 0;
  uint32_t* bound_;
  std::map<std::pair<uint32_t, int64_t>, uint32_t> constants_;
  std::vector<uint32_t> words_;
};

}  // namespace

std::string narrowLdexpExponents(std::vector<uint32_t>& spirv) {
  // Every shader of every case passes here: a word scan for an extended instruction numbered as
  // Ldexp spares the others the full parse below.
  bool mayHaveLdexp = false;
  forEachInstruction(spirv, [&](uint32_t op, size_t at, uint32_t words) {
    mayHaveLdexp |= op == SpvOpExtInst && words >= 5 && spirv[at + 4] == GLSLstd450Ldexp;
  });
  if (!mayHaveLdexp) return {};
  ModuleFacts facts;
  facts.base = spirv.data();
  std::unique_ptr<spv_context_t, void (*)(spv_context)> context(spvContextCreate(SPV_ENV_UNIVERSAL_1_6),
                                                                 spvContextDestroy);
  if (spvBinaryParse(context.get(), &facts, spirv.data(), spirv.size(), nullptr, collect, nullptr) != SPV_SUCCESS)
    return {};  // not this rewrite's business: the backend reports a module it cannot use

  // The exponent's scalar type and component count.
  auto exponentType = [&](uint32_t exponent, IntType* scalar, uint32_t* count) {
    auto type = facts.typeOf.find(exponent);
    if (type == facts.typeOf.end()) return false;
    uint32_t component = type->second;
    *count = 1;
    if (auto v = facts.vectors.find(component); v != facts.vectors.end()) {
      component = v->second.first;
      *count = v->second.second;
    }
    auto i = facts.ints.find(component);
    if (i == facts.ints.end()) return false;
    *scalar = i->second;
    return true;
  };

  uint32_t bound = spirv[3];
  Declarations declarations(facts, &bound);
  std::map<uint32_t, int> widths;  // exponent width -> ldexps narrowed
  // From the last site to the first, so that each insertion leaves the sites before it in place.
  for (auto site = facts.ldexps.rbegin(); site != facts.ldexps.rend(); ++site) {
    IntType scalar;
    uint32_t count = 1;
    if (!exponentType(site->exponent, &scalar, &count) || scalar.width == 32 || !scalar.isSigned) continue;
    const uint32_t int32Type = declarations.int32(count);
    std::vector<uint32_t> code;
    uint32_t narrowed = bound++;
    code.insert(code.end(), {(4u << 16) | SpvOpSConvert, int32Type, narrowed, site->exponent});
    if (scalar.width == 64) {
      // Compare and select rather than SClamp or SMin/SMax: Mesa 22.3's GLSL compiler crashes on
      // 64-bit integer min/max/clamp (the GL backend's path), and this form is as exact.
      const uint32_t type = facts.typeOf[site->exponent], bools = declarations.boolean(count);
      const uint32_t below = bound++, above = bound++, raised = bound++, clamped = bound++;
      code.insert(code.end(), {(5u << 16) | SpvOpSLessThan, bools, below, site->exponent,
                               declarations.constant(type, INT32_MIN)});
      code.insert(code.end(), {(5u << 16) | SpvOpSGreaterThan, bools, above, site->exponent,
                               declarations.constant(type, INT32_MAX)});
      code.insert(code.end(), {(6u << 16) | SpvOpSelect, int32Type, raised, below,
                               declarations.constant(int32Type, INT32_MIN), narrowed});
      code.insert(code.end(), {(6u << 16) | SpvOpSelect, int32Type, clamped, above,
                               declarations.constant(int32Type, INT32_MAX), raised});
      narrowed = clamped;
    }
    spirv[site->exponentWord] = narrowed;
    spirv.insert(spirv.begin() + static_cast<std::ptrdiff_t>(site->at), code.begin(), code.end());
    ++widths[scalar.width];
  }
  if (widths.empty()) return {};
  const std::vector<uint32_t>& added = declarations.words();
  spirv.insert(spirv.begin() + static_cast<std::ptrdiff_t>(facts.firstFunction), added.begin(), added.end());
  spirv[3] = bound;

  std::string note = "ldexp with ";
  for (auto w = widths.begin(); w != widths.end(); ++w)
    note += (w == widths.begin() ? "" : " and ") + std::to_string(w->first) + "-bit";
  return note + " exponents narrowed to 32 bits (clamped first: same results; lavapipe crashes on them, " +
         "SPIRV-Cross truncates them)";
}

namespace {

std::vector<uint32_t> literalWords(const std::string& text) {
  std::vector<uint32_t> words((text.size() + 4) / 4, 0);
  for (size_t i = 0; i < text.size(); ++i) words[i / 4] |= static_cast<uint32_t>(static_cast<unsigned char>(text[i])) << (8 * (i % 4));
  return words;
}

}  // namespace

std::string expandTrinaryMinMax(std::vector<uint32_t>& spirv) {
  constexpr const char* kTrinary = "SPV_AMD_shader_trinary_minmax";
  uint32_t trinaryImport = 0, glslImport = 0;
  forEachInstruction(spirv, [&](uint32_t op, size_t at, uint32_t words) {
    if (op != SpvOpExtInstImport) return;
    const std::string name = spirvLiteralString(spirv, at + 2, at + words);
    if (name == kTrinary) trinaryImport = spirv[at + 1];
    if (name == "GLSL.std.450") glslImport = spirv[at + 1];
  });
  if (trinaryImport == 0) return {};
  uint32_t bound = spirv[3];
  const bool newImport = glslImport == 0;
  if (newImport) glslImport = bound++;
  // The AMD instructions by number (1-9): FMin3, UMin3, SMin3, FMax3, UMax3, SMax3, FMid3, UMid3,
  // SMid3; the GLSL.std.450 min and max of the same kind of operand.
  static const uint32_t kMin[] = {GLSLstd450FMin, GLSLstd450UMin, GLSLstd450SMin};
  static const uint32_t kMax[] = {GLSLstd450FMax, GLSLstd450UMax, GLSLstd450SMax};
  std::vector<uint32_t> out(spirv.begin(), spirv.begin() + 5);
  int expanded = 0;
  bool bad = false;
  forEachInstruction(spirv, [&](uint32_t op, size_t at, uint32_t words) {
    const auto copy = [&] { out.insert(out.end(), spirv.begin() + static_cast<std::ptrdiff_t>(at), spirv.begin() + static_cast<std::ptrdiff_t>(at + words)); };
    if (op == SpvOpExtension && spirvLiteralString(spirv, at + 1, at + words) == kTrinary) return;
    if (op == SpvOpExtInstImport && spirv[at + 1] == trinaryImport) {
      if (!newImport) return;
      std::vector<uint32_t> name = literalWords("GLSL.std.450");
      out.push_back(static_cast<uint32_t>((2 + name.size()) << 16) | SpvOpExtInstImport);
      out.push_back(glslImport);
      out.insert(out.end(), name.begin(), name.end());
      return;
    }
    if (op != SpvOpExtInst || words != 8 || spirv[at + 3] != trinaryImport) {
      bad |= op == SpvOpExtInst && words >= 4 && spirv[at + 3] == trinaryImport;
      return copy();
    }
    const uint32_t type = spirv[at + 1], result = spirv[at + 2], number = spirv[at + 4];
    const uint32_t a = spirv[at + 5], b = spirv[at + 6], c = spirv[at + 7];
    if (number < 1 || number > 9) {
      bad = true;
      return copy();
    }
    const uint32_t kind = (number - 1) % 3, family = (number - 1) / 3;  // family 0 min3, 1 max3, 2 mid3
    const auto call = [&](uint32_t id, uint32_t glsl, uint32_t x, uint32_t y) {
      out.insert(out.end(), {(7u << 16) | SpvOpExtInst, type, id, glslImport, glsl, x, y});
    };
    if (family < 2) {
      const uint32_t f = family == 0 ? kMin[kind] : kMax[kind], pair = bound++;
      call(pair, f, a, b);
      call(result, f, pair, c);
    } else {
      const uint32_t low = bound++, high = bound++, highOrC = bound++;
      call(low, kMin[kind], a, b);
      call(high, kMax[kind], a, b);
      call(highOrC, kMin[kind], high, c);
      call(result, kMax[kind], low, highOrC);
    }
    ++expanded;
  });
  if (bad) return {};  // an instruction of the set this rewrite does not know: left for the driver to judge
  out[3] = bound;
  spirv = std::move(out);
  return std::to_string(expanded) + " min3/max3/mid3 of SPV_AMD_shader_trinary_minmax expanded into GLSL.std.450 min and max " +
         "(the same values; few Vulkan drivers offer the extension)";
}

std::string lowerForDrivers(std::vector<uint32_t>& spirv) {
  std::string notes;
  for (std::string note : {narrowLdexpExponents(spirv), expandTrinaryMinMax(spirv)})
    if (!note.empty()) notes += (notes.empty() ? "" : "; ") + note;
  return notes;
}

}  // namespace parity::rhi
