// VkRunner's pipeline properties and entry points (its README, "[test] section"): a property
// names a member of the structures VkGraphicsPipelineCreateInfo points to and takes a value for
// the draws after it; draws with different sets of properties run different pipelines.
#include "harness/scripts/shader_test/steps.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace parity::harness::script::shader_test {

namespace {

enum class PropertyType { Bool, Float, Uint, Enum, Flags };

struct PropertyDef {
  const char* name;
  PropertyType type;
  const char* prefix;               // of the Vulkan names its values take
  std::vector<const char*> values;  // Enum: names by Vulkan value; Flags: names of bits 0, 1, ...
  const char* defaultValue;         // VkRunner's, canonical (see canonical())
};

const std::vector<const char*> kCompareOps = {"NEVER", "LESS", "EQUAL", "LESS_OR_EQUAL", "GREATER", "NOT_EQUAL", "GREATER_OR_EQUAL", "ALWAYS"};
const std::vector<const char*> kStencilOps = {"KEEP", "ZERO", "REPLACE", "INCREMENT_AND_CLAMP", "DECREMENT_AND_CLAMP", "INVERT",
                                              "INCREMENT_AND_WRAP", "DECREMENT_AND_WRAP"};
const std::vector<const char*> kBlendFactors = {
    "ZERO", "ONE", "SRC_COLOR", "ONE_MINUS_SRC_COLOR", "DST_COLOR", "ONE_MINUS_DST_COLOR", "SRC_ALPHA", "ONE_MINUS_SRC_ALPHA",
    "DST_ALPHA", "ONE_MINUS_DST_ALPHA", "CONSTANT_COLOR", "ONE_MINUS_CONSTANT_COLOR", "CONSTANT_ALPHA", "ONE_MINUS_CONSTANT_ALPHA",
    "SRC_ALPHA_SATURATE", "SRC1_COLOR", "ONE_MINUS_SRC1_COLOR", "SRC1_ALPHA", "ONE_MINUS_SRC1_ALPHA"};
const std::vector<const char*> kBlendOps = {"ADD", "SUBTRACT", "REVERSE_SUBTRACT", "MIN", "MAX"};

// Every property of VkRunner's pipeline key, with its defaults.
const std::vector<PropertyDef>& properties() {
  static const std::vector<PropertyDef> k = {
      {"topology", PropertyType::Enum, "VK_PRIMITIVE_TOPOLOGY_",
       {"POINT_LIST", "LINE_LIST", "LINE_STRIP", "TRIANGLE_LIST", "TRIANGLE_STRIP", "TRIANGLE_FAN", "LINE_LIST_WITH_ADJACENCY",
        "LINE_STRIP_WITH_ADJACENCY", "TRIANGLE_LIST_WITH_ADJACENCY", "TRIANGLE_STRIP_WITH_ADJACENCY", "PATCH_LIST"},
       "triangle_strip"},
      {"primitiveRestartEnable", PropertyType::Bool, "", {}, "false"},
      {"patchControlPoints", PropertyType::Uint, "", {}, "0"},
      {"depthClampEnable", PropertyType::Bool, "", {}, "false"},
      {"rasterizerDiscardEnable", PropertyType::Bool, "", {}, "false"},
      {"polygonMode", PropertyType::Enum, "VK_POLYGON_MODE_", {"FILL", "LINE", "POINT"}, "fill"},
      {"cullMode", PropertyType::Flags, "VK_CULL_MODE_", {"FRONT_BIT", "BACK_BIT"}, "0"},
      {"frontFace", PropertyType::Enum, "VK_FRONT_FACE_", {"COUNTER_CLOCKWISE", "CLOCKWISE"}, "counter_clockwise"},
      {"depthBiasEnable", PropertyType::Bool, "", {}, "false"},
      {"depthBiasConstantFactor", PropertyType::Float, "", {}, "0"},
      {"depthBiasClamp", PropertyType::Float, "", {}, "0"},
      {"depthBiasSlopeFactor", PropertyType::Float, "", {}, "0"},
      {"lineWidth", PropertyType::Float, "", {}, "1"},
      {"logicOpEnable", PropertyType::Bool, "", {}, "false"},
      {"logicOp", PropertyType::Enum, "VK_LOGIC_OP_",
       {"CLEAR", "AND", "AND_REVERSE", "COPY", "AND_INVERTED", "NO_OP", "XOR", "OR", "NOR", "EQUIVALENT", "INVERT", "OR_REVERSE",
        "COPY_INVERTED", "OR_INVERTED", "NAND", "SET"},
       "set"},
      {"blendEnable", PropertyType::Bool, "", {}, "false"},
      {"srcColorBlendFactor", PropertyType::Enum, "VK_BLEND_FACTOR_", kBlendFactors, "src_alpha"},
      {"dstColorBlendFactor", PropertyType::Enum, "VK_BLEND_FACTOR_", kBlendFactors, "one_minus_src_alpha"},
      {"colorBlendOp", PropertyType::Enum, "VK_BLEND_OP_", kBlendOps, "add"},
      {"srcAlphaBlendFactor", PropertyType::Enum, "VK_BLEND_FACTOR_", kBlendFactors, "src_alpha"},
      {"dstAlphaBlendFactor", PropertyType::Enum, "VK_BLEND_FACTOR_", kBlendFactors, "one_minus_src_alpha"},
      {"alphaBlendOp", PropertyType::Enum, "VK_BLEND_OP_", kBlendOps, "add"},
      {"colorWriteMask", PropertyType::Flags, "VK_COLOR_COMPONENT_", {"R_BIT", "G_BIT", "B_BIT", "A_BIT"}, "15"},
      {"depthTestEnable", PropertyType::Bool, "", {}, "false"},
      {"depthWriteEnable", PropertyType::Bool, "", {}, "false"},
      {"depthCompareOp", PropertyType::Enum, "VK_COMPARE_OP_", kCompareOps, "less"},
      {"depthBoundsTestEnable", PropertyType::Bool, "", {}, "false"},
      {"stencilTestEnable", PropertyType::Bool, "", {}, "false"},
      {"front.failOp", PropertyType::Enum, "VK_STENCIL_OP_", kStencilOps, "keep"},
      {"front.passOp", PropertyType::Enum, "VK_STENCIL_OP_", kStencilOps, "keep"},
      {"front.depthFailOp", PropertyType::Enum, "VK_STENCIL_OP_", kStencilOps, "keep"},
      {"front.compareOp", PropertyType::Enum, "VK_COMPARE_OP_", kCompareOps, "always"},
      {"front.compareMask", PropertyType::Uint, "", {}, "4294967295"},
      {"front.writeMask", PropertyType::Uint, "", {}, "4294967295"},
      {"front.reference", PropertyType::Uint, "", {}, "0"},
      {"back.failOp", PropertyType::Enum, "VK_STENCIL_OP_", kStencilOps, "keep"},
      {"back.passOp", PropertyType::Enum, "VK_STENCIL_OP_", kStencilOps, "keep"},
      {"back.depthFailOp", PropertyType::Enum, "VK_STENCIL_OP_", kStencilOps, "keep"},
      {"back.compareOp", PropertyType::Enum, "VK_COMPARE_OP_", kCompareOps, "always"},
      {"back.compareMask", PropertyType::Uint, "", {}, "4294967295"},
      {"back.writeMask", PropertyType::Uint, "", {}, "4294967295"},
      {"back.reference", PropertyType::Uint, "", {}, "0"},
      {"minDepthBounds", PropertyType::Float, "", {}, "0"},
      {"maxDepthBounds", PropertyType::Float, "", {}, "0"},
  };
  return k;
}

const PropertyDef* findProperty(const std::string& name) {
  for (const PropertyDef& d : properties())
    if (name == d.name) return &d;
  return nullptr;
}

const char* const kStages[] = {"vertex", "tessellation control", "tessellation evaluation", "geometry", "fragment", "compute"};

Stage stageOf(const std::string& name) {
  static const std::map<std::string, Stage> k = {{"vertex", Stage::Vertex}, {"tessellation control", Stage::TessControl},
                                                 {"tessellation evaluation", Stage::TessEvaluation}, {"geometry", Stage::Geometry},
                                                 {"fragment", Stage::Fragment}, {"compute", Stage::Compute}};
  return k.at(name);
}

}  // namespace

bool DrawCommands::isPipelineProperty(const std::string& name) { return findProperty(name) != nullptr; }

// The value in canonical form: "true"/"false", a number (Float, Uint, the bits of Flags) or an
// Enum's Vulkan name in lower case without its prefix ("less_or_equal", as Amber spells them).
// VkRunner takes numbers for every integer property and ORs values joined by '|'.
void DrawCommands::pipelineState(int line, const std::vector<std::string>& w) {
  // STAGE entrypoint NAME, the stage in one or two words.
  const auto at = std::find(w.begin(), w.end(), "entrypoint");
  if (at != w.end()) {
    std::string stage;
    for (auto it = w.begin(); it != at; ++it) stage += (stage.empty() ? "" : " ") + *it;
    if (std::find(std::begin(kStages), std::end(kStages), stage) == std::end(kStages))
      error(line, "unknown stage '" + stage + "' (vertex, tessellation control, tessellation evaluation, geometry, fragment, compute)");
    if (at + 2 != w.end()) error(line, stage + " entrypoint needs one name");
    properties_[stage + " entrypoint"] = *(at + 1);
    return;
  }
  const PropertyDef& d = *findProperty(w[0]);
  std::string text;
  for (size_t i = 1; i < w.size(); ++i) text += (i > 1 ? " " : "") + w[i];
  if (text.empty()) error(line, w[0] + " needs a value");
  Value number;
  std::string value;
  if (d.type == PropertyType::Bool) {
    if (text == "true" || text == "false") value = text;
    else if (parseNumber(text, &number) && number.isInteger) value = number.i ? "true" : "false";
    else error(line, w[0] + " takes true, false or an integer, got '" + text + "'");
  } else if (d.type == PropertyType::Float) {
    if (!parseNumber(text, &number)) error(line, w[0] + " needs a number, got '" + text + "'");
    std::ostringstream out;
    out.precision(9);
    out << static_cast<float>(number.d);
    value = out.str();
  } else {
    // Integers, Vulkan names, or several of them joined by '|'.
    int64_t bits = 0;
    std::vector<std::string> parts;
    std::string part;
    for (char ch : text + "|") {
      if (ch != '|') {
        part += ch;
        continue;
      }
      parts.push_back(trim(part));
      part.clear();
    }
    for (const std::string& p : parts) {
      if (parseNumber(p, &number) && number.isInteger && number.i >= 0 && number.i <= 0xFFFFFFFFll) {
        bits |= number.i;
        continue;
      }
      const std::string prefix = d.prefix;
      int64_t found = -1;
      if (!prefix.empty() && p.rfind(prefix, 0) == 0)
        for (size_t i = 0; i < d.values.size(); ++i)
          if (p.substr(prefix.size()) == d.values[i]) found = d.type == PropertyType::Flags ? int64_t(1) << i : int64_t(i);
      if (d.type == PropertyType::Flags && (p == prefix + "NONE")) found = 0;
      if (d.type == PropertyType::Flags && (p == prefix + "FRONT_AND_BACK")) found = 3;
      if (found < 0) {
        std::string names;
        for (const char* v : d.values) names += (names.empty() ? "" : ", ") + prefix + v;
        error(line, w[0] + ": unknown value '" + p + "'" + (names.empty() ? " (a number)" : " (" + names + " or a number)"));
      }
      bits |= found;
    }
    if (d.type == PropertyType::Enum) {
      if (bits >= static_cast<int64_t>(d.values.size())) error(line, w[0] + ": no value " + std::to_string(bits));
      value = lower(d.values[static_cast<size_t>(bits)]);
    } else {
      value = std::to_string(bits);
    }
  }
  // The patch size is a draw's, as `patch parameter vertices` sets it.
  if (w[0] == "patchControlPoints") {
    patchVertices_ = static_cast<uint32_t>(std::stoul(value));
    return;
  }
  properties_[w[0]] = value;
}

void DrawCommands::applyProperties(Pipeline& p) const {
  auto has = [&](const std::string& name) { return properties_.count(name) != 0; };
  auto get = [&](const std::string& name) {
    auto it = properties_.find(name);
    return it != properties_.end() ? it->second : std::string(findProperty(name)->defaultValue);
  };
  auto uint = [&](const std::string& name) { return static_cast<uint32_t>(std::stoul(get(name))); };
  for (const std::string& n : p.shaders) {
    const Shader* s = script_.findShader(n);
    for (const char* stage : kStages)
      if (s && s->stage == stageOf(stage) && has(std::string(stage) + " entrypoint"))
        p.entryPoints[n] = get(std::string(stage) + " entrypoint");
  }
  if (p.compute) return;
  if (has("depthTestEnable")) p.depthTest = get("depthTestEnable") == "true";
  if (has("depthWriteEnable")) p.depthWrite = get("depthWriteEnable") == "true";
  if (has("depthCompareOp")) p.depthCompare = get("depthCompareOp");
  if (has("depthClampEnable")) p.depthClamp = get("depthClampEnable") == "true";
  if (has("polygonMode")) p.polygonMode = get("polygonMode");
  if (has("frontFace")) p.frontFace = get("frontFace");
  if (has("cullMode")) {
    const uint32_t m = uint("cullMode");
    p.cullMode = m == 0 ? "none" : m == 1 ? "front" : m == 2 ? "back" : "front_and_back";
  }
  if (has("depthBiasEnable") || has("depthBiasConstantFactor") || has("depthBiasClamp") || has("depthBiasSlopeFactor")) {
    const bool on = get("depthBiasEnable") == "true";
    p.depthBiasConstant = on ? std::stof(get("depthBiasConstantFactor")) : 0;
    p.depthBiasClamp = on ? std::stof(get("depthBiasClamp")) : 0;
    p.depthBiasSlope = on ? std::stof(get("depthBiasSlopeFactor")) : 0;
  }
  if (has("blendEnable")) {
    p.blend.enabled = get("blendEnable") == "true";
    p.blend.srcColor = get("srcColorBlendFactor"), p.blend.dstColor = get("dstColorBlendFactor");
    p.blend.colorOp = get("colorBlendOp");
    p.blend.srcAlpha = get("srcAlphaBlendFactor"), p.blend.dstAlpha = get("dstAlphaBlendFactor");
    p.blend.alphaOp = get("alphaBlendOp");
  }
  if (has("colorWriteMask")) p.colorWriteMask = static_cast<uint8_t>(uint("colorWriteMask") & 0xF);
  for (const std::string face : {"front", "back"}) {
    StencilFace& f = face == "front" ? p.front : p.back;
    if (has("stencilTestEnable")) f.test = get("stencilTestEnable") == "true";
    if (has(face + ".failOp")) f.failOp = get(face + ".failOp");
    if (has(face + ".passOp")) f.passOp = get(face + ".passOp");
    if (has(face + ".depthFailOp")) f.depthFailOp = get(face + ".depthFailOp");
    if (has(face + ".compareOp")) f.compareOp = get(face + ".compareOp");
    // The RHI's stencil values are 8 bits, as every stencil format here is.
    if (has(face + ".compareMask")) f.compareMask = uint(face + ".compareMask") & 0xFF;
    if (has(face + ".writeMask")) f.writeMask = uint(face + ".writeMask") & 0xFF;
    if (has(face + ".reference")) f.reference = uint(face + ".reference") & 0xFF;
  }
}

std::string DrawCommands::propertiesPipeline(int line, const std::string& base, const std::string& topology, bool indexed) {
  if (!propertiesOfFirstDraw_) {
    for (Pipeline& p : script_.pipelines) applyProperties(p);
    propertiesOfFirstDraw_ = properties_;
  }
  const bool compute = pipeline(base)->compute;
  // What a pipeline of this kind depends on: a compute pipeline its entry point alone.
  auto relevant = [&](const std::map<std::string, std::string>& all) {
    std::map<std::string, std::string> out;
    for (const auto& [name, value] : all)
      if ((name == "compute entrypoint") == compute) out[name] = value;
    return out;
  };
  if (!compute) {
    auto on = [&](const std::string& name) { return properties_.count(name) && properties_.at(name) != "false"; };
    if (on("rasterizerDiscardEnable")) unsupported(line, "rasterizerDiscardEnable true");
    if (on("logicOpEnable")) unsupported(line, "logicOpEnable true (logic operations)");
    if (on("depthBoundsTestEnable")) unsupported(line, "depthBoundsTestEnable true");
    if (on("primitiveRestartEnable") && indexed) unsupported(line, "primitiveRestartEnable true");
    if (properties_.count("cullMode") && properties_.at("cullMode") == "3") unsupported(line, "cullMode VK_CULL_MODE_FRONT_AND_BACK");
    const bool lines = topology.find("LINE") != std::string::npos ||
                       (properties_.count("polygonMode") && properties_.at("polygonMode") == "line");
    if (lines && properties_.count("lineWidth") && std::stof(properties_.at("lineWidth")) != 1.0f)
      unsupported(line, "lineWidth " + properties_.at("lineWidth") + " (wide lines)");
  }
  const std::map<std::string, std::string> now = relevant(properties_);
  if (now == relevant(*propertiesOfFirstDraw_)) return base;
  for (size_t i = 0; i < propertyVariants_.size(); ++i)
    if (propertyVariants_[i].first == base && propertyVariants_[i].second == now) return base + " state " + std::to_string(i + 1);
  propertyVariants_.push_back({base, now});
  Pipeline variant = *pipeline(base);
  variant.name = base + " state " + std::to_string(propertyVariants_.size());
  applyProperties(variant);
  script_.pipelines.push_back(variant);
  return variant.name;
}

}  // namespace parity::harness::script::shader_test
