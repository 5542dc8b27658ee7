#include "harness/scripts/amber/reader.h"

#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <sstream>

namespace parity::harness::script::amber {

Reader::Reader(const std::string& text, const std::string& name) : name_(name) {
  std::string line;
  std::istringstream in(text);
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    lines_.push_back(line);
  }
  // Amber's line continuation: a '\\' ending a line joins the next line to it. logical_[i] is
  // the 1-based line a physical line belongs to.
  logical_.resize(lines_.size());
  for (size_t i = 0; i < lines_.size(); ++i)
    logical_[i] = i > 0 && continues(lines_[i - 1]) ? logical_[i - 1] : static_cast<int>(i + 1);
  script_.file = name;
}

bool Reader::continues(const std::string& l) {
  size_t hash = l.find('#');
  std::string code = l.substr(0, hash);
  size_t e = code.find_last_not_of(" \t");
  return e != std::string::npos && code[e] == '\\' && (e == 0 || std::isspace(static_cast<unsigned char>(code[e - 1])));
}

void Reader::errorAfter(const std::string& msg) {
  // Column just past the last token of the current line.
  int line = lastPhysical_ ? lastPhysical_ : 1;
  int col = static_cast<int>(lines_.empty() ? 1 : lines_[line - 1].size() + 1);
  throw ParseError{{line, col}, msg};
}

// Next token, crossing lines; '#' starts a comment to the end of the line.
Token Reader::next() {
  while (li_ < lines_.size()) {
    const std::string& l = lines_[li_];
    while (ci_ < l.size() && std::isspace(static_cast<unsigned char>(l[ci_]))) ++ci_;
    if (ci_ >= l.size() || l[ci_] == '#') {
      ++li_;
      ci_ = 0;
      continue;
    }
    size_t b = ci_;
    while (ci_ < l.size() && !std::isspace(static_cast<unsigned char>(l[ci_]))) ++ci_;
    if (l.compare(b, ci_ - b, "\\") == 0 && continues(l)) continue;  // line continuation
    Token t{l.substr(b, ci_ - b), static_cast<int>(li_ + 1), static_cast<int>(b + 1)};
    t.logical = logical_[li_];
    lastLine_ = t.logical;
    lastPhysical_ = t.line;
    return t;
  }
  return {};
}

// The next token if it is on the line of the last token read; the stream does not advance.
Token Reader::peekSameLine() {
  size_t li = li_, ci = ci_;
  int last = lastLine_, lastP = lastPhysical_;
  Token t = next();
  li_ = li, ci_ = ci, lastLine_ = last, lastPhysical_ = lastP;
  if (t.valid() && t.logical == last) return t;
  return {};
}

Token Reader::nextSameLine(const std::string& what) {
  int last = lastLine_, lastP = lastPhysical_;
  size_t li = li_, ci = ci_;
  Token t = next();
  if (!t.valid() || t.logical != last) {
    li_ = li, ci_ = ci, lastLine_ = last, lastPhysical_ = lastP;
    errorAfter("expected " + what);
  }
  return t;
}

void Reader::expectEndOfLine() {
  Token t = peekSameLine();
  if (t.valid()) error(t, "unexpected '" + t.text + "'");
}

// Skips to the line after the current one.
void Reader::skipLine() {
  if (li_ < lines_.size() && logical_[li_] == lastLine_) {
    ++li_;
    ci_ = 0;
    while (li_ < lines_.size() && logical_[li_] == lastLine_) ++li_;
  }
}

// Skips lines until one whose only token is END (for blocks we do not execute).
void Reader::skipBlock(const Token& start) {
  skipLine();
  while (li_ < lines_.size()) {
    std::string l = lines_[li_];
    size_t b = l.find_first_not_of(" \t");
    ++li_;
    ci_ = 0;
    if (b != std::string::npos && l.compare(b, 3, "END") == 0 && l.find_first_not_of(" \t", b + 3) == std::string::npos) {
      lastLine_ = logical_[li_ - 1];
      lastPhysical_ = static_cast<int>(li_);
      return;
    }
  }
  error(start, "missing END for '" + start.text + "'");
}

bool Reader::isNumber(const std::string& s) {
  if (s.empty()) return false;
  char* end = nullptr;
  std::strtod(s.c_str(), &end);
  return end && *end == 0;
}

uint32_t Reader::uintToken(const Token& t) {
  char* end = nullptr;
  errno = 0;
  unsigned long long v = std::strtoull(t.text.c_str(), &end, 0);
  if (t.text.empty() || *end || t.text[0] == '-' || errno || v > 0xFFFFFFFFull)
    error(t, "expected a non-negative integer, got '" + t.text + "'");
  return static_cast<uint32_t>(v);
}

uint32_t Reader::dimensionSameLine(const Token& keyword, const std::string& what) {
  Token t = nextSameLine(what);
  uint32_t v = uintToken(t);
  if (v > kMaxImageDimension)
    error(t, keyword.text + " " + t.text + " is larger than the " + std::to_string(kMaxImageDimension) +
                 " a script may use");
  return v;
}

double Reader::numberToken(const Token& t) {
  if (!isNumber(t.text)) error(t, "expected a number, got '" + t.text + "'");
  return std::strtod(t.text.c_str(), nullptr);
}

Value Reader::valueToken(const Token& t) {
  Value v;
  const std::string& s = t.text;
  bool looksInt = !s.empty() && s.find_first_of(".eE") == std::string::npos;
  if (s.size() > 2 && (s[0] == '0' && (s[1] == 'x' || s[1] == 'X'))) looksInt = true;
  if (looksInt) {
    char* end = nullptr;
    errno = 0;
    long long x = s[0] == '-' ? std::strtoll(s.c_str(), &end, 0) : static_cast<long long>(std::strtoull(s.c_str(), &end, 0));
    if (*end == 0 && errno == 0) {
      v.isInteger = true;
      v.i = x;
      v.d = s[0] == '-' ? static_cast<double>(x) : static_cast<double>(static_cast<unsigned long long>(x));
      return v;
    }
  }
  v.d = numberToken(t);
  v.i = saturatingInt64(v.d);
  return v;
}

void Reader::expectWord(const std::string& word) {
  Token t = nextSameLine(word);
  if (t.text != word) error(t, "expected " + word + ", got '" + t.text + "'");
}

void Reader::storeValue(std::vector<uint8_t>& bytes, size_t offset, Scalar s, const Value& v) {
  script::storeValue(bytes, offset, s, v);
}

void Reader::storeElement(std::vector<uint8_t>& bytes, const Layout& layout, size_t index, size_t field, const Value& v) {
  const Field& f = layout.fields[field];
  storeValue(bytes, index * layout.stride + f.offset, f.scalar, v);
}

// The lines after the current one up to a line holding only END, verbatim; false without END.
bool Reader::blockLines(std::string* out, int* firstLine) {
  skipLine();
  if (firstLine) *firstLine = static_cast<int>(li_ + 1);
  bool found = false;
  while (li_ < lines_.size()) {
    const std::string& l = lines_[li_++];
    size_t b = l.find_first_not_of(" \t");
    if (b != std::string::npos && l.compare(b, 3, "END") == 0 && l.find_first_not_of(" \t", b + 3) == std::string::npos) {
      found = true;
      break;
    }
    *out += l + "\n";
  }
  ci_ = 0;
  if (li_ > 0) lastLine_ = logical_[li_ - 1], lastPhysical_ = static_cast<int>(li_);
  return found;
}

Pipeline* Reader::pipelineRef(const Token& n) {
  for (auto& p : script_.pipelines)
    if (p.name == n.text) return &p;
  error(n, "unknown pipeline '" + n.text + "'");
}

}  // namespace parity::harness::script::amber
