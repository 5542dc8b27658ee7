// The reading side of the AmberScript parser, shared by its statement families
// (declarations.cpp, pipelines.cpp, commands.cpp, parser.cpp): the token stream with Amber's
// line continuations and comments, number and value tokens, errors with their line and column,
// and the Script being built. Private to harness/scripts/amber/.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "harness/scripts/script.h"

namespace parity::harness::script::amber {

struct Token {
  std::string text;
  int line = 0, col = 0;
  int logical = 0;  // line the token belongs to after joining continued lines
  bool valid() const { return line > 0; }
};

// Thrown by Reader::error and caught by parseScript, which turns it into the one-line message.
struct ParseError {
  Location loc;
  std::string message;
};

class Reader {
 protected:
  Reader() = default;
  Reader(const std::string& text, const std::string& name);

  std::string name_;  // the script's path: FILE and VIRTUAL_FILE names are relative to it
  Script script_;

  [[noreturn]] void error(const Token& t, const std::string& msg) { throw ParseError{{t.line, t.col}, msg}; }
  static bool continues(const std::string& l);
  [[noreturn]] void errorAfter(const std::string& msg);
  // Next token, crossing lines; '#' starts a comment to the end of the line.
  Token next();
  // The next token if it is on the line of the last token read; the stream does not advance.
  Token peekSameLine();
  Token nextSameLine(const std::string& what);
  void expectEndOfLine();
  // Skips to the line after the current one.
  void skipLine();
  // Skips lines until one whose only token is END (for blocks we do not execute).
  void skipBlock(const Token& start);
  static bool isNumber(const std::string& s);
  uint32_t uintToken(const Token& t);
  uint32_t uintSameLine(const std::string& what) { return uintToken(nextSameLine(what)); }
  uint32_t dimensionSameLine(const Token& keyword, const std::string& what);
  double numberToken(const Token& t);
  double numberSameLine(const std::string& what) { return numberToken(nextSameLine(what)); }
  Value valueToken(const Token& t);
  void expectWord(const std::string& word);
  void unsupported(const Token& t, const std::string& feature) { script_.unsupported.push_back({feature, {t.line, t.col}}); }
  static void storeValue(std::vector<uint8_t>& bytes, size_t offset, Scalar s, const Value& v);
  static void storeElement(std::vector<uint8_t>& bytes, const Layout& layout, size_t index, size_t field, const Value& v);
  // The lines after the current one up to a line holding only END, verbatim; false without END.
  // `firstLine`: the 1-based line of the first of them.
  bool blockLines(std::string* out, int* firstLine = nullptr);
  static bool onOff(const std::string& s) { return lower(s) == "on" || lower(s) == "true"; }
  Pipeline* pipelineRef(const Token& n);

 private:
  std::vector<std::string> lines_;
  std::vector<int> logical_;
  size_t li_ = 0, ci_ = 0;  // next unread character
  int lastLine_ = 0;        // logical line of the last token read
  int lastPhysical_ = 0;    // physical line of the last token read
};

}  // namespace parity::harness::script::amber
