#include "harness/scripts/opengl_uniform_types.h"

#include <spirv_cross/spirv_cross_c.h>

#include <memory>
#include <type_traits>

namespace parity::harness::script {

std::optional<std::string> openGlValueTypeName(Scalar scalar, uint32_t rows, uint32_t columns) {
  std::string base;
  switch (scalar) {
    case Scalar::Float32: base = "GL_FLOAT"; break;
    case Scalar::Float64: base = "GL_DOUBLE"; break;
    case Scalar::Int32: base = "GL_INT"; break;
    case Scalar::Uint32: base = "GL_UNSIGNED_INT"; break;
    case Scalar::Int64: base = "GL_INT64"; break;
    case Scalar::Uint64: base = "GL_UNSIGNED_INT64"; break;
    default: return std::nullopt;
  }
  const bool wideInteger = scalar == Scalar::Int64 || scalar == Scalar::Uint64;  // ARB_gpu_shader_int64's names end in _ARB
  std::string name;
  if (columns > 1) {
    if (scalar != Scalar::Float32 && scalar != Scalar::Float64) return std::nullopt;  // only float and double matrices
    name = base + "_MAT" + std::to_string(columns) + (rows == columns ? "" : "x" + std::to_string(rows));
  } else {
    name = rows > 1 ? base + "_VEC" + std::to_string(rows) : base;
  }
  return wideInteger ? name + "_ARB" : name;
}

namespace {

struct SpvcContextDeleter {
  void operator()(spvc_context c) const { spvc_context_destroy(c); }
};

// OpenGL's name of a sampled or storage image type, after its prefix ("GL_SAMPLER_", "GL_IMAGE_").
std::string dimensionName(SpvDim dim, bool arrayed, bool multisampled) {
  switch (dim) {
    case SpvDim1D: return arrayed ? "1D_ARRAY" : "1D";
    case SpvDim2D: return multisampled ? (arrayed ? "2D_MULTISAMPLE_ARRAY" : "2D_MULTISAMPLE") : arrayed ? "2D_ARRAY" : "2D";
    case SpvDim3D: return "3D";
    case SpvDimCube: return arrayed ? "CUBE_MAP_ARRAY" : "CUBE";
    case SpvDimRect: return "2D_RECT";
    case SpvDimBuffer: return "BUFFER";
    default: return "";
  }
}

}  // namespace

std::optional<std::string> openGlOpaqueTypeName(const std::vector<uint32_t>& spirv, const std::string& name) {
  spvc_context raw = nullptr;
  if (spvc_context_create(&raw) != SPVC_SUCCESS) return std::nullopt;
  std::unique_ptr<std::remove_pointer_t<spvc_context>, SpvcContextDeleter> context(raw);
  spvc_parsed_ir ir = nullptr;
  spvc_compiler compiler = nullptr;
  spvc_resources resources = nullptr;
  if (spvc_context_parse_spirv(raw, spirv.data(), spirv.size(), &ir) != SPVC_SUCCESS ||
      spvc_context_create_compiler(raw, SPVC_BACKEND_NONE, ir, SPVC_CAPTURE_MODE_TAKE_OWNERSHIP, &compiler) != SPVC_SUCCESS ||
      spvc_compiler_create_shader_resources(compiler, &resources) != SPVC_SUCCESS)
    return std::nullopt;
  for (spvc_resource_type kind : {SPVC_RESOURCE_TYPE_SAMPLED_IMAGE, SPVC_RESOURCE_TYPE_STORAGE_IMAGE}) {
    const spvc_reflected_resource* items = nullptr;
    size_t count = 0;
    spvc_resources_get_resource_list_for_type(resources, kind, &items, &count);
    for (size_t i = 0; i < count; ++i) {
      const char* variable = spvc_compiler_get_name(compiler, items[i].id);
      if (!variable || name != variable) continue;
      spvc_type type = spvc_compiler_get_type_handle(compiler, items[i].base_type_id);
      const SpvDim dim = spvc_type_get_image_dimension(type);
      const bool storage = kind == SPVC_RESOURCE_TYPE_STORAGE_IMAGE;
      const bool shadow = !storage && spvc_type_get_image_is_depth(type);
      const bool arrayed = spvc_type_get_image_arrayed(type), multisampled = spvc_type_get_image_multisampled(type);
      const spvc_basetype sampled = spvc_type_get_basetype(spvc_compiler_get_type_handle(compiler, spvc_type_get_image_sampled_type(type)));
      const std::string dimension = dimensionName(dim, arrayed, multisampled);
      if (dimension.empty()) return std::nullopt;
      const std::string prefix = sampled == SPVC_BASETYPE_INT32 ? "GL_INT_" : sampled == SPVC_BASETYPE_UINT32 ? "GL_UNSIGNED_INT_" : "GL_";
      return prefix + (storage ? "IMAGE_" : "SAMPLER_") + dimension + (shadow ? "_SHADOW" : "");
    }
  }
  return std::nullopt;
}

}  // namespace parity::harness::script
