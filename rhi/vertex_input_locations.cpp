#include "rhi/vertex_input_locations.h"

#include <spirv_cross/spirv.h>

#include <algorithm>
#include <map>
#include <set>

#include "rhi/shader_reflection.h"  // forEachInstruction

namespace parity::rhi {

namespace {

struct Module {
  std::map<uint32_t, std::vector<uint32_t>> types;  // result id -> the instruction's words
  std::map<uint32_t, uint32_t> constants;           // OpConstant (32-bit) -> value
  std::map<uint32_t, size_t> locationWords;         // id -> the word holding its Location
  std::set<uint32_t> builtIns;
  std::vector<std::pair<uint32_t, uint32_t>> inputs;  // (variable, pointee type), Input storage

  uint32_t locations(uint32_t type, bool vulkan) const {
    auto t = types.find(type);
    if (t == types.end()) return 1;
    const std::vector<uint32_t>& w = t->second;
    switch (w[0] & 0xFFFF) {
      case SpvOpTypeArray: {
        auto length = constants.find(w[3]);
        return (length == constants.end() ? 1 : length->second) * locations(w[2], vulkan);
      }
      case SpvOpTypeMatrix: return w[3] * locations(w[2], vulkan);
      case SpvOpTypeStruct: {
        uint32_t sum = 0;
        for (size_t member = 2; member < w.size(); ++member) sum += locations(w[member], vulkan);
        return sum;
      }
      case SpvOpTypeVector: {
        auto component = types.find(w[2]);
        const bool wide = component != types.end() && component->second.size() > 2 && component->second[2] == 64;
        return vulkan && wide && w[3] > 2 ? 2 : 1;
      }
      default: return 1;
    }
  }
};

Module read(const std::vector<uint32_t>& spirv) {
  Module m;
  forEachInstruction(spirv, [&](uint32_t op, size_t i, uint32_t n) {
    const uint32_t* w = spirv.data() + i;
    switch (op) {
      case SpvOpTypeInt: case SpvOpTypeFloat: case SpvOpTypeVector: case SpvOpTypeMatrix:
      case SpvOpTypeArray: case SpvOpTypeStruct: case SpvOpTypePointer:
        m.types[w[1]] = std::vector<uint32_t>(w, w + n);
        break;
      case SpvOpConstant:
        if (n >= 4) m.constants[w[2]] = w[3];
        break;
      case SpvOpDecorate:
        if (n >= 4 && w[2] == SpvDecorationLocation) m.locationWords[w[1]] = i + 3;
        if (n >= 3 && w[2] == SpvDecorationBuiltIn) m.builtIns.insert(w[1]);
        break;
      case SpvOpVariable:
        if (n >= 4 && w[3] == SpvStorageClassInput && m.types.count(w[1])) m.inputs.push_back({w[2], m.types[w[1]][3]});
        break;
      default: break;
    }
  });
  return m;
}

}  // namespace

void vulkanVertexInputLocations(std::vector<uint32_t>& spirv) {
  const Module m = read(spirv);
  struct Input {
    uint32_t location, vulkanSize;
    size_t word;
  };
  std::vector<Input> inputs;
  bool differs = false;
  for (const auto& [id, type] : m.inputs) {
    auto word = m.locationWords.find(id);
    if (word == m.locationWords.end() || m.builtIns.count(id)) continue;
    const uint32_t vulkan = m.locations(type, true);
    differs |= vulkan != m.locations(type, false);
    inputs.push_back({spirv[word->second], vulkan, word->second});
  }
  if (!differs) return;
  std::stable_sort(inputs.begin(), inputs.end(), [](const Input& a, const Input& b) { return a.location < b.location; });
  uint32_t shift = 0, end = 0;
  for (const Input& in : inputs) {
    const uint32_t location = std::max(in.location + shift, end);
    shift = location - in.location;
    end = location + in.vulkanSize;
    spirv[in.word] = location;
  }
}

}  // namespace parity::rhi
