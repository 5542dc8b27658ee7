// What every step of the script runner shares: the two ways a script stops (Unsupported: SKIP
// naming the construct; Failure: FAIL with the reason), script values and formats as the RHI's,
// and the bindings the OpenGL GLSL of piglit's files is linked to.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>

#include "harness/scripts/script.h"
#include "rhi/rhi.h"

namespace parity::harness::script::runner {

// Thrown by any step: the script is a SKIP naming the construct.
struct Unsupported {
  std::string what;
};
// Thrown by any step: the script is a FAIL with this reason.
struct Failure {
  std::string what;
};

inline std::string lineOf(const Location& l) { return "line " + std::to_string(l.line); }

struct TexFormat {
  rhi::Format format = rhi::Format::Undefined;
  bool bgra = false;  // script bytes are B,G,R,A; the texture stores R,G,B,A
  // A 3-channel 8-bit script format (R8G8B8_SNORM, B8G8R8_UNORM, ...), which the RHI has not: the
  // texture is its 4-channel format, each texel given this alpha byte (1.0, what a read of a
  // 3-channel format returns) on upload and losing it on readback.
  uint8_t alphaFill = 0;
  uint32_t scriptBytesPerTexel() const { return alphaFill ? 3 : rhi::formatInfo(format).bytesPerTexel; }
};

inline bool isIntegerScalar(Scalar s) { return s != Scalar::Float16 && s != Scalar::Float32 && s != Scalar::Float64; }
inline double srgbToLinear(double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); }

// The format Amber gives an image declared with a DATA_TYPE: one channel per vector component
// (int32 -> R32_SINT, vec4<float> -> R32G32B32A32_SFLOAT). Empty when the type's layout is no
// format's (matrices, padded vec3).
std::string formatOfDataType(const ElementType& t);

TexFormat textureFormat(const ElementType& t);

// Whether every component of a vertex type is an integer (uint or int, not normalised) of one
// scalar type: what the RHI's integer vertex formats fetch.
bool integerComponents(const ElementType& t);

// The RHI's 32-bit integer vertex format of n components (uint or int, as the shader reads it).
rhi::VertexFormat integerVertexFormat(Scalar s, size_t n);

double readScalar(const uint8_t* p, Scalar s);

std::string fmt(double v);

rhi::ShaderStage rhiStage(Stage s);

rhi::CompareOp compareOp(const std::string& s);

rhi::StencilOp stencilOp(const std::string& s);
// The stencil reference and masks of a pipeline whose faces test the stencil. The RHI has one of
// each: they agree where the faces that use a value (the reference: a compare other than
// always/never or a replace; the compare mask: such a compare; the write mask: an op other than
// keep) give it the same, and are the user's value (else the front face's).
struct StencilValues {
  uint32_t reference = 0, compareMask = 0xFF, writeMask = 0xFF;
  bool agree = true;
};
StencilValues stencilValues(const Pipeline& p);

rhi::BlendFactor blendFactor(const std::string& s);

rhi::BlendOp blendOp(const std::string& s);

rhi::AddressMode addressMode(const std::string& s);

rhi::BorderColor borderColor(const std::string& s);


// `declarations` after the #version line and any #extension lines (which must precede
// declarations), then a #line that keeps the compiler's line numbers those of the script.
// `version`: the line for a source without one; `versionAdded`: the source's #version line was
// added to it (its lines start after it).
std::string withDeclarations(std::string src, const std::string& declarations, int sourceLine, const std::string& version,
                             bool versionAdded = false);

// Each stage's loose uniforms are a block of their own (linkOpenGlBlocks), named apart.
inline std::string looseUniformBlockOf(const Shader& s) { return "ParityDefaultUniforms_" + s.name; }

// Where OpenGL GLSL's uniform blocks go (rhi::ShaderCompileOptions::openGlSource, and
// linkOpenGlBlocks): a set no script uses, remapped to set 0 with the other bindings.
inline constexpr uint32_t kDefaultUniformSet = 15;
// Where OpenGL GLSL's sampler uniforms go, one binding per sampler name (linkOpenGlBlocks).
inline constexpr uint32_t kOpenGlSamplerSet = 14;
// Where the atomic counters of OpenGL binding N go: binding N of this set (linkOpenGlBlocks).
inline constexpr uint32_t kAtomicCounterSet = 13;
inline constexpr const char* kAtomicCounterBlockPrefix = "gl_AtomicCounterBlock_";
inline constexpr const char* kDefaultUniformBlock = "gl_DefaultUniformBlock";

// Its input is named as piglit's passthrough names it, so [vertex data] columns find it by name.
inline constexpr const char* kPassthroughVs = R"(#version 450
layout(location = 0) in vec4 piglit_vertex;
void main() { gl_Position = piglit_vertex; }
)";
// The same for a next stage (tessellation or geometry) of GLSL before 4.50, whose gl_PerVertex
// has no gl_CullDistance: the blocks of both sides must have the same members (Vulkan's
// interface rules; the validation layer checks them).
inline constexpr const char* kPassthroughVsWithoutCullDistance = R"(#version 450
layout(location = 0) in vec4 piglit_vertex;
out gl_PerVertex { vec4 gl_Position; float gl_PointSize; float gl_ClipDistance[]; };
void main() { gl_Position = piglit_vertex; }
)";

}  // namespace parity::harness::script::runner
