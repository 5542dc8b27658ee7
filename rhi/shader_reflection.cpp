#include "rhi/shader_reflection.h"

#include "rhi/combined_samplers.h"

#include <spirv_cross/spirv_cross_c.h>

#include <algorithm>
#include <memory>
#include <tuple>
#include <unordered_map>

namespace parity::rhi {

namespace {

bool pairLess(const SeparatePair& a, const SeparatePair& b) {
  return std::tie(a.textureBinding, a.samplerBinding, a.depthCompare) <
         std::tie(b.textureBinding, b.samplerBinding, b.depthCompare);
}

struct ContextDeleter {
  void operator()(spvc_context c) const { spvc_context_destroy(c); }
};
using ContextPtr = std::unique_ptr<std::remove_pointer_t<spvc_context>, ContextDeleter>;

void onSpvcError(void* userdata, const char* message) {
  auto* error = static_cast<std::string*>(userdata);
  if (error->empty()) *error = message;
}

// The length of the gl_ClipDistance array the module writes: an Output variable decorated BuiltIn
// ClipDistance, or the member so decorated of an output block (gl_PerVertex), arrays of either per
// vertex (tessellation control) looked through. glslang declares the member in every gl_PerVertex,
// sized 1 where unused, so it counts only where an access chain (or a store) reaches it.
uint32_t outputClipDistances(const std::vector<uint32_t>& w) {
  std::unordered_map<uint32_t, std::vector<uint32_t>> types;  // id -> words from the opcode on
  std::unordered_map<uint32_t, uint32_t> constants, clipMembers;  // struct -> member
  std::vector<uint32_t> clipVariables;
  std::vector<std::pair<uint32_t, uint32_t>> outputs;  // (variable, pointer type)
  std::vector<std::vector<uint32_t>> chains;          // access chains: base, then the index ids
  std::vector<uint32_t> stored;                       // pointers stored to
  forEachInstruction(w, [&](uint32_t op, size_t i, uint32_t n) {
    if (op == SpvOpDecorate && n >= 4 && w[i + 2] == SpvDecorationBuiltIn && w[i + 3] == SpvBuiltInClipDistance)
      clipVariables.push_back(w[i + 1]);
    else if (op == SpvOpMemberDecorate && n >= 5 && w[i + 3] == SpvDecorationBuiltIn && w[i + 4] == SpvBuiltInClipDistance)
      clipMembers[w[i + 1]] = w[i + 2];
    else if (op == SpvOpTypeArray || op == SpvOpTypeStruct || op == SpvOpTypePointer)
      types[w[i + 1]].assign(w.begin() + long(i), w.begin() + long(i + n));
    else if (op == SpvOpConstant && n >= 4)
      constants[w[i + 2]] = w[i + 3];
    else if (op == SpvOpVariable && n >= 4 && w[i + 3] == SpvStorageClassOutput)
      outputs.emplace_back(w[i + 2], w[i + 1]);
    else if ((op == SpvOpAccessChain || op == SpvOpInBoundsAccessChain) && n >= 4)
      chains.emplace_back(w.begin() + long(i + 3), w.begin() + long(i + n));
    else if (op == SpvOpStore && n >= 3)
      stored.push_back(w[i + 1]);
  });
  auto opOf = [&](uint32_t id) { auto t = types.find(id); return t == types.end() ? 0u : t->second[0] & 0xFFFF; };
  auto innermostLength = [&](uint32_t type) {
    uint32_t length = 0;
    for (; opOf(type) == SpvOpTypeArray; type = types[type][2]) length = constants.count(types[type][3]) ? constants[types[type][3]] : 0;
    return length;
  };
  for (const auto& [variable, pointer] : outputs) {
    if (opOf(pointer) != SpvOpTypePointer) continue;
    uint32_t pointee = types[pointer][3];
    if (std::find(clipVariables.begin(), clipVariables.end(), variable) != clipVariables.end()) {
      const bool written = std::count(stored.begin(), stored.end(), variable) > 0 ||
                           std::any_of(chains.begin(), chains.end(), [&](const std::vector<uint32_t>& c) { return c[0] == variable; });
      return written ? innermostLength(pointee) : 0;
    }
    const size_t memberIndex = opOf(pointee) == SpvOpTypeArray ? 2 : 1;  // after the vertex index of gl_out[]
    while (opOf(pointee) == SpvOpTypeArray) pointee = types[pointee][2];
    auto member = clipMembers.find(pointee);
    if (opOf(pointee) != SpvOpTypeStruct || member == clipMembers.end() || member->second + 2 >= types[pointee].size()) continue;
    const bool written = std::any_of(chains.begin(), chains.end(), [&](const std::vector<uint32_t>& c) {
      return c[0] == variable && c.size() > memberIndex && constants.count(c[memberIndex]) && constants[c[memberIndex]] == member->second;
    });
    return written ? innermostLength(types[pointee][member->second + 2]) : 0;
  }
  return 0;
}

}  // namespace

bool reflectSpirv(const std::vector<uint32_t>& spirv, ShaderStage stage, ShaderReflection* out,
                  std::string* error) {
  std::string spvcError;
  spvc_context rawContext = nullptr;
  if (spvc_context_create(&rawContext) != SPVC_SUCCESS) {
    *error = "SPIRV-Cross: cannot create a context";
    return false;
  }
  ContextPtr context(rawContext);
  spvc_context_set_error_callback(rawContext, onSpvcError, &spvcError);

  spvc_parsed_ir ir = nullptr;
  spvc_compiler compiler = nullptr;
  if (spvc_context_parse_spirv(rawContext, spirv.data(), spirv.size(), &ir) != SPVC_SUCCESS ||
      spvc_context_create_compiler(rawContext, SPVC_BACKEND_NONE, ir, SPVC_CAPTURE_MODE_TAKE_OWNERSHIP,
                                   &compiler) != SPVC_SUCCESS) {
    *error = "SPIR-V cannot be parsed: " + spvcError;
    return false;
  }

  spvc_resources resources = nullptr;
  spvc_compiler_create_shader_resources(compiler, &resources);

  ShaderReflection r;
  r.stage = stage;

  auto list = [&](spvc_resource_type type) {
    const spvc_reflected_resource* items = nullptr;
    size_t count = 0;
    spvc_resources_get_resource_list_for_type(resources, type, &items, &count);
    return std::vector<spvc_reflected_resource>(items, items + count);
  };

  struct KindOf {
    spvc_resource_type type;
    BindingKind kind;
  };
  const KindOf kinds[] = {
      {SPVC_RESOURCE_TYPE_UNIFORM_BUFFER, BindingKind::UniformBuffer},
      {SPVC_RESOURCE_TYPE_STORAGE_BUFFER, BindingKind::StorageBuffer},
      {SPVC_RESOURCE_TYPE_SAMPLED_IMAGE, BindingKind::SampledTexture},
      {SPVC_RESOURCE_TYPE_STORAGE_IMAGE, BindingKind::StorageTexture},
      {SPVC_RESOURCE_TYPE_SEPARATE_IMAGE, BindingKind::SeparateTexture},
      {SPVC_RESOURCE_TYPE_SEPARATE_SAMPLERS, BindingKind::SeparateSampler},
  };
  for (const KindOf& k : kinds) {
    for (const spvc_reflected_resource& res : list(k.type)) {
      const std::string name = res.name ? res.name : "";
      uint32_t set = spvc_compiler_get_decoration(compiler, res.id, SpvDecorationDescriptorSet);
      uint32_t binding = spvc_compiler_get_decoration(compiler, res.id, SpvDecorationBinding);
      if (set != 0) {
        *error = "resource '" + name + "' is in descriptor set " + std::to_string(set) +
                 "; parity shaders use set 0 only";
        return false;
      }
      if (binding >= kMaxBindings) {
        *error = "resource '" + name + "' uses binding " + std::to_string(binding) + "; bindings must be below " +
                 std::to_string(kMaxBindings);
        return false;
      }
      ShaderResource sr;
      sr.binding = binding;
      sr.kind = k.kind;
      sr.name = name;
      spvc_type declared = spvc_compiler_get_type_handle(compiler, res.type_id);
      if (unsigned dimensions = spvc_type_get_num_array_dimensions(declared); dimensions > 0) {
        const SpvId size = spvc_type_get_array_dimension(declared, 0);
        if (dimensions > 1 || !spvc_type_array_dimension_is_literal(declared, 0) || size == 0 ||
            size > kMaxArrayElements) {
          *error = "resource '" + name + "' is a descriptor array that is " +
                   (dimensions > 1 ? std::string("of arrays")
                    : !spvc_type_array_dimension_is_literal(declared, 0) ? std::string("sized by a specialization constant")
                    : size == 0 ? std::string("unsized")
                                : "of " + std::to_string(size) + " elements") +
                   "; parity binds one-dimensional arrays of 1.." + std::to_string(kMaxArrayElements) + " resources";
          return false;
        }
        sr.arraySize = size;
      }
      // samplerBuffer and imageBuffer: texel buffers, not textures.
      const bool texelBuffer =
          (k.kind == BindingKind::SampledTexture || k.kind == BindingKind::StorageTexture) &&
          spvc_type_get_image_dimension(spvc_compiler_get_type_handle(compiler, res.type_id)) == SpvDimBuffer;
      if (texelBuffer)
        sr.kind = k.kind == BindingKind::SampledTexture ? BindingKind::UniformTexelBuffer : BindingKind::StorageTexelBuffer;
      if (k.kind == BindingKind::SampledTexture || k.kind == BindingKind::StorageTexture ||
          k.kind == BindingKind::SeparateTexture) {
        spvc_type type = spvc_compiler_get_type_handle(compiler, res.type_id);
        if (k.kind == BindingKind::SeparateTexture && spvc_type_get_image_dimension(type) == SpvDimBuffer) {
          *error = "resource '" + name + "' is a texelBuffer without a sampler; use samplerBuffer";
          return false;
        }
        sr.multisampled = spvc_type_get_image_multisampled(type);
        sr.arrayed = spvc_type_get_image_arrayed(type);
        sr.cube = spvc_type_get_image_dimension(type) == SpvDimCube;
        if (spvc_type_get_image_dimension(type) == SpvDim1D) sr.dimensions = 1;
        if (spvc_type_get_image_dimension(type) == SpvDim3D) sr.dimensions = 3;
        sr.depthCompare = spvc_type_get_image_is_depth(type);
        spvc_type sampled = spvc_compiler_get_type_handle(compiler, spvc_type_get_image_sampled_type(type));
        spvc_basetype base = spvc_type_get_basetype(sampled);
        sr.integer = base == SPVC_BASETYPE_UINT32 || base == SPVC_BASETYPE_INT32;
      }
      bool aliased = false;
      for (const ShaderResource& existing : r.resources) {
        if (existing.binding != binding) continue;
        // Two blocks of one kind at one binding view one buffer (SPIR-V allows descriptors to
        // alias; GL binds both blocks to the binding's point): the binding is listed once.
        aliased = existing.kind == sr.kind && existing.arraySize == sr.arraySize &&
                  (sr.kind == BindingKind::UniformBuffer || sr.kind == BindingKind::StorageBuffer);
        if (!aliased) {
          *error = "resources '" + existing.name + "' and '" + name + "' share binding " + std::to_string(binding);
          return false;
        }
      }
      if (!aliased) r.resources.push_back(sr);
    }
  }
  // SPIRV-Cross cannot combine arrays of samplers (for GLSL, where the pairs matter: Vulkan binds
  // the halves as they are), so a module with one reports no pairs; the GL device refuses it
  // (Capabilities::separateSamplerArrays).
  const bool samplerArrays = std::any_of(r.resources.begin(), r.resources.end(), [](const ShaderResource& sr) {
    return sr.kind == BindingKind::SeparateSampler && sr.arraySize > 1;
  });
  if (!samplerArrays &&
      (!list(SPVC_RESOURCE_TYPE_SEPARATE_IMAGE).empty() || !list(SPVC_RESOURCE_TYPE_SEPARATE_SAMPLERS).empty())) {
    // Which separate textures and samplers the entry point combines: the same analysis the GL
    // backend runs before emitting GLSL (gl_shader.cpp), so both see the same pairs. The
    // resource lists above were taken first: the dummy sampler and the combined variables this
    // adds are not the module's resources.
    std::vector<CombinedPair> combined;
    if (!combineSeparatePairs(compiler, spirv, &combined)) {
      *error = "separate textures and samplers cannot be analysed: " + spvcError;
      return false;
    }
    for (const CombinedPair& c : combined) r.separatePairs.push_back(c.pair);
    std::sort(r.separatePairs.begin(), r.separatePairs.end(), pairLess);
    r.separatePairs.erase(std::unique(r.separatePairs.begin(), r.separatePairs.end()), r.separatePairs.end());
    if (r.separatePairs.size() > kMaxSeparatePairs) {
      *error = "the shader combines " + std::to_string(r.separatePairs.size()) +
               " separate texture/sampler pairs; at most " + std::to_string(kMaxSeparatePairs) + " are allowed";
      return false;
    }
  }
  std::sort(r.resources.begin(), r.resources.end(),
            [](const ShaderResource& a, const ShaderResource& b) { return a.binding < b.binding; });

  for (const spvc_reflected_resource& res : list(SPVC_RESOURCE_TYPE_PUSH_CONSTANT)) {
    size_t size = 0;
    spvc_compiler_get_declared_struct_size(compiler, spvc_compiler_get_type_handle(compiler, res.base_type_id),
                                           &size);
    r.pushConstantSize = static_cast<uint32_t>(size);
    if (size > kMaxPushConstantBytes) {
      *error = "push-constant block is " + std::to_string(size) + " bytes; at most " +
               std::to_string(kMaxPushConstantBytes) + " are allowed";
      return false;
    }
  }

  if (stage == ShaderStage::Vertex) {
    for (const spvc_reflected_resource& res : list(SPVC_RESOURCE_TYPE_STAGE_INPUT)) {
      const uint32_t location = spvc_compiler_get_decoration(compiler, res.id, SpvDecorationLocation);
      r.inputLocations.push_back(location);
      spvc_type type = spvc_compiler_get_type_handle(compiler, res.type_id);
      if (spvc_type_get_bit_width(type) != 64 || spvc_type_get_vector_size(type) < 3) continue;
      uint32_t vectors = spvc_type_get_columns(type);
      for (unsigned d = 0; d < spvc_type_get_num_array_dimensions(type); ++d) vectors *= spvc_type_get_array_dimension(type, d);
      r.doubleWideInputs.push_back({location, vectors});
    }
    std::sort(r.inputLocations.begin(), r.inputLocations.end());
  }
  if (stage == ShaderStage::Fragment) {
    for (const spvc_reflected_resource& res : list(SPVC_RESOURCE_TYPE_STAGE_OUTPUT)) {
      uint32_t location = spvc_compiler_get_decoration(compiler, res.id, SpvDecorationLocation);
      if (location < 32) r.colorOutputs |= 1u << location;
    }
  }
  if (stage != ShaderStage::Fragment && stage != ShaderStage::Compute) r.clipDistances = outputClipDistances(spirv);
  if (stage == ShaderStage::Vertex)
    forEachInstruction(spirv, [&](uint32_t op, size_t i, uint32_t words) {
      if (op == SpvOpDecorate && words >= 4 && spirv[i + 2] == SpvDecorationBuiltIn && spirv[i + 3] == SpvBuiltInBaseVertex)
        r.readsBaseVertex = true;
    });
  if (stage == ShaderStage::Compute) {
    for (unsigned i = 0; i < 3; ++i)
      r.localSize[i] = spvc_compiler_get_execution_mode_argument_by_index(compiler, SpvExecutionModeLocalSize, i);
  }
  *out = std::move(r);
  return true;
}

bool combineSeparatePairs(spvc_compiler compiler, const std::vector<uint32_t>& spirv, std::vector<CombinedPair>* out) {
  spvc_variable_id dummy = 0;
  if (spvc_compiler_build_dummy_sampler_for_combined_images(compiler, &dummy) != SPVC_SUCCESS ||
      spvc_compiler_build_combined_image_samplers(compiler) != SPVC_SUCCESS)
    return false;
  const spvc_combined_image_sampler* combined = nullptr;
  size_t count = 0;
  spvc_compiler_get_combined_image_samplers(compiler, &combined, &count);
  for (size_t i = 0; i < count; ++i) {
    CombinedPair c;
    c.pair.textureBinding = spvc_compiler_get_decoration(compiler, combined[i].image_id, SpvDecorationBinding);
    c.pair.samplerBinding = combined[i].sampler_id == dummy
                                ? kNoSamplerBinding
                                : spvc_compiler_get_decoration(compiler, combined[i].sampler_id, SpvDecorationBinding);
    // Not spvc_compiler_variable_is_depth_or_compare (it returned 252 for a plain pair with this
    // SPIRV-Cross build) nor the combined variable's reflected type (SPIR-V 1.4+ lists only
    // entry-point interface variables, which the combined ones are not).
    c.pair.depthCompare = sampledAsShadow(spirv, combined[i].image_id, combined[i].sampler_id);
    c.combinedVariable = combined[i].combined_id;
    out->push_back(c);
  }
  return true;
}

bool sampledAsShadow(const std::vector<uint32_t>& spirv, uint32_t imageVar, uint32_t samplerVar) {
  std::unordered_map<uint32_t, bool> depthImage;        // OpTypeImage id -> depth 1
  std::unordered_map<uint32_t, uint32_t> sampledImage;  // OpTypeSampledImage id -> image type
  std::unordered_map<uint32_t, uint32_t> loadedFrom;    // OpLoad result -> pointer
  std::unordered_map<uint32_t, uint32_t> elementOf;     // OpAccessChain result -> base (descriptor arrays)
  struct Combine {
    uint32_t type, image, sampler;
  };
  std::vector<Combine> combines;
  forEachInstruction(spirv, [&](uint32_t op, size_t at, uint32_t words) {
    const uint32_t* w = &spirv[at];
    if (op == SpvOpTypeImage && words >= 9) depthImage[w[1]] = w[4] == 1;
    if (op == SpvOpTypeSampledImage && words >= 3) sampledImage[w[1]] = w[2];
    if (op == SpvOpLoad && words >= 4) loadedFrom[w[2]] = w[3];
    if ((op == SpvOpAccessChain || op == SpvOpInBoundsAccessChain) && words >= 4) elementOf[w[2]] = w[3];
    if (op == SpvOpSampledImage && words >= 5) combines.push_back({w[1], w[3], w[4]});
  });
  for (const Combine& c : combines) {
    auto image = loadedFrom.find(c.image), sampler = loadedFrom.find(c.sampler);
    if (image == loadedFrom.end() || sampler == loadedFrom.end()) continue;
    auto variable = [&](uint32_t pointer) {
      auto base = elementOf.find(pointer);
      return base == elementOf.end() ? pointer : base->second;
    };
    if (variable(image->second) != imageVar || variable(sampler->second) != samplerVar) continue;
    auto type = sampledImage.find(c.type);
    if (type != sampledImage.end() && depthImage[type->second]) return true;
  }
  return false;
}

std::vector<SeparatePair> mergeSeparatePairs(const std::vector<const ShaderReflection*>& stages) {
  std::vector<SeparatePair> pairs;
  for (const ShaderReflection* s : stages) pairs.insert(pairs.end(), s->separatePairs.begin(), s->separatePairs.end());
  std::sort(pairs.begin(), pairs.end(), pairLess);
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

}  // namespace parity::rhi
