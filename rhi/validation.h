// parity's RHI validation layer: a Device that checks every call against the rules below and
// forwards valid calls to the backend it wraps. Backends assume valid input.
//
// Each rule has a stable id (tests assert on it; never renumber or rename). A call that breaks
// a rule is reported through DeviceDesc::onValidationError and dropped: creation returns a null
// handle, commands do nothing, readbacks return an empty vector, writeTimestamp returns
// kInvalidTimestamp. Only the first rule a call breaks is reported.
//
// State the layer assumes (the contract of rhi.h made explicit):
//  * setPipeline, setViewport, setScissor, draw and drawIndexed belong inside a pass; every
//    pass starts with no graphics pipeline bound.
//  * setBindings merges: each entry replaces the binding of the same number and leaves the
//    others bound. Bindings, push constants, vertex/index buffers and the compute pipeline are
//    kept across passes and submits until replaced.
//  * Bindings are checked when a draw or dispatch uses them (against the shaders' reflection),
//    so a stale binding the current pipeline does not declare is harmless.
//  * When beginPass is dropped, the commands up to the matching endPass are dropped silently,
//    so one mistake is reported once.
//  * Destroying a null handle does nothing.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "rhi/rhi.h"

// X(id, one-line description). Append new rules; never rename or reuse an id.
#define PARITY_RHI_VALIDATION_RULES(X)                                                                        \
  /* handles */                                                                                               \
  X(E_HANDLE_INVALID, "a null or destroyed handle was passed where a live object is required")                \
  /* buffers */                                                                                               \
  X(E_BUFFER_SIZE_ZERO, "createBuffer with size 0")                                                           \
  X(E_BUFFER_USAGE,                                                                                           \
    "buffer usage flags are empty or unknown, or a buffer is used as vertex/index/uniform/storage "           \
    "buffer without that usage flag")                                                                         \
  X(E_BUFFER_OFFSET,                                                                                          \
    "setVertexBuffer/setIndexBuffer offset at or past the end of the buffer, or an index buffer offset "      \
    "that is not a multiple of the index size")                                                               \
  /* textures and views */                                                                                    \
  X(E_TEXTURE_SIZE_ZERO, "texture width, height, depth, layers or mipLevels is 0")                            \
  X(E_TEXTURE_SIZE_TOO_LARGE, "texture width or height above 16384, or more than 2048 layers")                \
  X(E_TEXTURE_FORMAT_UNDEFINED, "texture format is Undefined or not a known format")                          \
  X(E_TEXTURE_LAYERS, "a Tex2D texture with layers != 1 (use Tex2DArray)")                                    \
  X(E_TEXTURE_CUBE_LAYERS, "a Cube texture without exactly 6 layers or with width != height")                 \
  X(E_TEXTURE_DIMENSION,                                                                                      \
    "a Tex1D texture with height != 1, a Tex3D texture with layers != 1 or a side above 2048, or depth != 1 " \
    "on a texture that is not Tex3D")                                                                         \
  X(E_TEXTURE_MIP_COUNT, "texture mipLevels larger than the full mip chain of its size")                      \
  X(E_TEXTURE_MSAA_SAMPLES, "texture samples not 1 or 4, or above DeviceInfo::caps.maxSamples")               \
  X(E_TEXTURE_MSAA_INVALID,                                                                                   \
    "multisampled texture that is not Tex2D, has mips or layers, has initial data, or Storage usage "          \
    "without Capabilities::storageMultisample")                                                               \
  X(E_TEXTURE_USAGE,                                                                                          \
    "texture usage flags are empty or unknown, Storage usage on a depth or sRGB format, or a texture "        \
    "bound as sampled/storage texture without Sampled/Storage usage")                                         \
  X(E_TEXTURE_DESTROY_WITH_VIEWS, "a texture destroyed while views of it are alive (destroy views first)")    \
  X(E_VIEW_PARENT_INVALID, "texture view parent is null, destroyed, or itself a view")                        \
  X(E_VIEW_SIZE_CLASS, "texture view format of another size class (bytesPerTexel) than its parent's")         \
  X(E_VIEW_DEPTH,                                                                                             \
    "texture view that changes the format of a depth texture, or a depth-format view of a colour "            \
    "texture")                                                                                                \
  X(E_VIEW_RANGE, "texture view layer or mip range outside its parent")                                       \
  X(E_VIEW_SWIZZLE,                                                                                           \
    "texture view swizzle naming no component, or a view with a swizzle other than the identity used as an "  \
    "attachment or a storage texture")                                                                        \
  /* shaders and pipelines */                                                                                 \
  X(E_SHADER_SPIRV_EMPTY, "createShader without SPIR-V words")                                                \
  X(E_SHADER_REFLECTION,                                                                                      \
    "the SPIR-V module could not be reflected or breaks the binding model (set 0, binding < 16, push "        \
    "constants <= 128 bytes, descriptor arrays one-dimensional of 1..16 elements)")                          \
  X(E_SHADER_ENTRY_POINT, "the SPIR-V module has no entry point named desc.entryPoint for desc.stage")        \
  X(E_PIPELINE_SHADER_MISSING,                                                                                \
    "pipeline without a vertex or fragment shader, or compute pipeline without a compute shader")             \
  X(E_PIPELINE_SHADER_STAGE, "pipeline shader slot given a shader of another stage")                          \
  X(E_PIPELINE_BINDING_CONFLICT, "vertex and fragment shader declare the same binding with different kinds")  \
  X(E_PIPELINE_COLOR_TARGET_COUNT,                                                                            \
    "colorTargetCount above 4, or neither a colour target nor a depth-stencil format")                        \
  X(E_PIPELINE_FORMAT,                                                                                        \
    "a colour target with a depth format, or a depthStencilFormat that is not a depth format")                \
  X(E_PIPELINE_BLEND, "blending enabled on an integer colour target format")                                  \
  X(E_PIPELINE_ATTRIBUTE,                                                                                     \
    "vertex attributes: more than 8, duplicate or >= 16 location, buffer slot >= 4,"                          \
    " or an input location the vertex shader reads but no attribute supplies")                                \
  X(E_PIPELINE_SAMPLES, "pipeline samples not 1 or 4, or above DeviceInfo::caps.maxSamples")                  \
  X(E_PIPELINE_DEPTH_STATE,                                                                                   \
    "depth or stencil test/write enabled without a depth-stencil format, or stencil with D32F")               \
  /* passes */                                                                                                \
  X(E_PASS_NESTED, "beginPass inside a pass")                                                                 \
  X(E_PASS_NOT_BEGUN, "endPass, setPipeline, setViewport, setScissor, draw or drawIndexed outside a pass")    \
  X(E_PASS_NO_ATTACHMENTS, "beginPass without any colour or depth-stencil attachment")                        \
  X(E_PASS_ATTACHMENT_FORMAT,                                                                                 \
    "a depth texture in a colour slot, or a colour texture as depth-stencil attachment")                      \
  X(E_PASS_ATTACHMENT_USAGE, "an attachment or resolve target without RenderTarget usage")                    \
  X(E_PASS_ATTACHMENT_RANGE, "attachment layer or mip outside the texture")                                   \
  X(E_PASS_ATTACHMENT_SIZE_MISMATCH, "attachments (at their mip) of different sizes in one pass")             \
  X(E_PASS_ATTACHMENT_SAMPLES, "attachments with different sample counts in one pass")                        \
  X(E_PASS_ATTACHMENT_DUPLICATE, "the same texture layer/mip attached twice in one pass")                     \
  X(E_PASS_RESOLVE,                                                                                           \
    "resolve target on a single-sample attachment, or a multisampled, differently sized or formatted "        \
    "resolve target, or a resolve of an integer format")                                                      \
  X(E_VIEWPORT_INVALID, "viewport with negative or non-finite size, or min/maxDepth outside [0, 1]")          \
  X(E_SCISSOR_INVALID, "scissor rectangle with a negative origin")                                            \
  /* draws */                                                                                                 \
  X(E_DRAW_NO_PIPELINE, "draw without a pipeline set in the current pass")                                    \
  X(E_DRAW_PIPELINE_MISMATCH,                                                                                 \
    "the pipeline's colour formats, depth-stencil format or samples differ from the current pass's "          \
    "attachments")                                                                                            \
  X(E_VERTEX_BUFFER_SLOT, "setVertexBuffer slot >= 4")                                                        \
  X(E_VERTEX_BUFFER_MISSING,                                                                                  \
    "draw with a pipeline whose attributes read a vertex buffer slot that is not set")                        \
  X(E_INDEX_BUFFER_MISSING, "drawIndexed without an index buffer")                                            \
  X(E_DRAW_VERTEX_RANGE, "a draw reads vertices or instances past the end of a vertex buffer")                \
  X(E_DRAW_INDEX_RANGE, "drawIndexed reads indices past the end of the index buffer")                         \
  /* resource bindings and push constants */                                                                  \
  X(E_BINDING_INDEX,                                                                                          \
    "setBindings entry with binding >= 16, or the same binding and array element twice in one call")          \
  X(E_BINDING_MISSING,                                                                                        \
    "a binding (or an element of a descriptor array) the pipeline's shaders declare was not supplied by "     \
    "setBindings")                                                                                            \
  X(E_BINDING_KIND, "the kind supplied for a binding differs from the kind the shader declares")              \
  X(E_BINDING_RANGE,                                                                                          \
    "binding buffer range past the end of the buffer, buffer offset not a multiple of 256, a uniform "        \
    "buffer range above 65536 bytes, or storage texture mip outside the texture")                             \
  X(E_BINDING_TEXTURE_MISMATCH,                                                                               \
    "bound texture or sampler does not fit the shader's declaration (multisampled, integer, "                 \
    "shadow/compare, array or cube)")                                                                         \
  X(E_BINDING_FEEDBACK, "a texture the draw samples or stores to is an attachment of the current pass")       \
  X(E_PUSH_CONSTANT_SIZE, "pushConstants with null data, size 0, size above 128 or not a multiple of 4")      \
  X(E_PUSH_CONSTANT_MISSING, "fewer push-constant bytes pushed than the pipeline's shaders declare")          \
  /* compute */                                                                                               \
  X(E_DISPATCH_IN_PASS, "setComputePipeline or dispatch inside a render pass")                                \
  X(E_DISPATCH_NO_PIPELINE, "dispatch without a compute pipeline")                                            \
  X(E_DISPATCH_SIZE, "dispatch with more than 65535 work groups in a dimension")                              \
  /* transfers */                                                                                             \
  X(E_TRANSFER_IN_PASS,                                                                                       \
    "writeBuffer, writeTexture, readBuffer, readTexture, copyBuffer or copyTexture inside a pass")            \
  X(E_TRANSFER_EMPTY,                                                                                         \
    "null data or size 0 in writeBuffer/readBuffer/copyBuffer, or null data in writeTexture")                 \
  X(E_WRITE_OUT_OF_RANGE, "writeBuffer range past the end of the buffer")                                     \
  X(E_READ_OUT_OF_RANGE, "readBuffer range past the end of the buffer")                                       \
  X(E_COPY_OUT_OF_RANGE, "copyBuffer source or destination range past the end of its buffer")                 \
  X(E_SUBRESOURCE_RANGE, "writeTexture, readTexture or copyTexture layer or mip outside the texture")         \
  X(E_TRANSFER_MSAA, "writeTexture or copyTexture on a multisampled texture")                                 \
  X(E_READBACK_MSAA, "readTexture of a multisampled texture (resolve it first)")                              \
  X(E_READBACK_ASPECT,                                                                                        \
    "readTexture aspect that the format lacks (Color on depth, Depth on colour, Stencil without "             \
    "stencil)")                                                                                               \
  X(E_COPY_SIZE_CLASS, "copyTexture between formats of different size classes")                               \
  X(E_COPY_SIZE_MISMATCH, "copyTexture between subresources of different sizes")                              \
  X(E_COPY_DEPTH, "copyTexture involving a depth format where the two formats differ")                        \
  X(E_COPY_OVERLAP,                                                                                           \
    "copyTexture within one subresource, or copyBuffer with overlapping ranges of one buffer")                \
  /* timing and submission */                                                                                 \
  X(E_TIMESTAMP_IN_PASS, "writeTimestamp or resetTimestamps inside a pass")                                   \
  X(E_TIMESTAMP_PENDING, "timestampNs for a timestamp written after the last submit")                         \
  X(E_SUBMIT_IN_PASS, "submit inside a pass")                                                                 \
  /* separate textures and samplers, border colours (appended) */                                             \
  X(E_PIPELINE_SEPARATE_PAIRS,                                                                                \
    "a pipeline's shaders combine more than 16 distinct separate texture/sampler binding pairs")              \
  X(E_BINDING_BORDER_COLOR,                                                                                   \
    "a ClampToBorder sampler whose border colour family (Float/Int) does not match the texture it samples "   \
    "(integer textures need an Int border colour, others a Float one)")                                      \
  X(E_BINDING_TEXEL_FORMAT,                                                                                   \
    "a texel buffer binding whose texelFormat is not one of RGBA8, RGBA8_UINT, R32_UINT, R32F, RG32F, "       \
    "RGBA16F, RGBA32F, or whose bound size is not a whole number of texels")                                  \
  /* descriptor arrays (appended) */                                                                          \
  X(E_BINDING_ARRAY_ELEMENT, "setBindings entry with arrayElement >= 16 (kMaxArrayElements)")               \
  X(E_PIPELINE_ARRAY_SIZE, "two stages of a pipeline declare one binding as arrays of different sizes")       \
  X(E_SHADER_SAMPLER_ARRAY,                                                                                   \
    "an array of SeparateSampler on a device without DeviceInfo::caps.separateSamplerArrays (GL)")            \
  /* rasterisation state (appended) */                                                                        \
  X(E_PIPELINE_RASTER_STATE,                                                                                  \
    "a pipeline topology or polygon mode of no known value, or a depth bias factor or clamp that is not "     \
    "finite")                                                                                                 \
  X(E_PIPELINE_DEVICE_FEATURE,                                                                                \
    "pipeline state needing a device feature DeviceInfo::features lacks: fillModeNonSolid (polygon mode "     \
    "Line or Point), depthClamp, depthBiasClamp (a non-zero depth bias clamp), geometryShader (adjacency "    \
    "topologies)")                                                                                          \
  /* subgroup size control (appended) */                                                                      \
  X(E_PIPELINE_SUBGROUP_SIZE,                                                                                 \
    "compute pipeline subgroup size control on a device without DeviceInfo::caps.subgroupSizeControl, a "     \
    "requiredSubgroupSize that is not a power of two in [minSubgroupSize, maxSubgroupSize], or fullSubgroups " \
    "with a local size x that is not a multiple of the subgroup size")                                       \
  /* filtering (appended) */                                                                                  \
  X(E_BINDING_FILTER_FORMAT,                                                                                  \
    "a texture whose format not every device filters read through a sampler with a Linear min, mag or mip "   \
    "filter: an integer texture (Vulkan forbids it, GL reads 0) or a depth texture without comparison "       \
    "(VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT is optional for depth formats; lavapipe has none)") \
  /* samplers (appended) */                                                                                   \
  X(E_SAMPLER_LOD,                                                                                            \
    "a sampler whose minLod, maxLod or mipLodBias is not finite, whose minLod is above its maxLod, or whose "  \
    "|mipLodBias| is above Capabilities::maxSamplerLodBias")

namespace parity::rhi {

using ValidationCallback = std::function<void(const std::string& id, const std::string& message)>;

enum class ValidationRuleId : uint16_t {
#define PARITY_RHI_VALIDATION_ENUM(id, description) id,
  PARITY_RHI_VALIDATION_RULES(PARITY_RHI_VALIDATION_ENUM)
#undef PARITY_RHI_VALIDATION_ENUM
  Count
};

struct ValidationRule {
  std::string id;           // "E_BUFFER_SIZE_ZERO"
  std::string description;  // one line
};

// Every rule, in table order (for docs and `parity explain`).
const std::vector<ValidationRule>& validationRules();
// The rule with this id, or null.
const ValidationRule* findValidationRule(std::string_view id);
const char* validationRuleName(ValidationRuleId id);

// What writeTimestamp returns when the call was dropped; timestampNs() answers nullopt for it.
constexpr TimestampId kInvalidTimestamp = 0xFFFFFFFFu;

std::unique_ptr<Device> wrapWithValidation(std::unique_ptr<Device> backend, ValidationCallback onError);

}  // namespace parity::rhi
