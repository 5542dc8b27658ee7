#include "platforms/x360/edram_frame.h"

#include <algorithm>
#include <stdexcept>

namespace parity::platforms::x360 {

void EdramFrame::declare(EdramSurface surface) {
  const bool colour = !surface.isDepth;
  declare(std::move(surface), colour);
}

void EdramFrame::declare(EdramSurface surface, bool resolvedLater) {
  if (lookup(surface.name)) throw std::invalid_argument("EDRAM surface declared twice: " + surface.name);
  State s;
  s.surface = std::move(surface);
  s.resolvedLater = resolvedLater;
  states_.push_back(std::move(s));
}

EdramFrame::State& EdramFrame::find(std::string_view name) {
  for (State& s : states_)
    if (s.surface.name == name) return s;
  throw std::invalid_argument("unknown EDRAM surface: " + std::string(name));
}

const EdramFrame::State* EdramFrame::lookup(std::string_view name) const {
  for (const State& s : states_)
    if (s.surface.name == name) return &s;
  return nullptr;
}

bool EdramFrame::isLive(std::string_view name) const {
  const State* s = lookup(name);
  return s && s->live;
}

const EdramSurface& EdramFrame::surface(std::string_view name) const {
  const State* s = lookup(name);
  if (!s) throw std::invalid_argument("unknown EDRAM surface: " + std::string(name));
  return s->surface;
}

void EdramFrame::clobber(std::string_view pass, const State& writer, const std::vector<std::string>& bound,
                         DiagnosticList& out) {
  const EdramSurface& w = writer.surface;
  for (State& other : states_) {
    if (&other == &writer || !other.live) continue;
    // Surfaces bound together that overlap are checkBoundTargets' finding.
    if (std::find(bound.begin(), bound.end(), other.surface.name) != bound.end()) continue;
    if (!tileRangesIntersect(tileRange(w), tileRange(other.surface))) continue;
    const EdramSurface& t = other.surface;
    std::string_view code = "E_EDRAM_OVERLAP";
    std::string why = "its contents are still live (X1)";
    if (w.role == SurfaceRole::GBuffer && t.role == SurfaceRole::GBuffer) {
      code = "E_GBUF_OVERLAP";
      why = "none of the G-buffers can overlap (X4)";
    } else if ((w.role == SurfaceRole::LBuffer && t.isDepth) || (t.role == SurfaceRole::LBuffer && w.isDepth)) {
      code = "E_LBUF_DEPTH_ALIAS";
      why = "the light pass still tests against the depth tiles (X4)";
    } else if (t.role == SurfaceRole::GBuffer && !t.isDepth && other.resolvedLater) {
      code = "E_USE_BEFORE_RESOLVE";
      why = t.name + " has not been resolved yet (X4)";
    }
    const std::string message = std::string(pass) + " writes " + w.name + " " + formatTileRange(tileRange(w)) +
                                " over " + t.name + " " + formatTileRange(tileRange(t)) + ": " + why;
    other.live = false;
    if (other.resolvedLater) {  // its resolve is still to come: lost now
      out.report(code, {w.name, t.name}, message);
    } else {  // lost if anything uses them later
      other.clobberCode = std::string(code);
      other.clobberMessage = message;
      other.clobberTargets = {w.name, t.name};
    }
  }
}

void EdramFrame::use(std::string_view how, State& s, DiagnosticList& out) {
  if (s.clobberCode.empty()) return;
  out.report(s.clobberCode, s.clobberTargets,
             std::string(how) + " uses the contents of " + s.surface.name + ", which were clobbered: " + s.clobberMessage);
  s.clobberCode.clear();
}

void EdramFrame::pass(std::string_view pass, const std::vector<Binding>& bound, DiagnosticList& out) {
  std::vector<EdramSurface> targets;
  for (const Binding& b : bound) targets.push_back(find(b.surface).surface);
  checkBoundTargets(pass, targets, out);
  for (const Binding& b : bound)
    if (b.loads) use(pass, find(b.surface), out);
  std::vector<std::string> names;
  for (const Binding& b : bound) names.push_back(b.surface);
  for (const Binding& b : bound) {
    if (!b.writes) continue;
    State& s = find(b.surface);
    clobber(pass, s, names, out);
    s.live = true;
    s.clobberCode.clear();  // what it holds now is this pass's
  }
  bound_ = std::move(names);
}

void EdramFrame::draw(std::string_view pass, const std::vector<std::string>& bound, DiagnosticList& out) {
  std::vector<Binding> b;
  for (const std::string& name : bound) b.push_back({name, false, true});
  this->pass(pass, b, out);
}

void EdramFrame::write(std::string_view pass, std::string_view surface, DiagnosticList& out) {
  State& s = find(surface);
  clobber(pass, s, bound_, out);
  s.live = true;
  s.clobberCode.clear();  // what it holds now is this pass's
}

void EdramFrame::resolve(std::string_view name, const ResolveRequest& request, std::string texture,
                         DiagnosticList& out) {
  State& s = find(name);
  checkResolveRequest(s.surface, request, out);
  use("the resolve of " + s.surface.name, s, out);
  // Colour contents are dead once resolved; depth stays live for later depth/stencil tests.
  if (!s.surface.isDepth) s.live = false;
  textures_.insert(std::move(texture));
}

void EdramFrame::sample(std::string_view pass, std::string_view name, DiagnosticList& out) {
  if (textures_.count(name)) return;
  if (const State* s = lookup(name)) {
    out.report("E_EDRAM_NOT_READABLE", {s->surface.name},
               std::string(pass) + " samples render target " + s->surface.name +
                   " directly; EDRAM is only reachable by the RB stage and resolves, resolve it to a texture (X1)");
  }
}

void EdramFrame::discard(std::string_view name) { find(name).live = false; }

}  // namespace parity::platforms::x360
