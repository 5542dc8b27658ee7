#include "harness/scripts/runner/spirv_edit.h"

#include <spirv-tools/optimizer.hpp>

#include "harness/scripts/runner/support.h"

namespace parity::harness::script::runner {

void optimizeSpirv(std::vector<uint32_t>& module, const std::vector<std::string>& passes, const std::string& shader) {
  spvtools::Optimizer optimizer(SPV_ENV_VULKAN_1_3);
  std::string messages;
  optimizer.SetMessageConsumer([&](spv_message_level_t, const char*, const spv_position_t&, const char* m) {
    messages += std::string(messages.empty() ? "" : "; ") + m;
  });
  for (const std::string& pass : passes) {
    const std::string flag = pass.rfind("--", 0) == 0 ? pass : "--" + pass;
    if (!optimizer.RegisterPassFromFlag(flag))
      throw Unsupported{"SHADER_OPTIMIZATION " + flag + " (not a pass of this SPIRV-Tools)"};
  }
  std::vector<uint32_t> optimized;
  if (!optimizer.Run(module.data(), module.size(), &optimized))
    throw Failure{"SHADER_OPTIMIZATION of shader '" + shader + "' failed: " + messages};
  module = std::move(optimized);
}

std::set<SetBinding> spirvBindings(const std::vector<uint32_t>& spirv) {
  std::map<uint32_t, uint32_t> set, binding;
  for (size_t i = 5; i < spirv.size();) {
    uint32_t op = spirv[i] & 0xFFFF, n = spirv[i] >> 16;
    if (n == 0) break;
    if (op == 71 && n >= 4) {
      if (spirv[i + 2] == 34) set[spirv[i + 1]] = spirv[i + 3];
      if (spirv[i + 2] == 33) binding[spirv[i + 1]] = spirv[i + 3];
    }
    i += n;
  }
  std::set<SetBinding> out;
  for (auto& [id, b] : binding) out.insert({set.count(id) ? set[id] : 0, b});
  return out;
}

void remapSpirv(std::vector<uint32_t>& spirv, const std::map<SetBinding, uint32_t>& map) {
  std::map<uint32_t, uint32_t> set;
  std::map<uint32_t, size_t> setWord, bindingWord;
  for (size_t i = 5; i < spirv.size();) {
    uint32_t op = spirv[i] & 0xFFFF, n = spirv[i] >> 16;
    if (n == 0) break;
    if (op == 71 && n >= 4) {
      if (spirv[i + 2] == 34) setWord[spirv[i + 1]] = i + 3;
      if (spirv[i + 2] == 33) bindingWord[spirv[i + 1]] = i + 3;
    }
    i += n;
  }
  for (auto& [id, bw] : bindingWord) {
    uint32_t s = setWord.count(id) ? spirv[setWord[id]] : 0;
    auto it = map.find({s, spirv[bw]});
    if (it == map.end()) continue;
    spirv[bw] = it->second;
    if (setWord.count(id)) spirv[setWord[id]] = 0;
  }
}

void addMissingDescriptorSets(std::vector<uint32_t>& spirv) {
  std::set<uint32_t> withSet;
  std::vector<std::pair<size_t, uint32_t>> bindings;  // (word after the OpDecorate Binding, id)
  for (size_t i = 5; i < spirv.size();) {
    uint32_t op = spirv[i] & 0xFFFF, n = spirv[i] >> 16;
    if (n == 0 || i + n > spirv.size()) break;
    if (op == 71 && n >= 4 && spirv[i + 2] == 34) withSet.insert(spirv[i + 1]);
    if (op == 71 && n >= 4 && spirv[i + 2] == 33) bindings.push_back({i + n, spirv[i + 1]});
    i += n;
  }
  // From the last, so that the earlier positions stay where they are.
  for (auto it = bindings.rbegin(); it != bindings.rend(); ++it)
    if (!withSet.count(it->second)) spirv.insert(spirv.begin() + long(it->first), {(4u << 16) | 71u, it->second, 34u, 0u});
}

void dropUniformLocations(std::vector<uint32_t>& spirv) {
  std::set<uint32_t> uniforms;
  for (size_t i = 5; i < spirv.size();) {
    uint32_t op = spirv[i] & 0xFFFF, n = spirv[i] >> 16;
    if (n == 0 || i + n > spirv.size()) return;
    if (op == 59 && n >= 4 && (spirv[i + 3] == 0 || spirv[i + 3] == 2 || spirv[i + 3] == 12)) uniforms.insert(spirv[i + 2]);  // UniformConstant, Uniform, StorageBuffer
    i += n;
  }
  std::vector<uint32_t> out(spirv.begin(), spirv.begin() + 5);
  for (size_t i = 5; i < spirv.size();) {
    uint32_t op = spirv[i] & 0xFFFF, n = spirv[i] >> 16;
    const bool uniformLocation = op == 71 && n >= 4 && spirv[i + 2] == 30 && uniforms.count(spirv[i + 1]);  // OpDecorate Location
    if (!uniformLocation) out.insert(out.end(), spirv.begin() + long(i), spirv.begin() + long(i + n));
    i += n;
  }
  spirv = std::move(out);
}

void originAtFirstRow(std::vector<uint32_t>& spirv) {
  for (size_t i = 5; i < spirv.size();) {
    uint32_t op = spirv[i] & 0xFFFF, n = spirv[i] >> 16;
    if (n == 0 || i + n > spirv.size()) break;
    if (op == 16 && n >= 3 && spirv[i + 2] == 8) spirv[i + 2] = 7;  // OpExecutionMode OriginLowerLeft -> OriginUpperLeft
    i += n;
  }
}

std::string looseUniformOf(const std::vector<uint32_t>& spirv) {
  std::map<uint32_t, std::pair<uint32_t, uint32_t>> types;  // id -> (opcode, the operand that leads on)
  std::map<uint32_t, std::string> names;
  std::vector<std::pair<uint32_t, uint32_t>> variables;  // (id, pointer type) in UniformConstant
  for (size_t i = 5; i < spirv.size();) {
    uint32_t op = spirv[i] & 0xFFFF, n = spirv[i] >> 16;
    if (n == 0 || i + n > spirv.size()) break;
    if (op == 5 && n >= 3) {  // OpName
      for (size_t w = i + 2; w < i + n; ++w)
        for (int byte = 0; byte < 4; ++byte)
          if (char ch = static_cast<char>((spirv[w] >> (8 * byte)) & 0xFF)) names[spirv[i + 1]] += ch;
    }
    if ((op == 28 || op == 29) && n >= 3) types[spirv[i + 1]] = {op, spirv[i + 2]};           // OpTypeArray/RuntimeArray: element
    else if (op == 32 && n == 4) types[spirv[i + 1]] = {op, spirv[i + 3]};                    // OpTypePointer: pointee
    else if (op >= 19 && op <= 39 && n >= 2) types[spirv[i + 1]] = {op, 0};
    else if (op == 5341 && n >= 2) types[spirv[i + 1]] = {op, 0};                             // OpTypeAccelerationStructureKHR
    if (op == 59 && n >= 4 && spirv[i + 3] == 0) variables.push_back({spirv[i + 2], spirv[i + 1]});  // OpVariable UniformConstant
    i += n;
  }
  for (const auto& [id, pointer] : variables) {
    uint32_t t = types.count(pointer) ? types[pointer].second : 0;
    while (types.count(t) && (types[t].first == 28 || types[t].first == 29)) t = types[t].second;
    const uint32_t op = types.count(t) ? types[t].first : 0;
    if (op != 25 && op != 26 && op != 27 && op != 5341)  // OpTypeImage, OpTypeSampler, OpTypeSampledImage
      return names.count(id) && !names[id].empty() ? names[id] : "%" + std::to_string(id);
  }
  return {};
}

void specializeSpirv(std::vector<uint32_t>& spirv, const std::map<uint32_t, uint32_t>& values, const std::string& shader) {
  std::map<uint32_t, uint32_t> idOfSpecId;
  for (size_t i = 5; i < spirv.size();) {
    uint32_t op = spirv[i] & 0xFFFF, n = spirv[i] >> 16;
    if (n == 0 || i + n > spirv.size()) break;
    if (op == 71 && n >= 4 && spirv[i + 2] == 1) idOfSpecId[spirv[i + 3]] = spirv[i + 1];  // OpDecorate SpecId
    i += n;
  }
  std::set<uint32_t> done;
  for (size_t i = 5; i < spirv.size();) {
    uint32_t op = spirv[i] & 0xFFFF, n = spirv[i] >> 16;
    if (n == 0 || i + n > spirv.size()) break;
    bool specConstant = op >= 48 && op <= 52;  // OpSpecConstantTrue/False, OpSpecConstant(Composite/Op)
    for (const auto& [specId, bits] : values) {
      auto id = idOfSpecId.find(specId);
      if (!specConstant || id == idOfSpecId.end() || n < 3 || spirv[i + 2] != id->second) continue;
      if (op != 50 || n != 4)  // OpSpecConstant with one literal word: a 32-bit scalar
        throw Unsupported{"SPECIALIZE " + std::to_string(specId) + " of a constant that is not a 32-bit scalar"};
      spirv[i + 3] = bits;
      done.insert(specId);
    }
    i += n;
  }
  for (const auto& [specId, bits] : values)
    if (!done.count(specId))
      throw Failure{"SPECIALIZE " + std::to_string(specId) + ": shader '" + shader + "' has no specialization constant with that id"};
}

}  // namespace parity::harness::script::runner
