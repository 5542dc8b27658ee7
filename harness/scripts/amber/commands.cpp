// AmberScript commands: CLEAR*, RUN, RESOLVE and EXPECT.
#include "harness/scripts/amber/statements.h"

#include <cstdlib>
#include <filesystem>
#include <map>

#include "platforms/common/platform.h"

namespace fs = std::filesystem;

namespace parity::harness::script::amber {

void CommandStatements::clear(const Token& t) {
  Command c;
  c.loc = {t.line, t.col};
  Token n = nextSameLine("pipeline name");
  pipelineRef(n);
  c.pipeline = n.text;
  if (t.text == "CLEAR_COLOR") {
    c.kind = Command::Kind::ClearColor;
    for (int i = 0; i < 4; ++i) c.color[i] = numberSameLine("colour component (0-255)");
  } else if (t.text == "CLEAR_DEPTH") {
    c.kind = Command::Kind::ClearDepth;
    c.color[0] = numberSameLine("depth");
  } else if (t.text == "CLEAR_STENCIL") {
    c.kind = Command::Kind::ClearStencil;
    c.color[0] = uintSameLine("stencil value");
  } else {
    c.kind = Command::Kind::Clear;
  }
  expectEndOfLine();
  script_.commands.push_back(c);
}

void CommandStatements::run(const Token& t) {
  Command c;
  c.loc = {t.line, t.col};
  Token n = nextSameLine("pipeline name");
  if (n.text == "TIMED_EXECUTION") n = nextSameLine("pipeline name");  // timing is only logged by Amber
  const Pipeline* p = pipelineRef(n);
  c.pipeline = n.text;
  Token w = nextSameLine("DRAW_RECT, DRAW_GRID, DRAW_ARRAY or workgroup counts");
  if (p->compute) {
    c.kind = Command::Kind::Compute;
    c.groups[0] = uintToken(w);
    c.groups[1] = uintSameLine("workgroup count y");
    c.groups[2] = uintSameLine("workgroup count z");
    expectEndOfLine();
  } else if (w.text == "DRAW_RECT" || w.text == "DRAW_GRID") {
    c.kind = w.text == "DRAW_RECT" ? Command::Kind::DrawRect : Command::Kind::DrawGrid;
    Token o = nextSameLine("POS");
    if (o.text == "ORTHO") {
      unsupported(o, "DRAW_RECT ORTHO");
      o = nextSameLine("POS");
    }
    if (o.text == "PATCH") {
      unsupported(o, "DRAW_RECT PATCH");
      o = nextSameLine("POS");
    }
    if (o.text != "POS") error(o, "expected POS, got '" + o.text + "'");
    c.x = static_cast<float>(numberSameLine("x"));
    c.y = static_cast<float>(numberSameLine("y"));
    expectWord("SIZE");
    c.w = static_cast<float>(numberSameLine("width"));
    c.h = static_cast<float>(numberSameLine("height"));
    if (c.kind == Command::Kind::DrawGrid) {
      expectWord("CELLS");
      c.cellsX = uintSameLine("columns");
      c.cellsY = uintSameLine("rows");
    }
    expectEndOfLine();
  } else if (w.text == "DRAW_ARRAY") {
    c.kind = Command::Kind::DrawArray;
    expectWord("AS");
    c.topology = nextSameLine("topology").text;
    while (true) {
      Token o = peekSameLine();
      if (!o.valid()) break;
      next();
      if (o.text == "INDEXED") c.indexed = true;
      else if (o.text == "START_IDX") c.start = uintSameLine("start index");
      else if (o.text == "COUNT") {
        c.count = uintSameLine("count");
        c.countGiven = true;
      } else if (o.text == "START_INSTANCE" || o.text == "INSTANCE_START") c.instanceStart = uintSameLine("first instance");
      else if (o.text == "INSTANCE_COUNT") c.instanceCount = uintSameLine("instance count");
      else error(o, "unexpected '" + o.text + "' in DRAW_ARRAY");
    }
  } else {
    error(w, "expected DRAW_RECT, DRAW_GRID or DRAW_ARRAY, got '" + w.text + "'");
  }
  script_.commands.push_back(c);
}

// Ours: RESOLVE img [SAMPLES n]: the platform's resolve (or copy) of a LOGICAL image.
void CommandStatements::resolve(const Token& t) {
  Command c;
  c.kind = Command::Kind::Resolve;
  c.loc = {t.line, t.col};
  Token n = nextSameLine("image name");
  const Buffer* b = script_.findBuffer(n.text);
  if (!b) error(n, "unknown image '" + n.text + "'");
  if (b->logical.empty()) error(n, "RESOLVE needs a LOGICAL image, '" + n.text + "' is not one");
  c.buffer = n.text;
  if (peekSameLine().valid()) {
    expectWord("SAMPLES");
    c.resolveSamples = uintSameLine("sample count");
  }
  expectEndOfLine();
  script_.commands.push_back(c);
}

// Ours: EXPECT img MEMORY BYTES [RESOLVED] [PLATFORM p] IDX x y [SIZE w h] EQ bytes...
void CommandStatements::expectMemory(Command& c, const Buffer& b) {
  c.kind = Command::Kind::ExpectMemory;
  if (b.logical.empty()) errorAfter("MEMORY BYTES needs a LOGICAL image, '" + b.name + "' is not one");
  expectWord("BYTES");
  Token w = nextSameLine("IDX");
  if (w.text == "RESOLVED") c.afterResolve = true, w = nextSameLine("IDX");
  if (w.text == "PLATFORM") {
    Token p = nextSameLine("platform name");
    if (!platforms::platformFromName(p.text)) error(p, "unknown platform '" + p.text + "' (reference, dx10, ps3, x360)");
    c.platform = p.text;
    w = nextSameLine("IDX");
  }
  if (w.text != "IDX") error(w, "expected IDX, got '" + w.text + "'");
  c.px = uintSameLine("x");
  c.py = uintSameLine("y");
  Token o = nextSameLine("SIZE or EQ");
  if (o.text == "SIZE") {
    c.pw = uintSameLine("width");
    c.ph = uintSameLine("height");
    o = nextSameLine("EQ");
  }
  if (o.text != "EQ") error(o, "expected EQ, got '" + o.text + "'");
  while (peekSameLine().valid()) {
    Token v = next();
    Value x = valueToken(v);
    if (!x.isInteger || x.i < 0 || x.i > 255) error(v, "expected a byte (0-255 or 0x00-0xFF), got '" + v.text + "'");
    c.values.push_back(x);
  }
  if (c.values.empty()) errorAfter("expected bytes after EQ");
}

// Ours: EXPECT img EQ_IMAGE (FILE path | GOLDEN name) [RMSE t] [MAX t] [FLIP t]
void CommandStatements::expectImage(Command& c) {
  c.kind = Command::Kind::ExpectImage;
  Token k = nextSameLine("FILE or GOLDEN");
  Token f = nextSameLine(k.text == "GOLDEN" ? "golden name" : "file name");
  fs::path dir = fs::path(name_).parent_path();
  if (k.text == "FILE") c.imageFile = (dir / f.text).string();
  else if (k.text == "GOLDEN") c.imageFile = (dir / "golden" / (f.text + ".png")).string();
  else error(k, "expected FILE or GOLDEN, got '" + k.text + "'");
  while (peekSameLine().valid()) {
    Token o = next();
    double v = numberSameLine("tolerance");
    if (o.text == "RMSE") c.imageRmse = v;
    else if (o.text == "MAX") c.imageMax = v;
    else if (o.text == "FLIP") c.imageFlip = v;
    else error(o, "unexpected '" + o.text + "' (RMSE, MAX or FLIP)");
  }
}

std::vector<Tolerance> CommandStatements::tolerances() {
  std::vector<Tolerance> out;
  while (true) {
    Token o = peekSameLine();
    if (!o.valid()) break;
    std::string s = o.text;
    bool percent = !s.empty() && s.back() == '%';
    if (percent) s.pop_back();
    if (!isNumber(s)) break;
    next();
    out.push_back({std::strtod(s.c_str(), nullptr), percent});
  }
  if (out.empty()) errorAfter("expected a tolerance");
  if (out.size() > 4) errorAfter("at most 4 tolerances");
  return out;
}

void CommandStatements::expect(const Token& t) {
  Command c;
  c.loc = {t.line, t.col};
  Token b = nextSameLine("buffer name");
  const Buffer* buf = script_.findBuffer(b.text);
  if (!buf) error(b, "unknown buffer '" + b.text + "'");
  c.buffer = b.text;
  Token w = nextSameLine("IDX, EQ_BUFFER or RMSE_BUFFER");
  if (w.text == "MEMORY" || w.text == "EQ_IMAGE") {
    if (w.text == "MEMORY") expectMemory(c, *buf);
    else expectImage(c);
    script_.commands.push_back(c);
    return;
  }
  if (w.text == "EQ_BUFFER" || w.text == "RMSE_BUFFER" || w.text == "EQ_HISTOGRAM_EMD_BUFFER") {
    c.kind = Command::Kind::ExpectBuffer;
    Token o = nextSameLine("buffer name");
    if (!script_.findBuffer(o.text)) error(o, "unknown buffer '" + o.text + "'");
    c.other = o.text;
    if (w.text != "EQ_BUFFER") {
      c.rmse = true;
      expectWord("TOLERANCE");
      c.rmseTolerance = numberSameLine("tolerance");
      c.emd = w.text == "EQ_HISTOGRAM_EMD_BUFFER";
    }
    expectEndOfLine();
    script_.commands.push_back(c);
    return;
  }
  if (w.text == "RELATIVE") {
    unsupported(w, "EXPECT RELATIVE");
    return skipLine();
  }
  if (w.text != "IDX") error(w, "expected IDX, EQ_BUFFER or RMSE_BUFFER, got '" + w.text + "'");
  Token x = nextSameLine("index");
  c.px = uintToken(x);
  Token o = nextSameLine("comparator");
  bool isProbe = false;
  if (isNumber(o.text)) {  // IDX x y: an image probe
    c.py = uintToken(o);
    isProbe = true;
    o = nextSameLine("SIZE or comparator");
    if (o.text == "SIZE") {
      c.pw = uintSameLine("width");
      c.ph = uintSameLine("height");
      o = nextSameLine("EQ_RGBA or EQ_RGB");
    }
  }
  if (o.text == "EQ_RGBA" || o.text == "EQ_RGB") {
    if (!isProbe) error(o, o.text + " needs IDX x y");
    c.kind = Command::Kind::ExpectProbe;
    c.rgba = o.text == "EQ_RGBA";
    for (int i = 0; i < (c.rgba ? 4 : 3); ++i) c.color[i] = numberSameLine("colour component");
    Token tol = peekSameLine();
    if (tol.valid()) {
      next();
      if (tol.text != "TOLERANCE") error(tol, "unexpected '" + tol.text + "'");
      c.tolerances = tolerances();
    }
    expectEndOfLine();
    script_.commands.push_back(c);
    return;
  }
  if (isProbe) error(o, "expected EQ_RGBA or EQ_RGB, got '" + o.text + "'");
  c.kind = Command::Kind::ExpectValues;
  if (o.text == "TOLERANCE") {
    c.tolerances = tolerances();
    o = nextSameLine("EQ");
    if (o.text != "EQ") error(o, "TOLERANCE needs EQ, got '" + o.text + "'");
    c.comparator = Comparator::FuzzyEq;
  } else {
    static const std::map<std::string, Comparator> kCmp = {{"EQ", Comparator::Eq}, {"NE", Comparator::Ne},
                                                           {"LT", Comparator::Lt}, {"LE", Comparator::Le},
                                                           {"GT", Comparator::Gt}, {"GE", Comparator::Ge}};
    auto it = kCmp.find(o.text);
    if (it == kCmp.end()) error(o, "unknown comparator '" + o.text + "' (EQ NE LT LE GT GE EQ_RGB EQ_RGBA)");
    c.comparator = it->second;
  }
  // Values may continue over following lines until the next command word.
  while (true) {
    Token v = peekSameLine();
    if (!v.valid()) break;
    next();
    c.values.push_back(valueToken(v));
  }
  if (c.values.empty()) errorAfter("expected values after " + o.text);
  script_.commands.push_back(c);
}

}  // namespace parity::harness::script::amber
