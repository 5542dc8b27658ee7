// The AmberScript parser, one class per statement family (docs/script-format.md lists the
// statements): declarations (SHADER, BUFFER, IMAGE, SAMPLER, STRUCT, VIRTUAL_FILE), pipelines
// (PIPELINE, DERIVE_PIPELINE and their bodies: ATTACH, BIND, VERTEX_DATA, DEPTH, STENCIL, BLEND,
// ...) and commands (CLEAR*, RUN, RESOLVE, EXPECT). Parser dispatches each statement to its family
// and holds the script-level statements (REQUIRE, SET, DEVICE_*, REPEAT, COPY). The families share
// one Reader, the token stream and the script being built, through a virtual base.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "harness/scripts/amber/reader.h"

namespace parity::harness::script::amber {

// declarations.cpp
class DeclarationStatements : protected virtual Reader {
 protected:
  // VIRTUAL_FILE path NEWLINE lines END: a file that SHADER ... VIRTUAL_FILE path (or FILE path)
  // reads instead of the disk.
  void virtualFile(const Token& t);
  // STRUCT name [STRIDE n] NEWLINE (type member [OFFSET n])* END
  void structDecl(const Token& t);
  // std430/std140 layout of a struct: flattened fields, size, alignment.
  void structLayout(const std::string& name, bool std140, Layout* out, uint32_t* size, uint32_t* align);
  void shader(const Token& t);
  void buffer(const Token& t, bool isImage);
  void sampler(const Token& t);

 private:
  struct StructMember {
    std::string type, name;
    std::optional<uint32_t> offset;
  };
  std::map<std::string, std::vector<StructMember>> structs_;
  std::map<std::string, uint32_t> structStrides_;        // STRUCT name STRIDE n
  std::map<std::string, std::string> virtualFiles_;      // VIRTUAL_FILE path -> contents
};

// pipelines.cpp
class PipelineStatements : protected virtual Reader {
 protected:
  void pipelineBody(Pipeline& p, const Token& start);
  void subgroup(Pipeline& p, const Token& w);
  void bind(Pipeline& p, const Token& w);
  static void addBind(Pipeline& p, const Bind& b);
  void depthBlock(Pipeline& p, const Token& start);
  void stencilBlock(Pipeline& p, const Token& start);
  void blendBlock(Pipeline& p, const Token& start);
  void pipeline(const Token& t);
  void derivePipeline(const Token& t);
};

// commands.cpp
class CommandStatements : protected virtual Reader {
 protected:
  void clear(const Token& t);
  void run(const Token& t);
  // Ours: RESOLVE img [SAMPLES n]: the platform's resolve (or copy) of a LOGICAL image.
  void resolve(const Token& t);
  // Ours: EXPECT img MEMORY BYTES [RESOLVED] [PLATFORM p] IDX x y [SIZE w h] EQ bytes...
  void expectMemory(Command& c, const Buffer& b);
  // Ours: EXPECT img EQ_IMAGE (FILE path | GOLDEN name) [RMSE t] [MAX t] [FLIP t]
  void expectImage(Command& c);
  std::vector<Tolerance> tolerances();
  void expect(const Token& t);
};

// parser.cpp
class Parser : DeclarationStatements, PipelineStatements, CommandStatements {
 public:
  Parser(const std::string& text, const std::string& name) : Reader(text, name) {}
  // Every statement of the file, in order.
  Script parseAll();

 private:
  void statement(const Token& t);
  void require(const Token& t);
  void set(const Token& t);
  // Checked against the device's features when the script runs (runScript).
  void deviceFeature(const Token& t);
};

}  // namespace parity::harness::script::amber
