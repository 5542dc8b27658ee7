// GL backend: programs from OpenGL GLSL (ShaderDesc::openGlGlsl). The driver compiles and links
// the source as its author wrote it for OpenGL, as piglit's shader_runner does; the SPIR-V beside
// it is its port (what the Vulkan backend runs) and says where everything of the program goes in
// the RHI's binding model:
//  * inputs and fragment outputs take the port's locations by name (glBindAttribLocation,
//    glBindFragDataLocation before linking; explicit layout locations win, as in OpenGL);
//  * uniform and storage blocks take the port's bindings by block name, samplers and images
//    their units by uniform name (element e of an array at point + e);
//  * the loose uniforms are members of the port's looseUniformBlock: before each draw or
//    dispatch their values are read from the buffer bound at that block's binding and set with
//    glProgramUniform*, so a caller writes them as it writes the port's block;
//  * atomic counters (the port's storage blocks of the same member names) are bound as the
//    atomic counter buffers of the bindings the source gives them;
//  * a uniform block the driver lays out otherwise than the port (OpenGL's `shared` and `packed`
//    layouts) is copied member by member into a buffer of the program's layout at each draw.
#include <spirv_cross/spirv_cross_c.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <type_traits>

#include "rhi/gl/gl_device.h"

namespace parity::rhi::gl {

namespace {

struct SpvcContextDeleter {
  void operator()(spvc_context c) const { spvc_context_destroy(c); }
};
using SpvcContext = std::unique_ptr<std::remove_pointer_t<spvc_context>, SpvcContextDeleter>;

// What the port declares, by the names OpenGL links by.
struct PortInterface {
  struct Located {
    std::string name;
    uint32_t location;
  };
  struct Bound {
    std::string name;  // a block's block name; a sampler's or image's variable name
    uint32_t binding, arraySize;
    // A uniform block's members as OpenGL names them ("Block.m" where the block has an
    // instance name) and where the port has them.
    std::vector<std::pair<std::string, LooseUniform>> members;
    std::vector<std::string> memberNames;  // a storage block's, as declared (arrays of arrays too)
  };
  std::vector<Located> inputs, outputs;
  std::vector<Bound> uniformBlocks, storageBlocks, opaque;
  std::vector<std::pair<std::string, LooseUniform>> loose;  // GL uniform name ("s.a[2]"), value place
};

uint32_t elementsOf(spvc_compiler compiler, spvc_type_id typeId) {
  spvc_type type = spvc_compiler_get_type_handle(compiler, typeId);
  uint32_t n = 1;
  for (unsigned d = 0; d < spvc_type_get_num_array_dimensions(type); ++d) n *= std::max(1u, spvc_type_get_array_dimension(type, d));
  return n;
}

// The scalars, vectors and matrices of struct member `index` of `structType`, at `base` bytes into
// the block, named `name` as glGetUniformLocation takes them. Arrays of arrays are not walked
// (OpenGL GLSL before 4.30 has none).
void flattenMember(spvc_compiler compiler, spvc_type_id structTypeId, unsigned index, const std::string& name, uint32_t base,
                   uint32_t binding, std::vector<std::pair<std::string, LooseUniform>>& out);

void flattenStruct(spvc_compiler compiler, spvc_type_id structTypeId, const std::string& prefix, uint32_t base, uint32_t binding,
                   std::vector<std::pair<std::string, LooseUniform>>& out) {
  spvc_type type = spvc_compiler_get_type_handle(compiler, structTypeId);
  for (unsigned i = 0; i < spvc_type_get_num_member_types(type); ++i) {
    const char* member = spvc_compiler_get_member_name(compiler, structTypeId, i);
    flattenMember(compiler, structTypeId, i, prefix + (member ? member : ""), base, binding, out);
  }
}

void flattenMember(spvc_compiler compiler, spvc_type_id structTypeId, unsigned index, const std::string& name, uint32_t base,
                   uint32_t binding, std::vector<std::pair<std::string, LooseUniform>>& out) {
  spvc_type parent = spvc_compiler_get_type_handle(compiler, structTypeId);
  const spvc_type_id memberId = spvc_type_get_member_type(parent, index);
  spvc_type member = spvc_compiler_get_type_handle(compiler, memberId);
  unsigned offset = 0, arrayStride = 0, matrixStride = 0;
  spvc_compiler_type_struct_member_offset(compiler, parent, index, &offset);
  const unsigned dimensions = spvc_type_get_num_array_dimensions(member);
  if (dimensions > 1) return;
  const uint32_t count = dimensions == 1 ? spvc_type_get_array_dimension(member, 0) : 1;
  if (dimensions == 1) spvc_compiler_type_struct_member_array_stride(compiler, parent, index, &arrayStride);
  const spvc_type_id elementId = spvc_type_get_base_type_id(member);
  spvc_type element = spvc_compiler_get_type_handle(compiler, elementId);
  const spvc_basetype basetype = spvc_type_get_basetype(element);
  if (spvc_type_get_columns(element) > 1) spvc_compiler_type_struct_member_matrix_stride(compiler, parent, index, &matrixStride);
  for (uint32_t e = 0; e < count; ++e) {
    const std::string path = dimensions == 1 ? name + "[" + std::to_string(e) + "]" : name;
    const uint32_t at = base + offset + e * arrayStride;
    if (basetype == SPVC_BASETYPE_STRUCT) {
      flattenStruct(compiler, elementId, path + ".", at, binding, out);
      continue;
    }
    LooseUniform u;
    u.binding = binding;
    u.offset = at;
    u.rows = spvc_type_get_vector_size(element);
    u.columns = spvc_type_get_columns(element);
    u.matrixStride = matrixStride;
    switch (basetype) {
      case SPVC_BASETYPE_FP32: u.type = LooseUniform::Type::Float; break;
      case SPVC_BASETYPE_INT32: u.type = LooseUniform::Type::Int; break;
      case SPVC_BASETYPE_UINT32:
      case SPVC_BASETYPE_BOOLEAN: u.type = LooseUniform::Type::UInt; break;  // a bool in a block is 32 bits
      case SPVC_BASETYPE_FP64: u.type = LooseUniform::Type::Double; break;
      case SPVC_BASETYPE_INT64: u.type = LooseUniform::Type::Int64; break;
      case SPVC_BASETYPE_UINT64: u.type = LooseUniform::Type::UInt64; break;
      default: continue;  // 8- and 16-bit types: no loose form in OpenGL
    }
    out.emplace_back(path, u);
  }
}

bool reflectPort(const GlShader& shader, PortInterface* out, std::string* error) {
  const std::string& looseBlock = shader.looseUniformBlock;
  spvc_context raw = nullptr;
  if (spvc_context_create(&raw) != SPVC_SUCCESS) {
    *error = "SPIRV-Cross: cannot create a context";
    return false;
  }
  SpvcContext context(raw);
  spvc_parsed_ir ir = nullptr;
  spvc_compiler compiler = nullptr;
  spvc_resources resources = nullptr;
  if (spvc_context_parse_spirv(raw, shader.spirv.data(), shader.spirv.size(), &ir) != SPVC_SUCCESS ||
      spvc_context_create_compiler(raw, SPVC_BACKEND_NONE, ir, SPVC_CAPTURE_MODE_TAKE_OWNERSHIP, &compiler) != SPVC_SUCCESS ||
      spvc_compiler_create_shader_resources(compiler, &resources) != SPVC_SUCCESS) {
    *error = "SPIRV-Cross cannot read the port";
    return false;
  }
  auto list = [&](spvc_resource_type type) {
    const spvc_reflected_resource* items = nullptr;
    size_t count = 0;
    spvc_resources_get_resource_list_for_type(resources, type, &items, &count);
    return std::vector<spvc_reflected_resource>(items, items + count);
  };
  auto decoration = [&](spvc_variable_id id, SpvDecoration d) { return spvc_compiler_get_decoration(compiler, id, d); };
  auto variableName = [&](spvc_variable_id id) {
    const char* n = spvc_compiler_get_name(compiler, id);
    return std::string(n ? n : "");
  };
  for (auto [type, located] : {std::pair{SPVC_RESOURCE_TYPE_STAGE_INPUT, &out->inputs}, {SPVC_RESOURCE_TYPE_STAGE_OUTPUT, &out->outputs}})
    for (const spvc_reflected_resource& r : list(type)) {
      const std::string name = variableName(r.id);
      if (!name.empty() && name.rfind("gl_", 0) != 0 && spvc_compiler_has_decoration(compiler, r.id, SpvDecorationLocation))
        located->push_back({name, decoration(r.id, SpvDecorationLocation)});
    }
  for (const spvc_reflected_resource& r : list(SPVC_RESOURCE_TYPE_UNIFORM_BUFFER)) {
    const uint32_t binding = decoration(r.id, SpvDecorationBinding);
    if (r.name == looseBlock)
      flattenStruct(compiler, r.base_type_id, "", 0, binding, out->loose);
    else
    {
      PortInterface::Bound block{r.name, binding, elementsOf(compiler, r.type_id), {}};
      const std::string prefix = variableName(r.id).empty() ? std::string() : std::string(r.name) + ".";
      flattenStruct(compiler, r.base_type_id, prefix, 0, binding, block.members);
      out->uniformBlocks.push_back(std::move(block));
    }
  }
  for (const spvc_reflected_resource& r : list(SPVC_RESOURCE_TYPE_STORAGE_BUFFER)) {
    PortInterface::Bound block{r.name, decoration(r.id, SpvDecorationBinding), elementsOf(compiler, r.type_id), {}};
    spvc_type type = spvc_compiler_get_type_handle(compiler, r.base_type_id);
    for (unsigned i = 0; i < spvc_type_get_num_member_types(type); ++i) {
      const char* member = spvc_compiler_get_member_name(compiler, r.base_type_id, i);
      block.memberNames.push_back(member ? member : "");
    }
    out->storageBlocks.push_back(std::move(block));
  }
  for (spvc_resource_type type : {SPVC_RESOURCE_TYPE_SAMPLED_IMAGE, SPVC_RESOURCE_TYPE_STORAGE_IMAGE})
    for (const spvc_reflected_resource& r : list(type))
      out->opaque.push_back({variableName(r.id), decoration(r.id, SpvDecorationBinding), elementsOf(compiler, r.type_id)});
  return true;
}

std::string elementName(const std::string& name, uint32_t arraySize, uint32_t element) {
  return arraySize > 1 ? name + "[" + std::to_string(element) + "]" : name;
}

}  // namespace

std::vector<GLuint> GlDevice::compileOpenGlGlsl(const ShaderDesc& desc, std::string* error) {
  std::vector<GLuint> units;
  for (const std::string& source : desc.openGlGlsl) {
    GLuint name = gl.CreateShader(glStage(desc.stage));
    const GLchar* text = source.c_str();
    gl.ShaderSource(name, 1, &text, nullptr);
    // The driver's compiler messages are this call's result, not debug output.
    gl.DebugMessageControl(GL_DEBUG_SOURCE_SHADER_COMPILER, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_FALSE);
    gl.CompileShader(name);
    for (GLenum severity : {GL_DEBUG_SEVERITY_HIGH, GL_DEBUG_SEVERITY_MEDIUM, GL_DEBUG_SEVERITY_LOW})
      gl.DebugMessageControl(GL_DEBUG_SOURCE_SHADER_COMPILER, GL_DONT_CARE, severity, 0, nullptr, GL_TRUE);
    units.push_back(name);
    GLint ok = GL_FALSE;
    gl.GetShaderiv(name, GL_COMPILE_STATUS, &ok);
    if (ok) continue;
    *error = "the OpenGL GLSL does not compile:\n" + shaderInfoLog(name);
    for (GLuint u : units) gl.DeleteShader(u);
    return {};
  }
  return units;
}

GLuint GlDevice::linkOpenGlGlsl(const std::vector<const GlShader*>& shaders, std::string* error, bool separable) {
  const GLuint program = gl.CreateProgram();
  if (separable) gl.ProgramParameteri(program, GL_PROGRAM_SEPARABLE, GL_TRUE);  // PipelineDesc::separablePrograms
  for (const GlShader* s : shaders) {
    for (GLuint unit : s->openGlUnits) gl.AttachShader(program, unit);
    PortInterface port;
    if (!reflectPort(*s, &port, error)) {
      gl.DeleteProgram(program);
      return 0;
    }
    if (s->stage == ShaderStage::Vertex)
      for (const PortInterface::Located& in : port.inputs)
        gl.BindAttribLocation(program, openGlAttributeLocation(s->reflection, in.location), in.name.c_str());
    if (s->stage == ShaderStage::Fragment)
      for (const PortInterface::Located& out : port.outputs) gl.BindFragDataLocation(program, out.location, out.name.c_str());
  }
  gl.DebugMessageControl(GL_DEBUG_SOURCE_SHADER_COMPILER, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_FALSE);
  gl.LinkProgram(program);
  for (GLenum severity : {GL_DEBUG_SEVERITY_HIGH, GL_DEBUG_SEVERITY_MEDIUM, GL_DEBUG_SEVERITY_LOW})
    gl.DebugMessageControl(GL_DEBUG_SOURCE_SHADER_COMPILER, GL_DONT_CARE, severity, 0, nullptr, GL_TRUE);
  for (const GlShader* s : shaders)
    for (GLuint unit : s->openGlUnits) gl.DetachShader(program, unit);
  GLint ok = GL_FALSE;
  gl.GetProgramiv(program, GL_LINK_STATUS, &ok);
  if (ok) return program;
  *error = "the OpenGL GLSL does not link:\n" + programInfoLog(program);
  gl.DeleteProgram(program);
  return 0;
}

void GlDevice::placeOpenGlInterface(const std::vector<const GlShader*>& shaders, GlProgram& p) {
  p.openGlClipSpace = true;
  p.looseUniforms.clear();
  p.attributeLocations.clear();
  p.repackedBlocks.clear();
  p.atomicCounterBuffers.clear();
  // The program's offsets of a port block's members; where one differs from the port's, the
  // block is repacked at each draw (GlProgram::RepackedBlock).
  auto repackIfLaidOutOtherwise = [&](const PortInterface::Bound& b) {
    for (uint32_t e = 0; e < b.arraySize && b.binding < kMaxBindings; ++e) {
      const GLuint block = gl.GetProgramResourceIndex(p.name, GL_UNIFORM_BLOCK, elementName(b.name, b.arraySize, e).c_str());
      const bool known = std::any_of(p.repackedBlocks.begin(), p.repackedBlocks.end(),
                                     [&](const GlProgram::RepackedBlock& r) { return r.binding == b.binding && r.element == e; });
      if (block == GL_INVALID_INDEX || known) continue;  // a block both stages declare is repacked once
      const GLenum sizeProperty = GL_BUFFER_DATA_SIZE;
      GLint size = 0;
      gl.GetProgramResourceiv(p.name, GL_UNIFORM_BLOCK, block, 1, &sizeProperty, 1, nullptr, &size);
      GlProgram::RepackedBlock repacked;
      repacked.binding = b.binding;
      repacked.element = e;
      repacked.size = static_cast<uint32_t>(std::max(size, 0));
      bool differs = false;
      for (const auto& [name, u] : b.members) {
        // Element k of an array of scalars, vectors or matrices is found through element 0.
        std::string query = name;
        uint32_t k = 0;
        if (!query.empty() && query.back() == ']') {
          const size_t open = query.rfind('[');
          k = static_cast<uint32_t>(std::stoul(query.substr(open + 1)));
          query = query.substr(0, open) + "[0]";
        }
        const GLuint index = gl.GetProgramResourceIndex(p.name, GL_UNIFORM, query.c_str());
        if (index == GL_INVALID_INDEX) continue;  // inactive in the program
        const GLenum properties[3] = {GL_OFFSET, GL_ARRAY_STRIDE, GL_MATRIX_STRIDE};
        GLint values[3] = {0, 0, 0};
        gl.GetProgramResourceiv(p.name, GL_UNIFORM, index, 3, properties, 3, nullptr, values);
        const uint32_t scalar = u.type == LooseUniform::Type::Double || u.type == LooseUniform::Type::Int64 ||
                                        u.type == LooseUniform::Type::UInt64 ? 8 : 4;
        const uint32_t to = static_cast<uint32_t>(values[0]) + k * static_cast<uint32_t>(values[1]);
        for (uint32_t c = 0; c < u.columns; ++c) {
          const uint32_t move[3] = {u.offset + c * u.matrixStride, to + c * static_cast<uint32_t>(values[2]), u.rows * scalar};
          differs |= move[0] != move[1];
          repacked.moves.push_back({move[0], move[1], move[2]});
        }
      }
      if (!differs || repacked.size == 0) continue;
      gl.CreateBuffers(1, &repacked.shadow);
      gl.NamedBufferStorage(repacked.shadow, repacked.size, nullptr, GL_DYNAMIC_STORAGE_BIT);
      p.repackedBlocks.push_back(std::move(repacked));
    }
  };
  // The port's storage block (glslang's relaxed rules gather OpenGL's atomic counters into one
  // per binding) holding each atomic counter buffer's counters, found by their names.
  auto placeAtomicCounterBuffers = [&](const std::vector<PortInterface::Bound>& storageBlocks) {
    GLint buffers = 0;
    gl.GetProgramInterfaceiv(p.name, GL_ATOMIC_COUNTER_BUFFER, GL_ACTIVE_RESOURCES, &buffers);
    for (GLint i = 0; i < buffers; ++i) {
      const GLenum properties[2] = {GL_BUFFER_BINDING, GL_NUM_ACTIVE_VARIABLES};
      GLint values[2] = {0, 0};
      gl.GetProgramResourceiv(p.name, GL_ATOMIC_COUNTER_BUFFER, static_cast<GLuint>(i), 2, properties, 2, nullptr, values);
      if (values[1] < 1) continue;
      const GLenum variables = GL_ACTIVE_VARIABLES;
      // All of them: Mesa (22.3) writes every active variable whatever the buffer size given.
      std::vector<GLint> counters(static_cast<size_t>(values[1]));
      gl.GetProgramResourceiv(p.name, GL_ATOMIC_COUNTER_BUFFER, static_cast<GLuint>(i), 1, &variables, values[1], nullptr, counters.data());
      char name[256] = {};  // the buffer's first counter names it
      gl.GetProgramResourceName(p.name, GL_UNIFORM, static_cast<GLuint>(counters[0]), sizeof name, nullptr, name);
      const std::string declared = std::string(name).substr(0, std::string(name).find('['));  // "a[1][0]": a
      for (const PortInterface::Bound& b : storageBlocks) {
        const bool holds = std::find(b.memberNames.begin(), b.memberNames.end(), declared) != b.memberNames.end();
        const bool known = std::any_of(p.atomicCounterBuffers.begin(), p.atomicCounterBuffers.end(),
                                       [&](const GlProgram::AtomicCounterBuffer& a) { return a.point == static_cast<GLuint>(values[0]); });
        if (holds && !known && b.binding < kMaxBindings) p.atomicCounterBuffers.push_back({b.binding, static_cast<GLuint>(values[0])});
      }
    }
  };
  for (const GlShader* s : shaders) {
    PortInterface port;
    std::string error;
    if (!reflectPort(*s, &port, &error)) continue;  // linkOpenGlGlsl read the same module
    if (s->stage == ShaderStage::Vertex) {
      // Where the program has each input (an explicit location wins over glBindAttribLocation);
      // the locations after an input's first, up to the next input, are its further vectors.
      std::sort(port.inputs.begin(), port.inputs.end(), [](const auto& a, const auto& b) { return a.location < b.location; });
      for (size_t i = 0; i < port.inputs.size(); ++i) {
        const GLint first = gl.GetAttribLocation(p.name, port.inputs[i].name.c_str());
        if (first < 0) continue;
        const uint32_t from = port.inputs[i].location, to = i + 1 < port.inputs.size() ? port.inputs[i + 1].location : kMaxVertexAttributes;
        const uint32_t base = openGlAttributeLocation(s->reflection, from);
        for (uint32_t l = from; l < to && l < kMaxVertexAttributes; ++l)
          p.attributeLocations[l] = static_cast<uint32_t>(first) + openGlAttributeLocation(s->reflection, l) - base;
      }
    }
    for (auto [blocks, interface] : {std::pair{&port.uniformBlocks, GL_UNIFORM_BLOCK}, {&port.storageBlocks, GL_SHADER_STORAGE_BLOCK}})
      for (const PortInterface::Bound& b : *blocks)
        for (uint32_t e = 0; e < b.arraySize && b.binding < kMaxBindings; ++e) {
          const GLuint index = gl.GetProgramResourceIndex(p.name, interface, elementName(b.name, b.arraySize, e).c_str());
          if (index == GL_INVALID_INDEX) continue;
          if (interface == GL_UNIFORM_BLOCK)
            gl.UniformBlockBinding(p.name, index, p.points[b.binding] + e);
          else
            gl.ShaderStorageBlockBinding(p.name, index, p.points[b.binding] + e);
        }
    for (const PortInterface::Bound& b : port.uniformBlocks) repackIfLaidOutOtherwise(b);
    placeAtomicCounterBuffers(port.storageBlocks);
    for (const PortInterface::Bound& o : port.opaque)
      for (uint32_t e = 0; e < o.arraySize && o.binding < kMaxBindings; ++e) {
        const GLint location = gl.GetUniformLocation(p.name, elementName(o.name, o.arraySize, e).c_str());
        if (location >= 0) gl.ProgramUniform1i(p.name, location, static_cast<GLint>(p.points[o.binding] + e));
      }
    for (auto& [name, u] : port.loose) {
      u.location = gl.GetUniformLocation(p.name, name.c_str());
      const bool known = std::any_of(p.looseUniforms.begin(), p.looseUniforms.end(),
                                     [&](const LooseUniform& l) { return l.location == u.location; });
      if (u.location >= 0 && !known) p.looseUniforms.push_back(u);  // a uniform both stages declare is set once
    }
  }
}

void GlDevice::applyOpenGlInterface(const GlProgram& p) {
  copyLooseUniforms(p);
  repackUniformBlocks(p);
  bindAtomicCounterBuffers(p);
}

void GlDevice::bindAtomicCounterBuffers(const GlProgram& p) {
  for (const GlProgram::AtomicCounterBuffer& a : p.atomicCounterBuffers) {
    const std::optional<ResourceBinding>& bound = bindings_[a.binding][0];
    std::unique_ptr<GlBuffer>* buffer = bound ? buffers_.get(bound->buffer) : nullptr;
    if (!buffer || bound->offset >= (*buffer)->desc.size) continue;
    const size_t size = bound->size ? bound->size : (*buffer)->desc.size - bound->offset;
    gl.BindBufferRange(GL_ATOMIC_COUNTER_BUFFER, a.point, (*buffer)->name, static_cast<GLintptr>(bound->offset), static_cast<GLsizeiptr>(size));
  }
}

void GlDevice::repackUniformBlocks(const GlProgram& p) {
  std::vector<unsigned char> from, to;
  for (const GlProgram::RepackedBlock& b : p.repackedBlocks) {
    const std::optional<ResourceBinding>& bound = bindings_[b.binding][b.element];
    std::unique_ptr<GlBuffer>* buffer = bound ? buffers_.get(bound->buffer) : nullptr;
    if (!buffer || bound->offset >= (*buffer)->desc.size) continue;
    const size_t size = bound->size ? std::min(bound->size, (*buffer)->desc.size - bound->offset) : (*buffer)->desc.size - bound->offset;
    from.assign(size, 0);
    gl.GetNamedBufferSubData((*buffer)->name, static_cast<GLintptr>(bound->offset), static_cast<GLsizeiptr>(size), from.data());
    to.assign(b.size, 0);
    for (const GlProgram::RepackedBlock::Move& m : b.moves)
      if (m.from + m.bytes <= from.size() && m.to + m.bytes <= to.size()) std::memcpy(to.data() + m.to, from.data() + m.from, m.bytes);
    gl.NamedBufferSubData(b.shadow, 0, static_cast<GLsizeiptr>(to.size()), to.data());
    gl.BindBufferRange(GL_UNIFORM_BUFFER, p.points[b.binding] + b.element, b.shadow, 0, static_cast<GLsizeiptr>(to.size()));
  }
}

void GlDevice::copyLooseUniforms(const GlProgram& p) {
  std::vector<unsigned char> block;
  uint32_t loaded = kMaxBindings;
  for (const LooseUniform& u : p.looseUniforms) {
    if (u.binding >= kMaxBindings) continue;
    if (u.binding != loaded) {
      loaded = u.binding;
      block.clear();
      const std::optional<ResourceBinding>& b = bindings_[u.binding][0];
      std::unique_ptr<GlBuffer>* buffer = b ? buffers_.get(b->buffer) : nullptr;
      if (!buffer || b->offset >= (*buffer)->desc.size) continue;
      const size_t size = b->size ? std::min(b->size, (*buffer)->desc.size - b->offset) : (*buffer)->desc.size - b->offset;
      block.resize(size);
      gl.GetNamedBufferSubData((*buffer)->name, static_cast<GLintptr>(b->offset), static_cast<GLsizeiptr>(size), block.data());
    }
    const bool wide = u.type == LooseUniform::Type::Double || u.type == LooseUniform::Type::Int64 || u.type == LooseUniform::Type::UInt64;
    const size_t scalar = wide ? 8 : 4;
    const size_t stride = u.columns > 1 ? u.matrixStride : u.rows * scalar;
    if (u.offset + (u.columns - 1) * stride + u.rows * scalar > block.size()) continue;
    // The block's columns are matrixStride apart; glProgramUniformMatrix* takes them packed.
    unsigned char packed[4 * 4 * 8];
    for (uint32_t c = 0; c < u.columns; ++c) std::memcpy(packed + c * u.rows * scalar, block.data() + u.offset + c * stride, u.rows * scalar);
    const GLint at = u.location;
    const GLuint prog = p.name;
    const int shape = static_cast<int>(u.columns * 10 + u.rows);
    if (u.type == LooseUniform::Type::Float || u.type == LooseUniform::Type::Double) {
      const bool d = u.type == LooseUniform::Type::Double;
      const auto* f = reinterpret_cast<const GLfloat*>(packed);
      const auto* dv = reinterpret_cast<const GLdouble*>(packed);
      switch (shape) {
        case 11: d ? gl.ProgramUniform1dv(prog, at, 1, dv) : gl.ProgramUniform1fv(prog, at, 1, f); break;
        case 12: d ? gl.ProgramUniform2dv(prog, at, 1, dv) : gl.ProgramUniform2fv(prog, at, 1, f); break;
        case 13: d ? gl.ProgramUniform3dv(prog, at, 1, dv) : gl.ProgramUniform3fv(prog, at, 1, f); break;
        case 14: d ? gl.ProgramUniform4dv(prog, at, 1, dv) : gl.ProgramUniform4fv(prog, at, 1, f); break;
        case 22: d ? gl.ProgramUniformMatrix2dv(prog, at, 1, GL_FALSE, dv) : gl.ProgramUniformMatrix2fv(prog, at, 1, GL_FALSE, f); break;
        case 33: d ? gl.ProgramUniformMatrix3dv(prog, at, 1, GL_FALSE, dv) : gl.ProgramUniformMatrix3fv(prog, at, 1, GL_FALSE, f); break;
        case 44: d ? gl.ProgramUniformMatrix4dv(prog, at, 1, GL_FALSE, dv) : gl.ProgramUniformMatrix4fv(prog, at, 1, GL_FALSE, f); break;
        case 23: d ? gl.ProgramUniformMatrix2x3dv(prog, at, 1, GL_FALSE, dv) : gl.ProgramUniformMatrix2x3fv(prog, at, 1, GL_FALSE, f); break;
        case 32: d ? gl.ProgramUniformMatrix3x2dv(prog, at, 1, GL_FALSE, dv) : gl.ProgramUniformMatrix3x2fv(prog, at, 1, GL_FALSE, f); break;
        case 24: d ? gl.ProgramUniformMatrix2x4dv(prog, at, 1, GL_FALSE, dv) : gl.ProgramUniformMatrix2x4fv(prog, at, 1, GL_FALSE, f); break;
        case 42: d ? gl.ProgramUniformMatrix4x2dv(prog, at, 1, GL_FALSE, dv) : gl.ProgramUniformMatrix4x2fv(prog, at, 1, GL_FALSE, f); break;
        case 34: d ? gl.ProgramUniformMatrix3x4dv(prog, at, 1, GL_FALSE, dv) : gl.ProgramUniformMatrix3x4fv(prog, at, 1, GL_FALSE, f); break;
        case 43: d ? gl.ProgramUniformMatrix4x3dv(prog, at, 1, GL_FALSE, dv) : gl.ProgramUniformMatrix4x3fv(prog, at, 1, GL_FALSE, f); break;
        default: break;
      }
      continue;
    }
    if (u.type == LooseUniform::Type::Int64 || u.type == LooseUniform::Type::UInt64) {
      if (u.rows < 1 || u.rows > 4) continue;
      if (u.type == LooseUniform::Type::Int64 && programUniformI64_[u.rows - 1])
        programUniformI64_[u.rows - 1](prog, at, 1, reinterpret_cast<const GLint64*>(packed));
      if (u.type == LooseUniform::Type::UInt64 && programUniformUI64_[u.rows - 1])
        programUniformUI64_[u.rows - 1](prog, at, 1, reinterpret_cast<const GLuint64*>(packed));
      continue;
    }
    const bool i = u.type == LooseUniform::Type::Int;
    const auto* iv = reinterpret_cast<const GLint*>(packed);
    const auto* uv = reinterpret_cast<const GLuint*>(packed);
    switch (u.rows) {
      case 1: i ? gl.ProgramUniform1iv(prog, at, 1, iv) : gl.ProgramUniform1uiv(prog, at, 1, uv); break;
      case 2: i ? gl.ProgramUniform2iv(prog, at, 1, iv) : gl.ProgramUniform2uiv(prog, at, 1, uv); break;
      case 3: i ? gl.ProgramUniform3iv(prog, at, 1, iv) : gl.ProgramUniform3uiv(prog, at, 1, uv); break;
      case 4: i ? gl.ProgramUniform4iv(prog, at, 1, iv) : gl.ProgramUniform4uiv(prog, at, 1, uv); break;
      default: break;
    }
  }
}

}  // namespace parity::rhi::gl
