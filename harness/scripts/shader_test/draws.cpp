// shader_test draws and pipeline state.
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

void DrawCommands::draw(int line, const std::vector<std::string>& w) {
  drawn_ = true;
  Command c;
  c.loc = {line, 1};
  c.patchControlPoints = patchVertices_;
  // Texture parameters are state of the draws after them, as in OpenGL.
  if (piglit_) c.samplerStates = script_.samplers;
  // draw [instanced] rect [ortho] [patch] [tex] [INSTANCES] X Y WIDTH HEIGHT [TX TY TWIDTH THEIGHT]
  const bool instancedRect = w[1] == "instanced";
  if (w[1] == "rect" || instancedRect) {
    size_t at = instancedRect ? 3 : 2;
    bool ortho = false, tex = false;
    while (at < w.size() && (w[at] == "ortho" || w[at] == "patch" || (w[at] == "tex" && !instancedRect))) {
      (w[at] == "patch" ? c.patch : w[at] == "tex" ? tex : ortho) = true;
      ++at;
    }
    std::vector<Value> v = numbers(line, w, at);
    if (instancedRect) {
      if (v.empty() || !v[0].isInteger || v[0].i < 1) error(line, "draw instanced rect needs an instance count first");
      c.instanceCount = static_cast<uint32_t>(v[0].i);
      v.erase(v.begin());
    }
    if (v.size() != (tex ? 8u : 4u)) error(line, tex ? "draw rect tex needs x y width height and tx ty twidth theight" : "draw rect needs x y width height");
    if (tex && script_.hasArbPrograms())
      return unsupported(line, "draw rect tex with ARB assembly programs (texture coordinates of OpenGL's fixed-function vertex arrays)");
    if (tex)
      for (size_t i = 0; i < 4; ++i) c.texcoords[i] = static_cast<float>(v[4 + i].d);
    c.kind = Command::Kind::DrawRect;
    c.pipeline = framebufferPipeline(propertiesPipeline(line, "rect", c.patch ? "PATCH_LIST" : "TRIANGLE_STRIP", false));
    c.x = static_cast<float>(v[0].d), c.y = static_cast<float>(v[1].d), c.w = static_cast<float>(v[2].d), c.h = static_cast<float>(v[3].d);
    c.ndc = !ortho;
    c.piglitCorners = true;
    script_.commands.push_back(c);
    return;
  }
  // draw arrays [instanced] [indexed] MODE FIRST COUNT [INSTANCES]
  size_t at = 2;
  bool instanced = false;
  while (at < w.size() && (w[at] == "instanced" || w[at] == "indexed")) {
    if (w[at] == "instanced") instanced = true;
    else c.indexed = true;
    ++at;
  }
  if (at >= w.size()) error(line, "draw arrays needs a primitive mode");
  std::string mode = w[at++];
  if (mode.rfind("GL_", 0) == 0) mode = mode.substr(3);
  static const std::map<std::string, std::string> kModes = {
      {"TRIANGLES", "TRIANGLE_LIST"}, {"TRIANGLE_LIST", "TRIANGLE_LIST"}, {"TRIANGLE_STRIP", "TRIANGLE_STRIP"},
      {"TRIANGLE_FAN", "TRIANGLE_FAN"}, {"POINTS", "POINT_LIST"}, {"POINT_LIST", "POINT_LIST"},
      {"LINES", "LINE_LIST"}, {"LINE_LIST", "LINE_LIST"}, {"LINE_STRIP", "LINE_STRIP"}, {"LINE_LOOP", "LINE_LOOP"},
      {"PATCHES", "PATCH_LIST"}, {"PATCH_LIST", "PATCH_LIST"},
      {"LINES_ADJACENCY", "LINE_LIST_WITH_ADJACENCY"}, {"LINE_LIST_WITH_ADJACENCY", "LINE_LIST_WITH_ADJACENCY"},
      {"LINE_STRIP_ADJACENCY", "LINE_STRIP_WITH_ADJACENCY"}, {"LINE_STRIP_WITH_ADJACENCY", "LINE_STRIP_WITH_ADJACENCY"},
      {"TRIANGLES_ADJACENCY", "TRIANGLE_LIST_WITH_ADJACENCY"}, {"TRIANGLE_LIST_WITH_ADJACENCY", "TRIANGLE_LIST_WITH_ADJACENCY"},
      {"TRIANGLE_STRIP_ADJACENCY", "TRIANGLE_STRIP_WITH_ADJACENCY"},
      {"TRIANGLE_STRIP_WITH_ADJACENCY", "TRIANGLE_STRIP_WITH_ADJACENCY"}};
  auto m = kModes.find(mode);
  // The compatibility profile's quads and polygons: one primitive each (gl_PrimitiveID, flat
  // shading's provoking vertex), which no split into triangles keeps.
  if (m == kModes.end() && (mode == "QUADS" || mode == "QUAD_STRIP" || mode == "POLYGON"))
    return unsupported(line, "draw arrays " + w[at - 1] + " (a compatibility-profile primitive)");
  if (m == kModes.end()) error(line, "unknown primitive mode '" + w[at - 1] + "'");
  c.topology = m->second;
  std::vector<Value> v = numbers(line, w, at);
  if (v.size() < 2 || v.size() > 3) error(line, "draw arrays needs FIRST COUNT [INSTANCES]");
  c.kind = Command::Kind::DrawArray;
  c.pipeline = framebufferPipeline(propertiesPipeline(line, pipeline("arrays") ? "arrays" : "rect", c.topology, c.indexed));
  // Indexed draws (VkRunner) read the indices from the first and add FIRST to each one.
  if (c.indexed) c.baseVertex = static_cast<int32_t>(v[0].i);
  else c.start = static_cast<uint32_t>(v[0].i);
  c.count = static_cast<uint32_t>(v[1].i);
  c.countGiven = true;
  if (v.size() == 3) c.instanceCount = static_cast<uint32_t>(v[2].i);
  else if (instanced) error(line, "draw arrays instanced needs an instance count");
  if (c.indexed && indices_.empty()) error(line, "draw arrays indexed without an [indices] section");
  script_.commands.push_back(c);
}

Command DrawCommands::clearCommand(int line, Command::Kind kind) {
  Command c;
  c.kind = kind;
  c.loc = {line, 1};
  c.pipeline = framebufferPipeline("rect");
  return c;
}

void DrawCommands::clearValue(int line, Command::Kind kind, const std::vector<Value>& v) {
  Command c = clearCommand(line, kind);
  for (size_t i = 0; i < v.size() && i < 4; ++i) c.color[i] = kind == Command::Kind::ClearColor ? v[i].d * 255.0 : v[i].d;
  clearState_.erase(std::remove_if(clearState_.begin(), clearState_.end(), [&](const Command& x) { return x.kind == kind; }),
                    clearState_.end());
  clearState_.push_back(c);
  // The runner keeps clear values per pipeline: every framebuffer's "rect" pipeline gets them.
  for (const Pipeline& p : script_.pipelines)
    if (p.name == "rect" || p.name.rfind("rect into ", 0) == 0) {
      c.pipeline = p.name;
      script_.commands.push_back(c);
    }
}

void DrawCommands::framebufferTexture(int line, const std::vector<std::string>& w) {
  if (w.size() != 4 || w[2] != "2d") return unsupported(line, "fb " + (w.size() > 2 ? w[1] + " " + w[2] : w[1]));
  Value unit;
  if (!parseNumber(w[3], &unit) || !unit.isInteger || unit.i < 0) error(line, "expected a texture unit, got '" + w[3] + "'");
  const Buffer* texture = nullptr;
  for (const Buffer& b : script_.buffers)
    if (b.textureUnit == unit.i) texture = &b;
  if (!texture) error(line, "fb tex 2d " + w[3] + ": no texture command filled unit " + w[3]);
  if (texture->layers > 1 || texture->mipLevels > 1 || texture->type.name[0] == 'D')
    return unsupported(line, "fb tex 2d of an array, mipmapped or depth texture");
  framebuffer_ = texture->name;
  width_ = texture->width, height_ = texture->height;
}

// A copy of `base` whose colour attachment is the current framebuffer texture, with no depth:
// piglit's framebuffer object has the colour attachment only.
std::string DrawCommands::framebufferPipeline(const std::string& base) {
  if (framebuffer_ == "framebuffer") return base;
  const std::string name = base + " into " + framebuffer_;
  if (pipeline(name)) return name;
  Pipeline copy = *pipeline(base);
  copy.name = name;
  copy.fbWidth = width_, copy.fbHeight = height_;
  copy.binds.erase(std::remove_if(copy.binds.begin(), copy.binds.end(), [](const Bind& b) { return b.kind == BindKind::DepthStencil; }),
                   copy.binds.end());
  for (Bind& b : copy.binds)
    if (b.kind == BindKind::Color) b.buffer = framebuffer_;
  script_.pipelines.push_back(copy);
  if (base == "rect")
    for (Command c : clearState_) {
      c.pipeline = name;
      script_.commands.push_back(c);
    }
  return name;
}

}  // namespace parity::harness::script::shader_test
