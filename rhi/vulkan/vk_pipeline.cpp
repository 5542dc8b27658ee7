// Vulkan backend: graphics and compute pipelines, with their layouts built from reflection.
#include <algorithm>

#include "rhi/double_vertex_inputs.h"
#include "rhi/vulkan/vk_device.h"

namespace parity::rhi::vulkan {

namespace {

VkShaderStageFlagBits toVkStage(ShaderStage s) {
  switch (s) {
    case ShaderStage::Vertex: return VK_SHADER_STAGE_VERTEX_BIT;
    case ShaderStage::Fragment: return VK_SHADER_STAGE_FRAGMENT_BIT;
    case ShaderStage::Compute: return VK_SHADER_STAGE_COMPUTE_BIT;
    case ShaderStage::Geometry: return VK_SHADER_STAGE_GEOMETRY_BIT;
    case ShaderStage::TessControl: return VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT;
    case ShaderStage::TessEvaluation: return VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT;
  }
  return VK_SHADER_STAGE_VERTEX_BIT;
}

VkDescriptorType toVkDescriptorType(BindingKind k) {
  switch (k) {
    case BindingKind::UniformBuffer: return VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    case BindingKind::StorageBuffer: return VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    case BindingKind::SampledTexture: return VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    case BindingKind::StorageTexture: return VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    case BindingKind::SeparateTexture: return VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE;
    case BindingKind::SeparateSampler: return VK_DESCRIPTOR_TYPE_SAMPLER;
    case BindingKind::UniformTexelBuffer: return VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
    case BindingKind::StorageTexelBuffer: return VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER;
  }
  return VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
}

VkPrimitiveTopology toVk(PrimitiveTopology t) {
  switch (t) {
    case PrimitiveTopology::Triangles: return VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    case PrimitiveTopology::TriangleStrip: return VK_PRIMITIVE_TOPOLOGY_TRIANGLE_STRIP;
    case PrimitiveTopology::Lines: return VK_PRIMITIVE_TOPOLOGY_LINE_LIST;
    case PrimitiveTopology::Points: return VK_PRIMITIVE_TOPOLOGY_POINT_LIST;
    case PrimitiveTopology::LineStrip: return VK_PRIMITIVE_TOPOLOGY_LINE_STRIP;
    case PrimitiveTopology::Patches: return VK_PRIMITIVE_TOPOLOGY_PATCH_LIST;
    case PrimitiveTopology::LinesWithAdjacency: return VK_PRIMITIVE_TOPOLOGY_LINE_LIST_WITH_ADJACENCY;
    case PrimitiveTopology::LineStripWithAdjacency: return VK_PRIMITIVE_TOPOLOGY_LINE_STRIP_WITH_ADJACENCY;
    case PrimitiveTopology::TrianglesWithAdjacency: return VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST_WITH_ADJACENCY;
    case PrimitiveTopology::TriangleStripWithAdjacency: return VK_PRIMITIVE_TOPOLOGY_TRIANGLE_STRIP_WITH_ADJACENCY;
  }
  return VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
}

VkPolygonMode toVk(PolygonMode m) {
  switch (m) {
    case PolygonMode::Fill: return VK_POLYGON_MODE_FILL;
    case PolygonMode::Line: return VK_POLYGON_MODE_LINE;
    case PolygonMode::Point: return VK_POLYGON_MODE_POINT;
  }
  return VK_POLYGON_MODE_FILL;
}

VkCullModeFlags toVk(CullMode c) {
  switch (c) {
    case CullMode::None: return VK_CULL_MODE_NONE;
    case CullMode::Front: return VK_CULL_MODE_FRONT_BIT;
    case CullMode::Back: return VK_CULL_MODE_BACK_BIT;
  }
  return VK_CULL_MODE_NONE;
}

VkCompareOp toVk(CompareOp op) {
  switch (op) {
    case CompareOp::Always: return VK_COMPARE_OP_ALWAYS;
    case CompareOp::Never: return VK_COMPARE_OP_NEVER;
    case CompareOp::Less: return VK_COMPARE_OP_LESS;
    case CompareOp::LessEqual: return VK_COMPARE_OP_LESS_OR_EQUAL;
    case CompareOp::Equal: return VK_COMPARE_OP_EQUAL;
    case CompareOp::NotEqual: return VK_COMPARE_OP_NOT_EQUAL;
    case CompareOp::Greater: return VK_COMPARE_OP_GREATER;
    case CompareOp::GreaterEqual: return VK_COMPARE_OP_GREATER_OR_EQUAL;
  }
  return VK_COMPARE_OP_ALWAYS;
}

VkStencilOp toVk(StencilOp op) {
  switch (op) {
    case StencilOp::Keep: return VK_STENCIL_OP_KEEP;
    case StencilOp::Zero: return VK_STENCIL_OP_ZERO;
    case StencilOp::Replace: return VK_STENCIL_OP_REPLACE;
    case StencilOp::IncrementClamp: return VK_STENCIL_OP_INCREMENT_AND_CLAMP;
    case StencilOp::DecrementClamp: return VK_STENCIL_OP_DECREMENT_AND_CLAMP;
    case StencilOp::Invert: return VK_STENCIL_OP_INVERT;
    case StencilOp::IncrementWrap: return VK_STENCIL_OP_INCREMENT_AND_WRAP;
    case StencilOp::DecrementWrap: return VK_STENCIL_OP_DECREMENT_AND_WRAP;
  }
  return VK_STENCIL_OP_KEEP;
}

VkBlendFactor toVk(BlendFactor f) {
  switch (f) {
    case BlendFactor::One: return VK_BLEND_FACTOR_ONE;
    case BlendFactor::Zero: return VK_BLEND_FACTOR_ZERO;
    case BlendFactor::SrcColor: return VK_BLEND_FACTOR_SRC_COLOR;
    case BlendFactor::OneMinusSrcColor: return VK_BLEND_FACTOR_ONE_MINUS_SRC_COLOR;
    case BlendFactor::DstColor: return VK_BLEND_FACTOR_DST_COLOR;
    case BlendFactor::OneMinusDstColor: return VK_BLEND_FACTOR_ONE_MINUS_DST_COLOR;
    case BlendFactor::SrcAlpha: return VK_BLEND_FACTOR_SRC_ALPHA;
    case BlendFactor::OneMinusSrcAlpha: return VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
    case BlendFactor::DstAlpha: return VK_BLEND_FACTOR_DST_ALPHA;
    case BlendFactor::OneMinusDstAlpha: return VK_BLEND_FACTOR_ONE_MINUS_DST_ALPHA;
    case BlendFactor::ConstantColor: return VK_BLEND_FACTOR_CONSTANT_COLOR;
    case BlendFactor::OneMinusConstantColor: return VK_BLEND_FACTOR_ONE_MINUS_CONSTANT_COLOR;
  }
  return VK_BLEND_FACTOR_ONE;
}

VkBlendOp toVk(BlendOp op) {
  switch (op) {
    case BlendOp::Add: return VK_BLEND_OP_ADD;
    case BlendOp::Subtract: return VK_BLEND_OP_SUBTRACT;
    case BlendOp::ReverseSubtract: return VK_BLEND_OP_REVERSE_SUBTRACT;
    case BlendOp::Min: return VK_BLEND_OP_MIN;
    case BlendOp::Max: return VK_BLEND_OP_MAX;
  }
  return VK_BLEND_OP_ADD;
}

VkStencilOpState toVk(const StencilFaceState& s, const DepthStencilState& ds) {
  VkStencilOpState out{};
  out.failOp = toVk(s.fail);
  out.passOp = toVk(s.pass);
  out.depthFailOp = toVk(s.depthFail);
  out.compareOp = toVk(s.compare);
  out.compareMask = ds.stencilReadMask;
  out.writeMask = ds.stencilWriteMask;
  return out;  // reference: dynamic state
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Layouts: one descriptor set (set 0) holding the union of the stages' resources, and one
// push-constant range as large as the largest block any stage declares.
// ---------------------------------------------------------------------------------------------
bool VulkanDevice::buildLayout(const std::vector<const ShaderObject*>& shaders, LayoutInfo* out) {
  std::array<VkShaderStageFlags, kMaxBindings> stagesOf{};
  for (const ShaderObject* s : shaders) {
    const VkShaderStageFlags bit = toVkStage(s->stage);
    out->stages |= bit;
    out->pushConstantSize = std::max(out->pushConstantSize, s->reflection.pushConstantSize);
    for (const ShaderResource& r : s->reflection.resources) {
      if (r.binding >= kMaxBindings) continue;
      if (!stagesOf[r.binding]) out->bindings.push_back(r);
      stagesOf[r.binding] |= bit;
    }
  }
  std::sort(out->bindings.begin(), out->bindings.end(),
            [](const ShaderResource& a, const ShaderResource& b) { return a.binding < b.binding; });
  std::vector<const ShaderReflection*> reflections;
  for (const ShaderObject* s : shaders) reflections.push_back(&s->reflection);
  out->separatePairs = mergeSeparatePairs(reflections);

  std::vector<VkDescriptorSetLayoutBinding> vkBindings;
  for (const ShaderResource& r : out->bindings)
    vkBindings.push_back({r.binding, toVkDescriptorType(r.kind), r.arraySize, stagesOf[r.binding], nullptr});
  VkDescriptorSetLayoutCreateInfo si{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  si.bindingCount = static_cast<uint32_t>(vkBindings.size());
  si.pBindings = vkBindings.data();
  if (vkCreateDescriptorSetLayout(device_, &si, nullptr, &out->setLayout) != VK_SUCCESS) return false;

  VkPushConstantRange range{out->stages, 0, (out->pushConstantSize + 3) & ~3u};
  VkPipelineLayoutCreateInfo li{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  li.setLayoutCount = 1;
  li.pSetLayouts = &out->setLayout;
  li.pushConstantRangeCount = out->pushConstantSize ? 1 : 0;
  li.pPushConstantRanges = &range;
  if (vkCreatePipelineLayout(device_, &li, nullptr, &out->layout) != VK_SUCCESS) {
    vkDestroyDescriptorSetLayout(device_, out->setLayout, nullptr);
    return false;
  }
  return true;
}

void VulkanDevice::destroyLayout(const LayoutInfo& layout) {
  vkDestroyPipelineLayout(device_, layout.layout, nullptr);
  vkDestroyDescriptorSetLayout(device_, layout.setLayout, nullptr);
}

// ---------------------------------------------------------------------------------------------
// Graphics pipelines (dynamic rendering: attachment formats instead of a render pass)
// ---------------------------------------------------------------------------------------------
PipelineHandle VulkanDevice::createPipeline(const PipelineDesc& desc) {
  const ShaderObject* vs = shaders_.get(desc.vertexShader);
  const ShaderObject* fs = shaders_.get(desc.fragmentShader);
  if (!vs) return {};
  std::vector<const ShaderObject*> stageShaders{vs};
  for (ShaderHandle optional : {desc.tessControlShader, desc.tessEvaluationShader, desc.geometryShader})
    if (const ShaderObject* s = shaders_.get(optional)) stageShaders.push_back(s);
  if (fs) stageShaders.push_back(fs);

  PipelineObject p;
  p.desc = desc;
  if (!buildLayout(stageShaders, &p.layout)) return {};

  // Vertex input: a binding for every buffer slot an attribute reads. Without R64* formats a
  // 64-bit attribute is fed as 32-bit words, and the vertex module reads them as such.
  std::vector<VkVertexInputBindingDescription> vbindings;
  std::vector<VkVertexInputAttributeDescription> vattributes;
  std::vector<DoubleAttribute> wordFed;
  const uint32_t attributeCount = std::min<uint32_t>(desc.attributeCount, kMaxVertexAttributes);
  for (uint32_t i = 0; i < attributeCount; ++i) {
    const VertexAttribute& a = desc.attributes[i];
    if (a.format >= VertexFormat::Double && !nativeDoubleVertexFormats_) {
      wordFed.push_back({a.location, uint32_t(a.format) - uint32_t(VertexFormat::Double) + 1});
      for (const WordAttribute& w : wordAttributes(wordFed.back()))
        vattributes.push_back({w.location, a.bufferSlot,
                               w.words == 2 ? VK_FORMAT_R32G32_UINT : VK_FORMAT_R32G32B32A32_UINT, a.offset + w.offset});
    } else {
      vattributes.push_back({a.location, a.bufferSlot, toVkVertexFormat(a.format), a.offset});
    }
    bool known = false;
    for (const auto& b : vbindings) known |= b.binding == a.bufferSlot;
    if (!known && a.bufferSlot < kMaxVertexBuffers) {
      const VertexBufferLayout& l = desc.vertexBuffers[a.bufferSlot];
      vbindings.push_back(
          {a.bufferSlot, l.stride, l.perInstance ? VK_VERTEX_INPUT_RATE_INSTANCE : VK_VERTEX_INPUT_RATE_VERTEX});
    }
  }
  VkShaderModule wordReader = VK_NULL_HANDLE;  // the vertex module, reading 64-bit inputs as words
  if (!wordFed.empty()) {
    std::vector<uint32_t> spirv = vs->spirv;
    if (std::string error = readDoubleInputsAsWords(spirv, wordFed); !error.empty()) {
      debugMessage("Vulkan error: pipeline '" + desc.label + "': " + error);
      destroyLayout(p.layout);
      return {};
    }
    VkShaderModuleCreateInfo mi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    mi.codeSize = spirv.size() * sizeof(uint32_t);
    mi.pCode = spirv.data();
    if (vkCreateShaderModule(device_, &mi, nullptr, &wordReader) != VK_SUCCESS) {
      destroyLayout(p.layout);
      return {};
    }
    notes_.push_back((desc.label.empty() ? std::string("pipeline") : desc.label) +
                     ": 64-bit vertex attributes fed as 32-bit words (the device has no 64-bit vertex formats)");
  }
  std::vector<VkPipelineShaderStageCreateInfo> stages;
  for (const ShaderObject* s : stageShaders) {
    VkPipelineShaderStageCreateInfo si{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    si.stage = toVkStage(s->stage);
    si.module = s == vs && wordReader ? wordReader : s->module;
    si.pName = s->entryPoint.c_str();
    stages.push_back(si);
  }

  VkPipelineVertexInputStateCreateInfo vi{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
  vi.vertexBindingDescriptionCount = static_cast<uint32_t>(vbindings.size());
  vi.pVertexBindingDescriptions = vbindings.data();
  vi.vertexAttributeDescriptionCount = static_cast<uint32_t>(vattributes.size());
  vi.pVertexAttributeDescriptions = vattributes.data();

  VkPipelineInputAssemblyStateCreateInfo ia{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
  ia.topology = toVk(desc.topology);
  VkPipelineTessellationStateCreateInfo ts{VK_STRUCTURE_TYPE_PIPELINE_TESSELLATION_STATE_CREATE_INFO};
  ts.patchControlPoints = desc.patchControlPoints;

  VkPipelineViewportStateCreateInfo vp{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
  // Every viewport index a shader may select (Capabilities::viewports), set alike at each draw.
  vp.viewportCount = info_.caps.viewports;
  vp.scissorCount = info_.caps.viewports;

  // Vulkan maps NDC y = -1 to framebuffer row 0, which is the RHI's convention, so a triangle
  // that is counter-clockwise in the saved image is counter-clockwise here as is.
  VkPipelineRasterizationStateCreateInfo rs{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
  rs.polygonMode = toVk(desc.raster.polygonMode);
  rs.cullMode = toVk(desc.raster.cull);
  rs.frontFace = desc.raster.frontFace == FrontFace::Clockwise ? VK_FRONT_FACE_CLOCKWISE
                                                                : VK_FRONT_FACE_COUNTER_CLOCKWISE;
  rs.lineWidth = 1.0f;
  rs.depthClampEnable = desc.raster.depthClampEnabled;
  // rhi's depth bias is Vulkan's (rhi.h): passed through.
  const DepthBias& bias = desc.raster.depthBias;
  rs.depthBiasEnable = bias.constantFactor != 0 || bias.slopeFactor != 0;
  rs.depthBiasConstantFactor = bias.constantFactor;
  rs.depthBiasSlopeFactor = bias.slopeFactor;
  rs.depthBiasClamp = bias.clamp;
  VkPipelineRasterizationProvokingVertexStateCreateInfoEXT provoking{
      VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_PROVOKING_VERTEX_STATE_CREATE_INFO_EXT};
  provoking.provokingVertexMode = VK_PROVOKING_VERTEX_MODE_LAST_VERTEX_EXT;
  if (desc.raster.provokingVertex == ProvokingVertex::Last) rs.pNext = &provoking;

  VkPipelineMultisampleStateCreateInfo ms{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
  ms.rasterizationSamples = desc.samples == 4 ? VK_SAMPLE_COUNT_4_BIT : VK_SAMPLE_COUNT_1_BIT;

  const bool hasDepth = isDepthFormat(desc.depthStencilFormat);
  VkPipelineDepthStencilStateCreateInfo ds{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
  ds.depthTestEnable = hasDepth;
  ds.depthWriteEnable = hasDepth && desc.depthStencil.depthWrite;
  ds.depthCompareOp = toVk(desc.depthStencil.depthCompare);
  ds.stencilTestEnable = hasStencil(desc.depthStencilFormat) && desc.depthStencil.stencilEnabled;
  ds.front = toVk(desc.depthStencil.front, desc.depthStencil);
  ds.back = toVk(desc.depthStencil.back, desc.depthStencil);
  ds.minDepthBounds = 0.0f;
  ds.maxDepthBounds = 1.0f;

  const uint32_t colorCount = std::min(desc.colorTargetCount, kMaxColorTargets);
  std::array<VkPipelineColorBlendAttachmentState, kMaxColorTargets> blends{};
  std::array<VkFormat, kMaxColorTargets> colorFormats{};
  for (uint32_t i = 0; i < colorCount; ++i) {
    const ColorTargetState& t = desc.colorTargets[i];
    colorFormats[i] = toVkFormat(t.format);
    VkPipelineColorBlendAttachmentState& b = blends[i];
    // Integer targets cannot blend (as on GL, where blending is ignored for them).
    b.blendEnable = t.blend.enabled && !isIntegerFormat(t.format);
    b.srcColorBlendFactor = toVk(t.blend.srcColor);
    b.dstColorBlendFactor = toVk(t.blend.dstColor);
    b.colorBlendOp = toVk(t.blend.colorOp);
    b.srcAlphaBlendFactor = toVk(t.blend.srcAlpha);
    b.dstAlphaBlendFactor = toVk(t.blend.dstAlpha);
    b.alphaBlendOp = toVk(t.blend.alphaOp);
    b.colorWriteMask = t.writeMask & 0xF;  // ColorMask_R/G/B/A match VK_COLOR_COMPONENT_*_BIT
  }
  VkPipelineColorBlendStateCreateInfo cb{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
  cb.attachmentCount = colorCount;
  cb.pAttachments = blends.data();

  const VkDynamicState dynamics[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR,
                                     VK_DYNAMIC_STATE_STENCIL_REFERENCE, VK_DYNAMIC_STATE_BLEND_CONSTANTS};
  VkPipelineDynamicStateCreateInfo dy{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
  dy.dynamicStateCount = 4;
  dy.pDynamicStates = dynamics;

  VkPipelineRenderingCreateInfo ri{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
  ri.colorAttachmentCount = colorCount;
  ri.pColorAttachmentFormats = colorFormats.data();
  ri.depthAttachmentFormat = hasDepth ? toVkFormat(desc.depthStencilFormat) : VK_FORMAT_UNDEFINED;
  ri.stencilAttachmentFormat =
      hasStencil(desc.depthStencilFormat) ? toVkFormat(desc.depthStencilFormat) : VK_FORMAT_UNDEFINED;

  VkGraphicsPipelineCreateInfo ci{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
  ci.pNext = &ri;
  ci.stageCount = static_cast<uint32_t>(stages.size());
  ci.pStages = stages.data();
  ci.pVertexInputState = &vi;
  ci.pInputAssemblyState = &ia;
  if (desc.tessControlShader) ci.pTessellationState = &ts;
  ci.pViewportState = &vp;
  ci.pRasterizationState = &rs;
  ci.pMultisampleState = &ms;
  ci.pDepthStencilState = &ds;
  ci.pColorBlendState = &cb;
  ci.pDynamicState = &dy;
  ci.layout = p.layout.layout;
  const VkResult created = vkCreateGraphicsPipelines(device_, VK_NULL_HANDLE, 1, &ci, nullptr, &p.pipeline);
  vkDestroyShaderModule(device_, wordReader, nullptr);
  if (created != VK_SUCCESS) {
    destroyLayout(p.layout);
    return {};
  }
  return pipelines_.add(std::move(p));
}

ComputePipelineHandle VulkanDevice::createComputePipeline(const ComputePipelineDesc& desc) {
  const ShaderObject* cs = shaders_.get(desc.computeShader);
  if (!cs || cs->stage != ShaderStage::Compute) return {};
  ComputePipelineObject p;
  p.desc = desc;
  if (!buildLayout({cs}, &p.layout)) return {};
  VkComputePipelineCreateInfo ci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  ci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
  ci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  ci.stage.module = cs->module;
  ci.stage.pName = cs->entryPoint.c_str();
  VkPipelineShaderStageRequiredSubgroupSizeCreateInfo required{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_REQUIRED_SUBGROUP_SIZE_CREATE_INFO};
  required.requiredSubgroupSize = desc.requiredSubgroupSize;
  if (desc.requiredSubgroupSize) ci.stage.pNext = &required;
  if (desc.fullSubgroups) ci.stage.flags |= VK_PIPELINE_SHADER_STAGE_CREATE_REQUIRE_FULL_SUBGROUPS_BIT;
  if (desc.varyingSubgroupSize) ci.stage.flags |= VK_PIPELINE_SHADER_STAGE_CREATE_ALLOW_VARYING_SUBGROUP_SIZE_BIT;
  if ((desc.requiredSubgroupSize || desc.fullSubgroups || desc.varyingSubgroupSize) && !info_.caps.subgroupSizeControl) return {};
  ci.layout = p.layout.layout;
  if (vkCreateComputePipelines(device_, VK_NULL_HANDLE, 1, &ci, nullptr, &p.pipeline) != VK_SUCCESS) {
    destroyLayout(p.layout);
    return {};
  }
  return computePipelines_.add(std::move(p));
}

void VulkanDevice::destroy(PipelineHandle h) {
  std::optional<PipelineObject> p = pipelines_.remove(h);
  if (!p) return;
  defer([this, pipeline = p->pipeline, layout = p->layout] {
    vkDestroyPipeline(device_, pipeline, nullptr);
    destroyLayout(layout);
  });
}

void VulkanDevice::destroy(ComputePipelineHandle h) {
  std::optional<ComputePipelineObject> p = computePipelines_.remove(h);
  if (!p) return;
  defer([this, pipeline = p->pipeline, layout = p->layout] {
    vkDestroyPipeline(device_, pipeline, nullptr);
    destroyLayout(layout);
  });
}

}  // namespace parity::rhi::vulkan
