// shader_test probes: probe rgba/rgb/all, relative probes, probe warn, probe ssbo, probe atomic counter.
#include "harness/scripts/shader_test/steps.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <sstream>

namespace parity::harness::script::shader_test {

std::vector<Tolerance> ProbeCommands::tolerances() const {
  if (!tolerances_.empty()) return tolerances_;
  return {{tolerance_ * 255.0, false}};  // in the 0..255 units of Command::color
}

void ProbeCommands::probe(int line, const std::vector<std::string>& w, size_t at, bool relative) {
  // probe [warn] [rect] rgb|rgba ... / probe [warn] all rgb|rgba ...
  Command c;
  c.kind = Command::Kind::ExpectProbe;
  c.loc = {line, 1};
  c.buffer = framebuffer_;
  c.warnOnly = at < w.size() && w[at] == "warn";
  if (c.warnOnly) ++at;
  bool all = at < w.size() && w[at] == "all";
  bool rect = at < w.size() && w[at] == "rect";
  if (all || rect) ++at;
  if (at >= w.size() || (w[at] != "rgb" && w[at] != "rgba")) {
    unsupported(line, "probe " + std::string(relative ? "(relative) " : "") + (at < w.size() ? w[at] : ""));
    return;
  }
  c.rgba = w[at++] == "rgba";
  std::vector<Value> v = numbers(line, w, at);
  size_t position = all ? 0 : rect ? 4 : 2, channels = c.rgba ? 4 : 3;
  // piglit reads the numbers it needs and ignores the rest ("probe rgb x y r g b a" occurs).
  if (v.size() < position + channels) error(line, "probe needs " + std::to_string(position + channels) + " numbers");
  auto coordinate = [&](size_t i, uint32_t size) {
    if (!relative) return static_cast<uint32_t>(std::max<int64_t>(0, v[i].i));
    return static_cast<uint32_t>(std::clamp(v[i].d * size, 0.0, double(size)));
  };
  if (all) {
    c.px = 0, c.py = 0, c.pw = width_, c.ph = height_;
  } else {
    c.px = coordinate(0, width_), c.py = coordinate(1, height_);
    if (rect) c.pw = coordinate(2, width_), c.ph = coordinate(3, height_);
    if (relative) c.px = std::min(c.px, width_ - 1), c.py = std::min(c.py, height_ - 1);
  }
  for (size_t i = 0; i < channels; ++i) c.color[i] = v[position + i].d * 255.0;
  c.tolerances = tolerances();
  script_.commands.push_back(c);
}

// active uniform NAME PNAME VALUE, for the layout properties (GL_UNIFORM_OFFSET, _ARRAY_STRIDE,
// _MATRIX_STRIDE, _IS_ROW_MAJOR), the element count (GL_UNIFORM_SIZE) and the type
// (GL_UNIFORM_TYPE, whose VALUE is a GL enum name: GL_FLOAT_VEC4). The others
// (GL_UNIFORM_NAME_LENGTH, _BLOCK_INDEX, _ATOMIC_COUNTER_BUFFER_INDEX) are a SKIP.
void ProbeCommands::activeUniform(int line, const std::vector<std::string>& w) {
  static const std::set<std::string> kIntegers = {"GL_UNIFORM_OFFSET", "GL_UNIFORM_ARRAY_STRIDE", "GL_UNIFORM_MATRIX_STRIDE",
                                                  "GL_UNIFORM_IS_ROW_MAJOR", "GL_UNIFORM_SIZE"};
  if (!kIntegers.count(w[3]) && w[3] != "GL_UNIFORM_TYPE") return unsupported(line, "active uniform " + w[3]);
  Command c;
  c.kind = Command::Kind::ExpectUniform;
  c.loc = {line, 1};
  c.uniform = w[2];
  c.other = w[3];
  if (w[3] == "GL_UNIFORM_TYPE") {
    if (w[4].rfind("GL_", 0) != 0) error(line, "active uniform GL_UNIFORM_TYPE needs a GL type name (GL_FLOAT_VEC4), got '" + w[4] + "'");
    c.typeName = w[4];
  } else {
    c.values = numbers(line, w, 4);
    if (!c.values[0].isInteger) error(line, "active uniform " + w[3] + " needs an integer, got '" + w[4] + "'");
  }
  script_.commands.push_back(c);
}

// probe ssbo TYPE BINDING OFFSET OP values
void ProbeCommands::probeBuffer(int line, const std::vector<std::string>& w) {
  if (w.size() < 7) error(line, "expected probe ssbo TYPE BINDING OFFSET OP values");
  Command c;
  c.kind = Command::Kind::ExpectValues;
  c.loc = {line, 1};
  c.valueType = valueTypeIn(line, w[2], "ssbo");
  c.valueTypeGiven = true;
  Value offset;
  if (!parseNumber(w[4], &offset) || !offset.isInteger || offset.i < 0) error(line, "expected a byte offset, got '" + w[4] + "'");
  c.px = static_cast<uint32_t>(offset.i);
  static const std::map<std::string, Comparator> kOps = {{"==", Comparator::Eq}, {"!=", Comparator::Ne}, {"<", Comparator::Lt},
                                                        {"<=", Comparator::Le}, {">", Comparator::Gt}, {">=", Comparator::Ge},
                                                        {"~=", Comparator::FuzzyEq}};
  auto op = kOps.find(w[5]);
  if (op == kOps.end()) error(line, "unknown comparison '" + w[5] + "' (== != < <= > >= ~=)");
  c.comparator = op->second;
  c.values = typedNumbers(line, w, 6, c.valueType);
  if (c.comparator == Comparator::FuzzyEq) c.tolerances = {{tolerances_.empty() ? tolerance_ : tolerances_[0].value / 255.0, false}};
  c.buffer = bufferFor(line, "ssbo", w[3], 0);
  if (!c.buffer.empty()) script_.commands.push_back(c);
}

// shader_runner.c: `atomic counters N` makes binding 0's buffer of N zeroed counters,
// `atomic counter buffer B N` binding B's, and `atomic counter B I V` sets counter I of B to V.
void ProbeCommands::atomicCounters(int line, const std::vector<std::string>& w) {
  std::vector<Value> v = numbers(line, w, w[1] == "counters" ? 2 : w.size() > 2 && w[2] == "buffer" ? 3 : 2);
  for (const Value& x : v)
    if (!x.isInteger || x.i < 0) error(line, "expected unsigned integers in '" + w[0] + " " + w[1] + " ...'");
  const bool create = w[1] == "counters" || (w.size() > 2 && w[2] == "buffer");
  if ((w[1] == "counters" && v.size() != 1) || (create && w[1] == "counter" && v.size() != 2) || (!create && v.size() != 3))
    error(line, "expected atomic counters N, atomic counter buffer BINDING N or atomic counter BINDING INDEX VALUE");
  const uint32_t binding = w[1] == "counters" ? 0 : static_cast<uint32_t>(v[0].i);
  Command c;
  c.kind = Command::Kind::WriteBuffer;
  c.loc = {line, 1};
  c.buffer = atomicCounterBuffer(line, binding);
  Buffer* buffer = nullptr;
  for (Buffer& b : script_.buffers)
    if (b.name == c.buffer) buffer = &b;
  if (create) {
    // A new buffer of zeros each time, as glBufferData makes one.
    const uint64_t bytes = uint64_t(v.back().i) * 4;
    if (bytes > kMaxBufferBytes) error(line, "too many atomic counters");
    if (buffer->bytes.size() < bytes) buffer->bytes.resize(bytes, 0);
    c.bytes.assign(bytes, 0);
  } else {
    c.px = static_cast<uint32_t>(v[1].i) * 4;
    storeValue(c.bytes, 0, Scalar::Uint32, v[2]);
    if (buffer->bytes.size() < c.px + 4u) buffer->bytes.resize(c.px + 4u, 0);
  }
  if (buffer->bytes.empty()) buffer->bytes.assign(4, 0);
  if (!c.bytes.empty()) script_.commands.push_back(c);
}

// probe atomic counter INDEX OP VALUE (binding 0's counter INDEX) or
// probe atomic counter buffer BINDING BYTE_OFFSET OP VALUE.
void ProbeCommands::probeAtomicCounter(int line, const std::vector<std::string>& w) {
  const bool buffer = w.size() > 3 && w[3] == "buffer";
  const size_t op = buffer ? 6 : 4;
  if (w.size() != op + 2) error(line, buffer ? "expected probe atomic counter buffer BINDING OFFSET OP VALUE" : "expected probe atomic counter INDEX OP VALUE");
  std::vector<std::string> numeric(w.begin() + (buffer ? 4 : 3), w.begin() + long(op));
  numeric.push_back(w[op + 1]);
  std::vector<Value> v = numbers(line, numeric, 0);
  for (const Value& x : v)
    if (!x.isInteger || x.i < 0) error(line, "expected unsigned integers in '" + trim(uncommented(lines_[size_t(line - 1)])) + "'");
  static const std::map<std::string, Comparator> kOps = {{"==", Comparator::Eq}, {"!=", Comparator::Ne}, {"<", Comparator::Lt},
                                                        {"<=", Comparator::Le}, {">", Comparator::Gt}, {">=", Comparator::Ge}};
  auto comparator = kOps.find(w[op]);
  if (comparator == kOps.end()) error(line, "unknown comparison '" + w[op] + "' (== != < <= > >=)");
  Command c;
  c.kind = Command::Kind::ExpectValues;
  c.loc = {line, 1};
  c.comparator = comparator->second;
  c.valueType = valueType(line, "uint", false);
  c.valueTypeGiven = true;
  c.buffer = atomicCounterBuffer(line, buffer ? static_cast<uint32_t>(v[0].i) : 0);
  c.px = static_cast<uint32_t>(buffer ? v[1].i : v[0].i * 4);
  c.values = {v.back()};
  script_.commands.push_back(c);
}

}  // namespace parity::harness::script::shader_test
