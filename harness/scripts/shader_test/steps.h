// piglit's and VkRunner's shader_test format, parsed into a Script (harness/scripts/script.h):
// what its parsing steps share (the file's sections, the framebuffer, vertex data and pipelines
// being built). The families of steps are layers over it: sections (sections.cpp) under buffers
// and uniforms (buffers.cpp) under probes (probes.cpp) under draws and state (draws.cpp), and
// ShaderTestParser (parser.cpp), which reads the [test] commands.
#pragma once

#include <array>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "harness/scripts/script.h"
#include "harness/scripts/shader_test_parser.h"

namespace parity::harness::script::shader_test {

struct ShaderTestError {
  int line = 0;
  std::string message;
};

std::string trim(const std::string& s);
// Words of a [test] line: parentheses and commas separate like blanks ("(0.5, 0.5)").
std::vector<std::string> words(const std::string& line);
// A line with its comment removed: '#' starts one in [require], [test] and data sections.
std::string uncommented(const std::string& line);
bool parseNumber(const std::string& s, Value* v);
// GLSL type names as Amber DATA_TYPE names: "vec3" -> "vec3<float>", "dmat2x3" -> "mat2x3<double>".
// Booleans are 32-bit words in a block. Empty when the type has no such spelling (samplers, ...).
std::string amberTypeName(const std::string& glsl);

class ShaderTestState {
 public:
  ShaderTestState(const std::string& text, const std::string& name) : name_(name) {
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) {
      if (!l.empty() && l.back() == '\r') l.pop_back();
      lines_.push_back(l);
    }
    script_.file = name;
  }

 protected:
  struct Section {
    std::string name;
    int header = 0;                               // line of "[name]"
    std::vector<std::pair<int, std::string>> lines;  // 1-based line, text
  };
  struct Attribute {
    std::string name;  // piglit: the shader input's name
    uint32_t location = 0;
    // piglit: locations after the input's own (an array element's, a matrix column's).
    uint32_t locationOffset = 0;
    std::string format;  // the Vulkan format name of one column's components
    ElementType type;
  };
  struct BufferUse {
    std::string kind;  // "ssbo", "ubo"
    uint32_t set = 0, binding = 0;
    uint64_t size = 0;
  };

  std::string name_;
  std::vector<std::string> lines_;
  std::vector<Section> sections_;
  Script script_;
  bool piglit_ = false;
  double tolerance_ = 0.01;
  std::vector<Tolerance> tolerances_;  // `tolerance` lines: replaces the default per channel
  uint32_t width_ = 250, height_ = 250;  // the window's size, then the current framebuffer's
  // piglit's `fb tex 2d N`: draws, clears and probes go to the texture on unit N from then on.
  std::string framebuffer_ = "framebuffer";
  std::vector<Command> clearState_;  // the last clear color, depth and stencil commands
  std::string framebufferFormat_ = "R8G8B8A8_UNORM", depthFormat_;
  std::vector<Attribute> attributes_;
  std::vector<uint32_t> vertexOffsets_;  // of each attribute in the interleaved vertex_data buffer
  uint32_t vertexStride_ = 0;
  std::vector<Value> indices_;
  std::map<std::string, Pipeline*> pipelineByRole_;
  bool drawn_ = false;
  uint32_t patchVertices_ = 0;  // the last `patch parameter vertices` (0: none yet)
  uint32_t uboArrayIndex_ = 0;  // `ubo array index N`
  // VkRunner's pipeline properties and stage entry points set so far (properties.cpp), by name
  // ("front.failOp", "fragment entrypoint"), each with its value in canonical form, and those
  // the first draw or dispatch used: the pipelines hold these; other sets are variants of them.
  std::map<std::string, std::string> properties_;
  std::optional<std::map<std::string, std::string>> propertiesOfFirstDraw_;
  // The variants made so far: pipeline "BASE state N" is element N - 1, (BASE, its properties).
  std::vector<std::pair<std::string, std::map<std::string, std::string>>> propertyVariants_;
  // VkRunner's `ubo|ssbo|push layout`: how typed values are laid out in each kind of buffer.
  struct BlockLayout {
    bool std140 = false, rowMajor = false;
  };
  std::map<std::string, BlockLayout> blockLayouts_ = {{"ubo", {true, false}}, {"ssbo", {}}, {"push", {}}};
  int lastTextureUnit_ = 0;
  // piglit's `[require] SPIRV YES|ONLY|NO` (empty: not given). YES and ONLY make the [X shader
  // spirv] sections the program, NO (or nothing) the GLSL ones: piglit's runner ignores the others.
  std::string spirvMode_;
  bool spirvProgram() const { return piglit_ && (spirvMode_ == "YES" || spirvMode_ == "ONLY"); }
  // piglit's `block binding|offset|array index|matrix stride|row major N`: where the next
  // `uniform` of a SPIR-V program (which has no names to look up) goes, and which block a
  // `verify program_interface_query` asks about. -1: not given yet.
  struct BlockPosition {
    int64_t binding = -1, offset = -1, arrayIndex = 0, matrixStride = -1;
    bool rowMajor = false;
  };
  BlockPosition block_;
  // piglit's [X shader specializations] of a SPIR-V program: by shader name, SpecId -> the
  // constant's 32 bits (Pipeline::specializations of every pipeline running the shader).
  std::map<std::string, std::map<uint32_t, uint32_t>> specializations_;
  int glslVersion_ = 110;  // piglit's active texture unit: the last `texture` command's

  [[noreturn]] void error(int line, const std::string& msg) { throw ShaderTestError{line, msg}; }
  void unsupported(int line, const std::string& what) { script_.unsupported.push_back({what, {line, 1}}); }
  void splitSections();
  // VkRunner: a line ending in '\' goes on in the next one (outside shader sections, whose
  // backslashes are the shading language's).
  void joinContinuedLines();
};

// The sections: [require], the shaders, [vertex data], [indices], and the framebuffer they imply.
class SectionSteps : public ShaderTestState {
 public:
  using ShaderTestState::ShaderTestState;

 protected:
  void require(const Section& s);
  void shader(const Section& s);
  // [X shader specializations]: lines `uint|int|float SPEC_ID VALUE` (spirv_programs.cpp).
  void specializations(const Section& s, const std::string& shaderName);
  void arbProgram(const Section& s);
  void vertexData(const Section& s);
  // "piglit_vertex/float/2", "color/float/vec3" (piglit) or "0/R32G32_SFLOAT" (VkRunner).
  Attribute attribute(int line, const std::string& column);
  void indices(const Section& s);
  void declareFramebuffer();
};

// ssbo, ubo, push and uniform commands, atomic counter buffers and textures.
class BufferCommands : public SectionSteps {
 public:
  using SectionSteps::SectionSteps;

 protected:
  Pipeline* pipeline(const std::string& name);
  // Buffers named by ssbo/ubo commands: "ssbo N", "ssbo SET:BINDING" or, for element E of a
  // descriptor array, "ssbo SET:BINDING:E".
  std::string bufferFor(int line, const std::string& kind, const std::string& where, uint64_t extent);
  std::string pushBuffer(int line, uint64_t extent);
  ElementType valueType(int line, const std::string& glsl, bool std140, bool rowMajor = false);
  // valueType() in the layout of `kind`'s buffers ("ubo", "ssbo", "push"; VkRunner's
  // `KIND layout [std140|std430] [row_major|column_major]`).
  ElementType valueTypeIn(int line, const std::string& glsl, const std::string& kind);
  void blockLayout(int line, const std::vector<std::string>& w);
  std::vector<Value> numbers(int line, const std::vector<std::string>& w, size_t from);
  // numbers() of `type`'s fields in turn, a float's or double's hexadecimal ones read as its bits.
  std::vector<Value> typedNumbers(int line, const std::vector<std::string>& w, size_t from, const ElementType& type);
  // Values of `type` packed from byte 0 in the type's array stride.
  static std::vector<uint8_t> pack(const ElementType& type, const std::vector<Value>& values);
  // `KIND TYPE OFFSET values` written into a buffer (ubo/ssbo subdata, push, VkRunner's uniform).
  void writeBuffer(int line, const std::string& kind, const std::string& where, const std::vector<std::string>& w, size_t typeAt);
  // The atomic-counter buffer of OpenGL binding `binding` (piglit's atomics_bos[binding]).
  std::string atomicCounterBuffer(int line, uint32_t binding);
  // piglit's procedural textures (piglit-util-gl.c), as RGBA8 images on a texture unit, with the
  // sampler state piglit gives them: `texture rgbw UNIT (W, H)` is red, green, blue and white
  // quadrants (red at the first row and column), nearest, clamped to the edge;
  // `texture quads UNIT LEVEL (W, H) (SX, SY) (bl) (br) (tl) (tr)` is squares of SX x SY, bl where
  // the square's row and column (from the first row and column) are even, br at an odd column,
  // tl at an odd row, tr where both are odd, nearest; `texture checkerboard UNIT LEVEL (W, H)
  // (colour0) (colour1)` is quads of W/2 x H/2 with colour1 where exactly one is odd. piglit clamps
  // both to a red border, which Vulkan's border colours cannot express: they are clamped to the
  // edge here, which only differs for coordinates outside [0, 1].
  void texture(int line, const std::vector<std::string>& w);
  // `texture rgbw|junk 2DArray UNIT (W, H, LAYERS)`: piglit_array_texture's layers of one colour
  // each, red, green, blue, white and again; junk is undefined (zeros here).
  void arrayTexture(int line, const std::vector<std::string>& w);
  // `image texture UNIT [FORMAT]`: the texture on UNIT bound to image unit UNIT.
  void imageTexture(int line, const std::vector<std::string>& w);
  static void appendTexel(Buffer& image, const std::array<double, 4>& rgba);
  void miptree(int line, const std::vector<std::string>& w);
  void shadowTexture(int line, const std::vector<std::string>& w);
  void depthMode(int line, const std::string& mode);
  std::map<std::string, int> samplerUnits_;  // `uniform int NAME unit`: the last unit given to NAME
  Buffer textureImage(int line, int unit, uint32_t width, uint32_t height, const std::string& format);
  void placeTexture(int line, const Buffer& image, int unit);
  // texparameter 2D min|mag nearest|linear: the filter of the last texture's unit.
  void texparameter(int line, const std::vector<std::string>& w);
  // piglit: uniform TYPE NAME values
  void setUniform(int line, const std::vector<std::string>& w);
};

// probe rgba/rgb/all (relative too), probe ssbo and atomic counters.
class ProbeCommands : public BufferCommands {
 public:
  using BufferCommands::BufferCommands;

 protected:
  std::vector<Tolerance> tolerances() const;
  void probe(int line, const std::vector<std::string>& w, size_t at, bool relative);
  // active uniform NAME PNAME VALUE: a property of the uniform's layout in its block.
  void activeUniform(int line, const std::vector<std::string>& w);
  // SPIR-V programs (spirv_programs.cpp): `block ...`, `uniform TYPE NAME values` written at the
  // block position, `verify program_interface_query` and `verify program_query`.
  void blockPosition(int line, const std::vector<std::string>& w);
  void setBlockUniform(int line, const std::vector<std::string>& w);
  void verifyProgramQuery(int line, const std::vector<std::string>& w);
  // probe ssbo TYPE BINDING OFFSET OP values
  void probeBuffer(int line, const std::vector<std::string>& w);
  // shader_runner.c: `atomic counters N` makes binding 0's buffer of N zeroed counters,
  // `atomic counter buffer B N` binding B's, and `atomic counter B I V` sets counter I of B to V.
  void atomicCounters(int line, const std::vector<std::string>& w);
  // probe atomic counter INDEX OP VALUE (binding 0's counter INDEX) or
  // probe atomic counter buffer BINDING BYTE_OFFSET OP VALUE.
  void probeAtomicCounter(int line, const std::vector<std::string>& w);
};

// draw rect/arrays and the pipeline state commands.
class DrawCommands : public ProbeCommands {
 public:
  using ProbeCommands::ProbeCommands;

 protected:
  // VkRunner's pipeline properties (`cullMode VK_CULL_MODE_BACK_BIT`) and `STAGE entrypoint NAME`.
  void pipelineState(int line, const std::vector<std::string>& w);
  static bool isPipelineProperty(const std::string& name);
  // The pipeline a draw or dispatch at `line` runs: `base` while the properties are those of the
  // first one, else a variant of it with the current properties; their constructs the RHI lacks
  // are named unsupported here, at the draw that uses them.
  std::string propertiesPipeline(int line, const std::string& base, const std::string& topology, bool indexed);
  void applyProperties(Pipeline& p) const;
  // `fb tex 2d UNIT`: the texture on UNIT is the framebuffer from now on.
  void framebufferTexture(int line, const std::vector<std::string>& w);
  // The pipeline `base` drawing into the current framebuffer: itself for the window's, else a
  // copy whose colour attachment is that texture.
  std::string framebufferPipeline(const std::string& base);
  // clear color, clear depth, clear stencil: OpenGL context state, for every framebuffer.
  void clearValue(int line, Command::Kind kind, const std::vector<Value>& v);
  void draw(int line, const std::vector<std::string>& w);
  Command clearCommand(int line, Command::Kind kind);
};

// The whole file: sections first, then the [test] commands in order.
class ShaderTestParser : public DrawCommands {
 public:
  using DrawCommands::DrawCommands;
  Script run();

 private:
  Script parseAfterRequirements();
  void namedString(const Section& s);
  // glClipPlane and GL_CLIP_PLANEi into kClipPlaneUniform (all zeros while disabled), where a
  // shader writes gl_ClipVertex.
  void loadClipPlane(int line, size_t plane);
  void fixedFunctionBeforeDraw(int line, bool& state, bool value);
  // hint TARGET MODE: glHint's names, checked and recorded (Command::Kind::Hint).
  void hint(int line, const std::vector<std::string>& w);
  std::array<std::array<double, 4>, 8> clipPlanes_{};
  std::array<bool, 8> clipPlaneEnabled_{};
  void test(const Section& s);
  // The compatibility matrices the shaders read (opengl_glsl.h), set as OpenGL's matrix stacks
  // hold them: the model-view the identity, the projection `projection` (column by column).
  void loadCompatibilityMatrices(int line, const std::array<double, 16>& projection);
  void arbFixedFunction();
};

}  // namespace parity::harness::script::shader_test
